#version 460
#extension GL_GOOGLE_include_directive : require
// Shading of every draw of the impostor preview; IMPOSTOR_MODE selects the draw (see
// shared/render/impostor_layout.h). Particles are ray-cast against their true sphere, so silhouette,
// normal and depth are exact under perspective (and spheres intersect correctly).
#include "shared/render/impostor_layout.h"

layout(constant_id = 0) const uint IMPOSTOR_MODE = IMPOSTOR_MODE_PARTICLES;

layout(push_constant) uniform Push { ImpostorPush pc; };

layout(location = 0) in vec3 v_world;
layout(location = 1) flat in vec4 v_sphere;
layout(location = 2) flat in vec3 v_attr;

layout(location = 0) out vec4 out_color;

const vec3 kLight = normalize(vec3(-0.45, 0.80, 0.40));  // key light: up, left, towards the viewer
const float kAmbient = 0.28;

void particle() {
    vec3 c = v_sphere.xyz;
    float r = v_sphere.w;
    vec3 rd = normalize(v_world - pc.eye.xyz);
    vec3 oc = pc.eye.xyz - c;
    float b = dot(oc, rd);
    // r^2 - (distance of the ray from the centre)^2, without the cancellation of |oc|^2 - r^2
    vec3 perp = oc - b * rd;
    float disc = r * r - dot(perp, perp);
    if (disc < 0.0) discard;
    float t = -b - sqrt(disc);
    if (t <= 0.0) discard;
    vec3 hit = pc.eye.xyz + t * rd;
    vec4 clip = pc.view_proj * vec4(hit, 1.0);
    float depth = clip.z / clip.w;
    if (clip.w <= 0.0 || depth < 0.0 || depth > 1.0) discard;  // front cut by the near/far plane
    gl_FragDepth = depth;

    vec3 n = (hit - c) / r;
    vec3 v = -rd;
    vec3 h = normalize(kLight + v);
    float diffuse = max(dot(n, kLight), 0.0);
    float spec = pow(max(dot(n, h), 0.0), 48.0) * 0.35;
    vec3 color = v_attr * (kAmbient + 0.80 * diffuse) + vec3(spec);
    out_color = vec4(min(color, vec3(1.0)), 1.0);
}

void solid() {
    vec3 v = normalize(pc.eye.xyz - v_world);
    vec3 n = dot(v_attr, v) < 0.0 ? -v_attr : v_attr;  // two-sided: the floor is seen from inside
    float diffuse = max(dot(n, kLight), 0.0);
    vec3 albedo = pc.box_min.w * vec3(0.97, 0.98, 1.0);
    out_color = vec4(albedo * (0.45 + 0.55 * diffuse), 1.0);
}

void main() {
    if (IMPOSTOR_MODE == IMPOSTOR_MODE_PARTICLES) {
        particle();
        return;
    }
    // The shader writes gl_FragDepth (DepthReplacing), so every other mode must write it too.
    gl_FragDepth = gl_FragCoord.z;
    if (IMPOSTOR_MODE == IMPOSTOR_MODE_SOLID) {
        solid();
    } else if (IMPOSTOR_MODE == IMPOSTOR_MODE_LINES) {
        out_color = vec4(0.16, 0.19, 0.24, 1.0);
    } else {
        // soft sky: pale at the top, a muted grey-blue towards the bottom
        vec3 top = vec3(0.88, 0.90, 0.93);
        vec3 bottom = vec3(0.58, 0.61, 0.66);
        out_color = vec4(mix(top, bottom, clamp(v_world.x, 0.0, 1.0)), 1.0);
    }
}
