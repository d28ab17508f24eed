// Layout of the viewer's push brush (control/push_force.h): dragging in the window pushes the
// fluid near the mouse ray along the drag.
#ifndef AQUAFORM_PUSH_LAYOUT_H
#define AQUAFORM_PUSH_LAYOUT_H
#include "../core/compat.h"

AF_BEGIN

struct PushParams {
    vec4 origin;      ///< xyz: the mouse ray's origin (the eye) [m]; w: brush radius R [m]
    vec4 direction;   ///< xyz: the ray's unit direction; w unused
    vec3 accel;       ///< acceleration at the ray's axis [m/s^2]
    uint count;       ///< particles
};

/// Weight of the push at distance d from the ray: (1 - d/R)^2 inside the brush, 0 outside, only in
/// front of the eye; smooth at the rim so the fluid is not cut by an edge.
AF_FN float push_weight(vec3 x, PushParams p) {
    vec3 rel = x - vec3(p.origin);
    float along = dot(rel, vec3(p.direction));
    if (along <= 0.0f) return 0.0f;
    vec3 off = rel - along * vec3(p.direction);
    float d = length(off);
    float r = p.origin.w;
    if (d >= r) return 0.0f;
    float s = 1.0f - d / r;
    return s * s;
}

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::PushParams) == 48);
#endif

#endif
