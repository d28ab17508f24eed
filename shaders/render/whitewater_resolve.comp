#version 460
#extension GL_GOOGLE_include_directive : require
// Whitewater over a rendered frame, second pass (render/whitewater_layer.h): each pixel's summed
// opacity becomes its coverage, 1 - exp(-sum), and the frame's colour goes that far towards
// white water lit by the sun and the sky: scattering many times, it is matte and bright.
#include "shared/render/whitewater_draw_layout.h"

layout(local_size_x_id = 0) in;
layout(std140, binding = 0) uniform Draw { WhitewaterDrawParams params; };
layout(std430, binding = 1) buffer Coverage { uint coverage[]; };
layout(std430, binding = 2) buffer Color { uint color[]; };

const float kCoverageOne = 4096.0;

// The renderers' encoding (pack_srgb, common/environment.glsl): a 2.2 power.
vec3 to_linear(vec3 c) { return pow(c, vec3(2.2)); }
vec3 to_srgb(vec3 c) { return pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)); }

void main() {
    uint pixel = gl_GlobalInvocationID.x;
    if (pixel >= params.screen.x * params.screen.y) return;
    uint sum = coverage[pixel];
    coverage[pixel] = 0u;  // ready for the next frame
    if (sum == 0u) return;
    float cover = 1.0 - exp(-float(sum) / kCoverageOne);
    vec4 c = unpackUnorm4x8(color[pixel]);
    // White water: the sky's light from above and the sun's, scattered evenly; brighter than
    // the sky it is seen against (it scatters the sun's light too).
    vec3 white = vec3(1.0) * (0.9 + 0.1 * max(params.light.y, 0.0));
    vec3 rgb = mix(to_linear(c.rgb), white, cover);
    color[pixel] = packUnorm4x8(vec4(to_srgb(rgb), c.a));
}
