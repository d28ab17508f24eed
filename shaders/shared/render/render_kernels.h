// The smoothing kernel of the surface renderer: the cubic spline of Koschier et al. (the
// "symmetric decaying spline with finite support" of Wu et al. eq. 7, as the thesis implements
// it), with support radius r:
//   W(d, r) = 8 / (pi r^3) P(|d| / r),  P(q) = 6 (q^3 - q^2) + 1 for q <= 1/2, 2 (1 - q)^3 for q <= 1.
// The field the renderer ray-marches is the normalised density phi(p) = V sum_j W(p - x_j, r),
// with V = spacing^3 the volume of one particle, so that phi is 1 inside resting fluid.
#ifndef AQUAFORM_RENDER_KERNELS_H
#define AQUAFORM_RENDER_KERNELS_H
#include "../core/compat.h"

AF_BEGIN

const float RENDER_PI = 3.14159265358979f;

/// 8 / (pi r^3): the cubic spline's normalisation in three dimensions.
AF_FN float cubic_coefficient(float r) { return 8.0f / (RENDER_PI * r * r * r); }

/// P(q) for q = |d| / r; zero for q >= 1.
AF_FN float cubic_shape(float q) {
    float inner = 6.0f * (q * q * q - q * q) + 1.0f;
    float t = max(1.0f - q, 0.0f);
    return q <= 0.5f ? inner : 2.0f * t * t * t;
}

/// dP/dq; zero for q >= 1.
AF_FN float cubic_shape_derivative(float q) {
    float inner = 6.0f * (3.0f * q * q - 2.0f * q);
    float t = max(1.0f - q, 0.0f);
    return q <= 0.5f ? inner : -6.0f * t * t;
}

/// W(d, r) from |d|^2, r and 1 / r.
AF_FN float cubic_kernel(float d2, float inv_r, float coefficient) {
    return coefficient * cubic_shape(sqrt(d2) * inv_r);
}

/// grad W(d, r) (points from the particle towards d, negative along d); zero at d = 0.
AF_FN vec3 cubic_gradient(vec3 d, float d2, float inv_r, float coefficient) {
    float inv_len = inversesqrt(max(d2, 1.0e-20f));
    float q = d2 * inv_len * inv_r;
    return d * (coefficient * cubic_shape_derivative(q) * inv_r * inv_len);
}

/// The q at which P(q) = value (0 < value <= 1), by bisection: the radius, in units of r, of a
/// lone particle's iso-sphere. Used to choose the iso value and by tests.
AF_FN float cubic_shape_inverse(float value) {
    float lo = 0.0f;
    float hi = 1.0f;
    for (int i = 0; i < 40; ++i) {
        float mid = 0.5f * (lo + hi);
        if (cubic_shape(mid) > value) lo = mid;
        else hi = mid;
    }
    return 0.5f * (lo + hi);
}

AF_END

#endif
