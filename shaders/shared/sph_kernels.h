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
AF_FN float poly6(float r2, float h2, float coefficient) {
    if (r2 >= h2) return 0.0f;
    float d = h2 - r2;
    return coefficient * d * d * d;
}

/// grad W_spiky(r, h) = -45 / (pi h^6) (h - |r|)^2 r/|r| for 0 < |r| < h, else 0.
AF_FN vec3 spiky_gradient(vec3 r, float len, float h, float coefficient) {
    if (len >= h || len <= 1.0e-6f * h) return vec3(0.0f);
    float d = h - len;
    return r * (-coefficient * d * d / len);
}

AF_END

#endif
