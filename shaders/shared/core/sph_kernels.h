// SPH smoothing kernels of Mueller et al. 2003, used by the PBF solver (Macklin & Mueller 2013
// use poly6 for density and the spiky gradient for the constraint gradient).
#ifndef AQUAFORM_SPH_KERNELS_H
#define AQUAFORM_SPH_KERNELS_H
#include "compat.h"

AF_BEGIN

const float SPH_PI = 3.14159265358979f;

/// Normalisation of poly6: 315 / (64 pi h^9).
AF_FN float poly6_coefficient(float h) {
    float h3 = h * h * h;
    return 315.0f / (64.0f * SPH_PI * h3 * h3 * h3);
}

/// Normalisation of the spiky gradient: 45 / (pi h^6).
AF_FN float spiky_gradient_coefficient(float h) {
    float h3 = h * h * h;
    return 45.0f / (SPH_PI * h3 * h3);
}

/// W_poly6(r, h) = 315 / (64 pi h^9) (h^2 - r^2)^3 for r < h, else 0.
/// Branch-free, like the spiky gradient: SIMD hardware (the software device runs 8 particles
/// per instruction) pays for a branch in masking, and the neighbour loops call these per pair.
AF_FN float poly6(float r2, float h2, float coefficient) {
    float d = max(h2 - r2, 0.0f);
    return coefficient * d * d * d;
}

/// grad W_spiky(r, h) = -45 / (pi h^6) (h - |r|)^2 r/|r| for |r| < h, else 0; also 0 at r = 0,
/// so a particle's own term vanishes. Takes |r|^2: one inverse square root, no division.
AF_FN vec3 spiky_gradient(vec3 r, float r2, float h, float coefficient) {
    float inv_len = inversesqrt(max(r2, 1.0e-12f * h * h));
    float d = max(h - r2 * inv_len, 0.0f);
    return r * (-coefficient * d * d * inv_len);
}

/// grad W_poly6(r, h) = -6 * 315 / (64 pi h^9) (h^2 - r^2)^2 r for |r| < h, else 0. Unlike the
/// spiky gradient it vanishes smoothly at r = 0, so a lattice of sources sums to a flat field.
AF_FN vec3 poly6_gradient(vec3 r, float r2, float h2, float coefficient) {
    float d = max(h2 - r2, 0.0f);
    return r * (-6.0f * coefficient * d * d);
}

AF_END

#endif
