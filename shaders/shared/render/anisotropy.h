// Particle shapes of Yu & Turk 2013 for the classification of Wu et al. section 4.2: a weighted
// PCA of each particle's neighbourhood gives an ellipsoidal kernel G, and the anisotropic
// density rho_i = V sum_j W(x_i - x_j, G_j) (Wu eq. 8) separates aggregated particles (bulk and
// surface) from splashes.
//
// Defaults (kDefault* below), chosen from CPU experiments on a cubic lattice with r = 2 spacings
// (the solver's h), which tests/test_anisotropy.cpp re-measures. Densities in units of rest
// density; "iso" is the isotropic kernel, "aniso" these shapes with the defaults:
//                                      n    iso    aniso
//   interior (2+ layers deep)          27   1.000  1.000   (axes 1, 1, 1: the bulk is isotropic)
//   flat surface, face centre          18   0.850  1.543   (axes 1, 1, 0.503)
//   flat surface, lowest on the face   18   0.850  1.111   (beside an edge)
//   surface edge                       12   0.720  2.331
//   surface corner                      8   0.607  1.349   (a sphere by N_eps; neighbours lift it)
//   layer just below the surface       27   1.000  1.000   (eq. 8 alone: 0.850, 0.608 below a corner; see below)
//   one-particle-thick sheet            9   0.701  2.198
//   2x2x2 droplet                       8   0.607  0.607
//   3-particle clump                    3   0.49 .. 0.51 (both)
//   lone particle                       1   0.318  0.318   (= V W(0) = 1 / pi)
// and on a 16x8x16 lattice jittered by +-0.1 spacings: surface aniso >= 0.92 (iso median 0.85),
// interior (2+ layers deep) 0.96 at the 10th percentile with both kernels.
//
// - aggregate_density = 0.9: above a flat surface's isotropic 0.85, so the isotropic kernel
//   shows the failure Wu et al. describe (its surface is "splash"), below the bulk's 1.0 and far
//   above any small clump (<= 0.61).
// - k_s = 1.25: a full neighbourhood's normalised variances are ~0.96 (lattice) and scatter
//   around 1 in irregular fluid; 1.25 lifts them over the clamp at 1, so the bulk keeps the
//   isotropic kernel exactly and only a neighbourhood short along some axis (surface, edge,
//   sheet) is flattened. k_s = 1 would shrink bulk kernels at random and make the interior noisy
//   (jittered lattice: 15 of 200 particles 3 layers deep under 0.9, against none); k_s = 2 flattens
//   the surface so little that parts of it fall under 0.9 (0.86), 2.5 not at all.
// - k_r = 4 (Yu & Turk's value): only sheets and filaments reach it; a surface's ratio is ~2.
// - k_n = 1: a sparse particle keeps the isotropic sphere, so splashes have the same density in
//   both modes (k_n = 0.5 would make a lone particle 8 / pi = 2.5 and an "aggregate").
// - N_eps = 8: up to a 2x2x2 droplet the PCA says nothing and the particle stays a sphere; a
//   surface corner (8) is one too, but its flattened neighbours still make it aggregate.
// Property of eq. 8 (the neighbour's G_j): a flattened surface kernel no longer reaches the
// layer below, which drops to ~0.85 by eq. 8 alone. The classification therefore takes the larger
// of eq. 8 and the isotropic density (render/classify_density.comp): that layer stays aggregated
// (1.0), while every splash above keeps its density. With the anisotropic surface this matters:
// the layer's sprites begin before the surface's flattened ones, and as splashes they would hold
// D_splash_back inside the fluid, so the skip would never jump.
#ifndef AQUAFORM_ANISOTROPY_H
#define AQUAFORM_ANISOTROPY_H
#include "../core/compat.h"
#include "render_kernels.h"

// Cyclic Jacobi sweeps of the 3x3 eigen-solver: a fixed count, so no data-dependent loop on the
// GPU. Convergence is quadratic; over 1e5 random rotated matrices the largest off-diagonal left,
// relative to |A|, was 3e-2, 4e-6 and 3e-13 after 2, 3 and 4 sweeps: 5 keep a sweep of margin.
#define ANISO_JACOBI_SWEEPS 5

AF_BEGIN

/// Per-axis variance, in units of r^2, of a uniform ball of radius r under the Yu-Turk weight
/// w(d) = 1 - (d / r)^3, with q = rho / r:
///   int w x^2 dV / int w dV
///     = int_0^r (1 - q^3) (rho^2 / 3) 4 pi rho^2 drho / int_0^r (1 - q^3) 4 pi rho^2 drho
///     = (pi r^5 / 10) / (2 pi r^3 / 3) = 3 r^2 / 20.
/// Dividing the eigenvalues by it makes k_s dimensionless: k_s = 1 turns a full interior
/// neighbourhood into a sphere of radius ~r (the cubic lattice with r = 2 spacings: 0.964 r).
const float ANISO_UNIFORM_BALL_VARIANCE = 0.15f;
/// Normalised largest eigenvalue below which the neighbours coincide (a collapsed neighbourhood
/// has no axes to measure): such a particle stays a k_n-sphere.
const float ANISO_MIN_SPREAD = 1.0e-6f;
/// Smallest semi-axis in units of r: keeps 1 / s and |det G| finite whatever the parameters
/// (k_s or k_n set to 0). Fluid never gets near it: k_r bounds the ratio of the axes first.
const float ANISO_MIN_AXIS = 1.0e-3f;

// ---- Symmetric 3x3 eigen-decomposition (cyclic Jacobi) -------------------------------------

struct SymmetricEigen {
    vec3 values;   ///< eigenvalues, descending
    mat3 vectors;  ///< unit eigenvectors: column k belongs to values[k]
};

struct JacobiState {
    mat3 a;  ///< the matrix being diagonalised, J^T A J so far
    mat3 v;  ///< product of the rotations: columns converge to the eigenvectors
};

/// One Jacobi rotation A <- J^T A J, V <- V J that zeroes a_pq (Golub & Van Loan 8.4.2).
/// t = tan(angle) is written without dividing by a_pq, so a zero a_pq (already diagonal:
/// repeated or zero eigenvalues) gives t = 0 rather than inf or nan, and a_pp = a_qq gives the
/// 45 degree rotation. Products of rotations stay orthonormal, so the vectors need no
/// normalisation and repeated eigenvalues still get an orthonormal basis of their space.
AF_FN JacobiState jacobi_rotate(JacobiState s, int p, int q) {
    float apq = s.a[q][p];
    float diff = s.a[q][q] - s.a[p][p];
    float denominator = abs(diff) + sqrt(diff * diff + 4.0f * apq * apq);
    float numerator = diff >= 0.0f ? 2.0f * apq : -2.0f * apq;
    float t = denominator > 0.0f ? numerator / denominator : 0.0f;
    float c = inversesqrt(t * t + 1.0f);
    float sn = t * c;
    mat3 j = mat3(1.0f);
    j[p][p] = c;
    j[q][q] = c;
    j[q][p] = sn;   // row p, column q
    j[p][q] = -sn;  // row q, column p
    s.a = transpose(j) * s.a * j;
    s.v = s.v * j;
    return s;
}

/// Puts eigenpairs a and b in descending order (a compare-and-swap of a sorting network).
AF_FN SymmetricEigen eigen_order(SymmetricEigen e, int a, int b) {
    bool swap = e.values[b] > e.values[a];
    float value_a = e.values[a];
    vec3 vector_a = e.vectors[a];
    e.values[a] = swap ? e.values[b] : value_a;
    e.values[b] = swap ? value_a : e.values[b];
    e.vectors[a] = swap ? e.vectors[b] : vector_a;
    e.vectors[b] = swap ? vector_a : e.vectors[b];
    return e;
}

/// Eigenvalues (descending) and unit eigenvectors of a symmetric matrix. Scale-free: callers
/// pass matrices of order 1 (covariances in units of r^2) so that no precision is lost.
AF_FN SymmetricEigen symmetric_eigen(mat3 m) {
    JacobiState s;
    s.a = m;
    s.v = mat3(1.0f);
    for (int sweep = 0; sweep < ANISO_JACOBI_SWEEPS; ++sweep) {
        s = jacobi_rotate(s, 0, 1);
        s = jacobi_rotate(s, 0, 2);
        s = jacobi_rotate(s, 1, 2);
    }
    SymmetricEigen e;
    e.values = vec3(s.a[0][0], s.a[1][1], s.a[2][2]);
    e.vectors = s.v;
    e = eigen_order(e, 0, 1);
    e = eigen_order(e, 1, 2);
    e = eigen_order(e, 0, 1);
    return e;
}

// ---- Weighted PCA of a neighbourhood (Yu & Turk eqs. 10-12) --------------------------------

/// Running sums over the neighbours j of a particle i, in offsets u = (x_j - x_i) / r: relative
/// and scaled, so that sums stay of order 1 wherever the fluid is (no cancellation against
/// large world coordinates) and the covariance comes out in units of r^2.
struct NeighborhoodMoments {
    float weight;  ///< sum w_j
    vec3 first;    ///< sum w_j u_j
    mat3 second;   ///< sum w_j u_j u_j^T
    uint count;    ///< neighbours with |u| < 1, the particle itself included
};

AF_FN NeighborhoodMoments moments_empty() {
    NeighborhoodMoments m;
    m.weight = 0.0f;
    m.first = vec3(0.0f);
    m.second = mat3(0.0f);
    m.count = 0u;
    return m;
}

/// Adds neighbour u = (x_j - x_i) / r with Yu & Turk's weight w = 1 - |u|^3 (zero beyond r;
/// a smooth falloff, so that a neighbour crossing r does not make the axes jump). Branch-free:
/// the 27-cell loop visits many particles outside r.
AF_FN NeighborhoodMoments moments_add(NeighborhoodMoments m, vec3 u) {
    float q2 = dot(u, u);
    float inside = q2 < 1.0f ? 1.0f : 0.0f;
    float w = inside * (1.0f - q2 * sqrt(q2));
    m.weight += w;
    m.first += w * u;
    m.second += w * outerProduct(u, u);
    m.count += q2 < 1.0f ? 1u : 0u;
    return m;
}

/// Weighted covariance about the weighted mean (Yu & Turk eq. 12), in units of r^2:
/// C = sum w u u^T / sum w - mean mean^T. The particle itself has w = 1, so sum w >= 1.
AF_FN mat3 moments_covariance(NeighborhoodMoments m) {
    float inv_weight = 1.0f / max(m.weight, 1.0e-20f);
    vec3 mean = m.first * inv_weight;
    return m.second * inv_weight - outerProduct(mean, mean);
}

// ---- The kernel's shape G (Yu & Turk eqs. 13-15, Wu eq. 9) ---------------------------------

struct AnisotropicShape {
    mat3 g;       ///< G = (1 / r) R diag(1 / s_k) R^T (symmetric)
    float det_g;  ///< |det G| = 1 / (r^3 s_1 s_2 s_3)
    vec3 axes;    ///< semi-axes s_k of the kernel's support ellipsoid, in units of r, descending
};

/// G from the covariance C (in units of r^2, see moments_covariance) of `neighbor_count`
/// neighbours (the particle included):
///   sigma_k = eigenvalues of C / ANISO_UNIFORM_BALL_VARIANCE   (dimensionless, see above)
///   s_k     = k_s max(sigma_k, sigma_1 / k_r)  if n > N_eps     (Yu-Turk eq. 15: no axis shorter
///                                                                than 1 / k_r of the longest, so a
///                                                                flat neighbourhood stays finite)
///           = k_n                              otherwise        (too few neighbours for a PCA: a
///                                                                sphere of radius k_n r)
///   s_k     = min(s_k, 1)
/// The last clamp keeps every semi-axis r s_k <= r: the ellipsoid then lies inside the ball of
/// radius r, so the 27 grid cells of size r around a particle still hold every particle its
/// kernel reaches and the density sum stays exact.
AF_FN AnisotropicShape anisotropic_shape(mat3 covariance_r2, uint neighbor_count, float radius, float k_r,
                                         float k_s, float k_n, uint n_eps) {
    SymmetricEigen e = symmetric_eigen(covariance_r2 * (1.0f / ANISO_UNIFORM_BALL_VARIANCE));
    // (Rounding can leave a zero eigenvalue slightly negative.)
    vec3 sigma = max(e.values, vec3(0.0f));
    vec3 stretched = k_s * max(sigma, vec3(sigma.x / k_r));
    bool shaped = neighbor_count > n_eps && sigma.x > ANISO_MIN_SPREAD;
    vec3 axes = clamp(shaped ? stretched : vec3(k_n), vec3(ANISO_MIN_AXIS), vec3(1.0f));
    vec3 inv_axes = 1.0f / axes;
    float inv_radius = 1.0f / radius;
    mat3 scaled = mat3(e.vectors[0] * inv_axes.x, e.vectors[1] * inv_axes.y, e.vectors[2] * inv_axes.z);
    AnisotropicShape shape;
    shape.g = (scaled * transpose(e.vectors)) * inv_radius;
    shape.det_g = inv_axes.x * inv_axes.y * inv_axes.z * inv_radius * inv_radius * inv_radius;
    shape.axes = axes;
    return shape;
}

/// Laplacian smoothing of the kernel centre (Yu & Turk eq. 6): x_bar = (1 - lambda) x + lambda x_w,
/// with x_w the weighted mean of the neighbourhood (the moments' first / weight, in units of r).
/// It pulls a surface particle towards its neighbours, so that the jitter of a free surface's
/// particles does not show as bumps. A neighbourhood of N_eps or fewer is left where it is, like
/// its shape: a small clump's members would otherwise be pulled onto each other and drawn as one
/// fat droplet. |x_bar - x| < lambda r.
AF_FN vec3 smoothed_centre(vec3 x, NeighborhoodMoments m, float radius, float lambda, uint n_eps) {
    vec3 mean = m.first * (1.0f / max(m.weight, 1.0e-20f));
    return m.count > n_eps ? x + (lambda * radius) * mean : x;
}

/// The isotropic kernel's shape, G = I / r (for comparisons and tests).
AF_FN AnisotropicShape isotropic_shape(float radius) {
    AnisotropicShape shape;
    shape.g = mat3(1.0f / radius);
    shape.det_g = 1.0f / (radius * radius * radius);
    shape.axes = vec3(1.0f);
    return shape;
}

/// Anisotropic cubic kernel (Wu eq. 8): W(d, G) = (8 / pi) |det G| P(|G d|). With G = I / r it
/// is the isotropic cubic_kernel of render_kernels.h; like it, it integrates to 1 over space.
AF_FN float anisotropic_kernel(vec3 d, mat3 g, float det_g) {
    return (8.0f / RENDER_PI) * det_g * cubic_shape(length(g * d));
}

/// grad W(d, G) = (8 / pi) |det G| P'(q) G^T G d / q with q = |G d| (G symmetric); zero at d = 0.
AF_FN vec3 anisotropic_kernel_gradient(vec3 d, mat3 g, float det_g) {
    vec3 gd = g * d;
    float q2 = dot(gd, gd);
    float inv_q = inversesqrt(max(q2, 1.0e-20f));
    return (g * gd) * ((8.0f / RENDER_PI) * det_g * cubic_shape_derivative(q2 * inv_q) * inv_q);
}

AF_END

#ifdef __cplusplus
namespace aquaform::shader {
constexpr float kDefaultAnisoKr = 4.0f;
constexpr float kDefaultAnisoKs = 1.25f;
constexpr float kDefaultAnisoKn = 1.0f;
constexpr uint32_t kDefaultAnisoNeps = 8;
constexpr float kDefaultAggregateDensity = 0.9f;
constexpr float kDefaultCentreSmoothing = 0.9f;
}  // namespace aquaform::shader
#endif

#endif
