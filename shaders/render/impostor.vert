#version 460
#extension GL_GOOGLE_include_directive : require
// Vertices of every draw of the impostor preview, generated from gl_VertexIndex (no vertex
// buffers); IMPOSTOR_MODE selects the draw (see shared/render/impostor_layout.h).
#include "shared/render/impostor_layout.h"

layout(constant_id = 0) const uint IMPOSTOR_MODE = IMPOSTOR_MODE_PARTICLES;

layout(push_constant) uniform Push { ImpostorPush pc; };
layout(std430, set = 0, binding = 0) readonly buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = 1) readonly buffer Velocities { vec4 velocities[]; };

layout(location = 0) out vec3 v_world;             // world position (SKY: x = 0..1 top to bottom)
layout(location = 1) flat out vec4 v_sphere;       // PARTICLES: centre, radius
layout(location = 2) flat out vec3 v_attr;         // PARTICLES: base colour; SOLID: face normal

// Two triangles of a unit quad, in 0..1.
const vec2 kQuad[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
// Box edges as pairs of corners; corner bit 0 = x, bit 1 = y, bit 2 = z.
const uint kEdges[24] = uint[](0, 1, 2, 3, 4, 5, 6, 7,   // along x
                               0, 2, 1, 3, 4, 6, 5, 7,   // along y
                               0, 4, 1, 5, 2, 6, 3, 7);  // along z

// A position outside the clip volume: all six vertices of a skipped quad land here, so the
// triangles have no area and nothing is drawn.
const vec4 kCulled = vec4(0.0, 0.0, -2.0, 1.0);

vec3 ramp(float t) {
    // deep blue (slow) -> cyan -> near white (fast)
    const vec3 slow = vec3(0.03, 0.16, 0.50);
    const vec3 mid = vec3(0.15, 0.62, 0.90);
    const vec3 fast = vec3(0.86, 0.97, 1.00);
    return t < 0.5 ? mix(slow, mid, t * 2.0) : mix(mid, fast, t * 2.0 - 1.0);
}

void particle() {
    uint p = uint(gl_VertexIndex) / 6u;
    vec2 q = kQuad[uint(gl_VertexIndex) % 6u] * 2.0 - 1.0;
    vec3 c = positions[p].xyz;
    float r = pc.eye.w;
    vec3 to_c = c - pc.eye.xyz;
    float d2 = dot(to_c, to_c);
    // Skips NaN/infinite positions (a diverged solver) and spheres around the eye.
    if (any(isnan(c)) || any(isinf(c)) || !(d2 > r * r * 1.0001) || isinf(d2)) {
        gl_Position = kCulled;
        return;
    }
    float d = sqrt(d2);
    vec3 dir = to_c / d;
    vec3 right = cross(dir, pc.up.xyz);
    if (dot(right, right) < 1e-8) right = cross(dir, vec3(1.0, 0.0, 0.0));
    right = normalize(right);
    vec3 up = cross(right, dir);
    // The silhouette cone (sin a = r / d) cuts the plane through the centre in a circle of
    // radius d tan a, a little more than r: the quad must cover that, not just r.
    float half_size = r * d / sqrt(d2 - r * r);
    v_world = c + (q.x * right + q.y * up) * half_size;
    v_sphere = vec4(c, r);
    float speed = length(velocities[p].xyz);
    v_attr = ramp(clamp(speed * pc.up.w, 0.0, 1.0));
    gl_Position = pc.view_proj * vec4(v_world, 1.0);
}

void solid() {
    uint face = uint(gl_VertexIndex) / 6u;  // axis = face / 2, side = face % 2
    uint axis = face / 2u;
    vec2 q = kQuad[uint(gl_VertexIndex) % 6u];
    vec3 t = vec3(0.0);
    t[axis] = float(face % 2u);
    t[(axis + 1u) % 3u] = q.x;
    t[(axis + 2u) % 3u] = q.y;
    v_world = mix(pc.box_min.xyz, pc.box_max.xyz, t);
    vec3 n = vec3(0.0);
    n[axis] = face % 2u == 0u ? -1.0 : 1.0;
    v_attr = n;
    gl_Position = pc.view_proj * vec4(v_world, 1.0);
}

void lines() {
    uint corner = kEdges[gl_VertexIndex];
    vec3 t = vec3(corner & 1u, (corner >> 1u) & 1u, (corner >> 2u) & 1u);
    v_world = mix(pc.box_min.xyz, pc.box_max.xyz, t);
    gl_Position = pc.view_proj * vec4(v_world, 1.0);
    // Pulled slightly towards the eye so the floor's own edges do not hide the bottom lines.
    gl_Position.z -= 2e-5 * gl_Position.w;
}

void sky() {
    vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);  // (0,0) (2,0) (0,2)
    gl_Position = vec4(p * 2.0 - 1.0, 1.0, 1.0);
    v_world = vec3(p.y, 0.0, 0.0);  // 0 at the top row, 1 at the bottom (Vulkan y is down)
}

void main() {
    v_sphere = vec4(0.0);
    v_attr = vec3(0.0);
    v_world = vec3(0.0);
    if (IMPOSTOR_MODE == IMPOSTOR_MODE_PARTICLES) particle();
    else if (IMPOSTOR_MODE == IMPOSTOR_MODE_SOLID) solid();
    else if (IMPOSTOR_MODE == IMPOSTOR_MODE_LINES) lines();
    else sky();
}
