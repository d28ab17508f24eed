#version 460
#extension GL_GOOGLE_include_directive : require
// One iteration of screen-space curvature flow (van der Laan, Green & Sainz 2009, section 4):
// the depth moves along the mean curvature H of the view-space surface it describes,
//   n = (-C_y z_x, -C_x z_y, C_x C_y z) / sqrt(D),  D = C_y^2 z_x^2 + C_x^2 z_y^2 + C_x^2 C_y^2 z^2,
//   2H = dn_x/dx + dn_y/dy = (C_y E_x + C_x E_y) / D^(3/2),
//   E_x = 1/2 z_x dD/dx - z_xx D,  E_y = 1/2 z_y dD/dy - z_yy D,
// with central differences over the 3x3 neighbourhood (x, y in pixels). Here z is the positive
// eye depth d and C_x, C_y > 0 (the paper's z is negative OpenGL view z, whose projection makes
// its C negative), so the smoothing step reads d <- d - dt H: its small-slope limit is the heat
// equation d <- d + kappa (d_xx + d_yy). The paper's n leaves out the perspective terms of the
// exact normal (x/f z_x and y/f z_y in n_z), so a plane seen at an angle is not quite a fixed
// point: measured on a slab seen 40 deg off its normal, 200 iterations bend it by 0.3 radii.
// Choices the paper leaves open:
// - dt per pixel, dt = 2 kappa min(C_x, C_y) d, so that every iteration diffuses kappa px^2 at
//   small slopes wherever the fluid is: a fixed dt would be unstable near the camera (the
//   explicit step needs kappa <= 1/4) and do nothing far away.
// - Discontinuities: a neighbour that is empty, beyond the image, or more than `flow_jump` away
//   in depth is replaced by the centre's own depth (a zero-flux boundary), so no depth flows
//   across a silhouette or between layers, and the set of covered pixels never changes.
#include "shared/render/surface_layout.h"
#include "shared/render/screen_space_layout.h"

layout(local_size_x_id = 0) in;
layout(std430, binding = 0) readonly buffer Params { ScreenSpaceParams ss; };
layout(std430, binding = 1) readonly buffer Src { uint src[]; };
layout(std430, binding = 2) writeonly buffer Dst { uint dst[]; };

#include "common/screen_space_common.glsl"

ivec2 g_pixel;
float g_centre;

/// The neighbour's depth, or the centre's across a discontinuity.
float at(int dx, int dy) {
    ivec2 q = g_pixel + ivec2(dx, dy);
    if (!ss_inside(q)) return g_centre;
    uint bits = src[ss_index(q)];
    if (bits == DEPTH_EMPTY) return g_centre;
    float z = uintBitsToFloat(bits);
    return abs(z - g_centre) > ss.flow_jump ? g_centre : z;
}

void main() {
    uint index = gl_GlobalInvocationID.x;
    if (index >= ss.screen.x * ss.screen.y) return;
    uint centre_bits = src[index];
    if (centre_bits == DEPTH_EMPTY) {
        dst[index] = DEPTH_EMPTY;
        return;
    }
    float z = uintBitsToFloat(centre_bits);
    g_pixel = ivec2(index % ss.screen.x, index / ss.screen.x);
    g_centre = z;
    float right = at(1, 0), left = at(-1, 0), down = at(0, 1), up = at(0, -1);
    float zx = 0.5 * (right - left);
    float zy = 0.5 * (down - up);
    float zxx = right + left - 2.0 * z;
    float zyy = down + up - 2.0 * z;
    float zxy = 0.25 * (at(1, 1) - at(1, -1) - at(-1, 1) + at(-1, -1));
    float cx = ss.cx, cy = ss.cy;
    float cx2 = cx * cx, cy2 = cy * cy;
    float d = cy2 * zx * zx + cx2 * zy * zy + cx2 * cy2 * z * z;
    float ddx = 2.0 * (cy2 * zx * zxx + cx2 * zy * zxy + cx2 * cy2 * z * zx);
    float ddy = 2.0 * (cy2 * zx * zxy + cx2 * zy * zyy + cx2 * cy2 * z * zy);
    float ex = 0.5 * zx * ddx - zxx * d;
    float ey = 0.5 * zy * ddy - zyy * d;
    float h = (cy * ex + cx * ey) / (2.0 * d * sqrt(d));
    float dt = 2.0 * ss.flow_step * min(cx, cy) * z;
    dst[index] = floatBitsToUint(z - dt * h);
}
