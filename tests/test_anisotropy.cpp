// Particle classification (Wu et al. 4.2) with the Yu-Turk shapes of shaders/shared/render/anisotropy.h:
// the eigen-solver, the shapes of typical neighbourhoods, the kernel, a CPU classification of a
// lattice slab that re-measures the densities behind the documented defaults, and the two GPU
// passes (render/classify_shape.comp, render/classify_density.comp) against that CPU reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "grid/neighbor_grid.h"
#include "shaders/shared/render/anisotropy.h"
#include "shaders/shared/render/render_kernels.h"
#include "shaders/shared/render/surface_layout.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

using shader::AnisotropicShape;
using shader::NeighborhoodMoments;

// A power-of-two spacing: lattice positions, offsets and |d|^2 are exact, so a neighbour at
// exactly r is excluded identically on the CPU and the GPU.
constexpr float kSpacing = 0.125f;
constexpr float kRadius = 2.0f * kSpacing;  // the solver's h
constexpr float kVolume = kSpacing * kSpacing * kSpacing;

struct ShapeParams {
    float k_r = shader::kDefaultAnisoKr;
    float k_s = shader::kDefaultAnisoKs;
    float k_n = shader::kDefaultAnisoKn;
    uint32_t n_eps = shader::kDefaultAnisoNeps;
};

glm::mat3 random_rotation(std::mt19937& rng) {
    std::normal_distribution<float> g(0.0f, 1.0f);
    return glm::mat3_cast(glm::normalize(glm::quat(g(rng), g(rng), g(rng), g(rng))));
}

/// The shape of particle `i` from all `points` (brute force: points beyond r add exact zeros).
AnisotropicShape shape_of(const std::vector<glm::vec3>& points, size_t i, const ShapeParams& p,
                          uint32_t* count = nullptr) {
    NeighborhoodMoments m = shader::moments_empty();
    for (const glm::vec3& x : points) m = shader::moments_add(m, (x - points[i]) * (1.0f / kRadius));
    if (count) *count = m.count;
    return shader::anisotropic_shape(shader::moments_covariance(m), m.count, kRadius, p.k_r, p.k_s, p.k_n, p.n_eps);
}

/// Offsets of the cubic lattice within r of the origin (the origin included), rotated.
std::vector<glm::vec3> lattice_ball(const glm::mat3& rotation, bool lower_half_only) {
    std::vector<glm::vec3> points{glm::vec3(0.0f)};
    for (int z = -2; z <= 2; ++z)
        for (int y = -2; y <= 2; ++y)
            for (int x = -2; x <= 2; ++x) {
                const glm::vec3 d = glm::vec3(x, y, z) * kSpacing;
                if ((x || y || z) && glm::length(d) < kRadius && !(lower_half_only && y > 0))
                    points.push_back(rotation * d);
            }
    return points;
}

/// Semi-axis of the kernel's support along unit direction n, in units of r: 1 / (r |G n|).
float support_along(const AnisotropicShape& s, glm::vec3 n) { return 1.0f / (kRadius * glm::length(s.g * n)); }

// ---- Eigen-decomposition --------------------------------------------------------------------

void expect_eigen_recovers(const glm::mat3& rotation, glm::vec3 values, const char* what) {
    SCOPED_TRACE(what);
    const glm::mat3 diag(values.x, 0, 0, 0, values.y, 0, 0, 0, values.z);
    const glm::mat3 a = rotation * diag * glm::transpose(rotation);
    const shader::SymmetricEigen e = shader::symmetric_eigen(a);
    float expected[3] = {values.x, values.y, values.z};
    std::sort(expected, expected + 3, [](float l, float r) { return l > r; });
    const float scale = std::max({std::abs(values.x), std::abs(values.y), std::abs(values.z), 1.0e-3f});
    const float tol = 2.0e-6f * scale;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(e.values[k], expected[k], tol) << "eigenvalue " << k;
    EXPECT_GE(e.values[0], e.values[1]);
    EXPECT_GE(e.values[1], e.values[2]);
    const glm::mat3 gram = glm::transpose(e.vectors) * e.vectors;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) EXPECT_NEAR(gram[c][r], c == r ? 1.0f : 0.0f, 1.0e-6f) << "V^T V at " << r << c;
    for (int k = 0; k < 3; ++k) {
        // A v = lambda v holds for any basis of a repeated eigenvalue's space.
        const glm::vec3 residual = a * e.vectors[k] - e.values[k] * e.vectors[k];
        EXPECT_LT(glm::length(residual), 4.0f * tol) << "eigenpair " << k;
        // A distinct eigenvalue's vector is the rotated axis it came from (up to sign).
        const bool distinct = (k == 0 || expected[k - 1] - expected[k] > 1.0e-3f * scale) &&
                              (k == 2 || expected[k] - expected[k + 1] > 1.0e-3f * scale);
        if (!distinct) continue;
        const int axis = expected[k] == values.x ? 0 : expected[k] == values.y ? 1 : 2;
        EXPECT_NEAR(std::abs(glm::dot(e.vectors[k], rotation[axis])), 1.0f, 1.0e-5f) << "eigenvector " << k;
    }
}

TEST(AnisotropyEigen, RecoversRotatedDiagonalMatrices) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.05f, 2.0f);
    for (int trial = 0; trial < 200; ++trial) {
        const glm::mat3 q = random_rotation(rng);
        const float a = u(rng), b = u(rng), c = u(rng);
        expect_eigen_recovers(q, {a, b, c}, "distinct");
        expect_eigen_recovers(q, {a, a, c}, "two equal, third apart");
        expect_eigen_recovers(q, {a, c, c}, "two equal, other order");
        expect_eigen_recovers(q, {a, a, a}, "all equal");
        expect_eigen_recovers(q, {a, 0.0f, b}, "one zero (points on a plane)");
        expect_eigen_recovers(q, {0.0f, a, 0.0f}, "two zero (points on a line)");
        expect_eigen_recovers(q, {a, a * (1.0f + 1.0e-6f), b}, "nearly equal");
        expect_eigen_recovers(q, {-a, b, 0.0f}, "indefinite");
        if (::testing::Test::HasFailure()) break;
    }
    expect_eigen_recovers(glm::mat3(1.0f), {0.0f, 0.0f, 0.0f}, "zero matrix");
    expect_eigen_recovers(glm::mat3(1.0f), {0.3f, 0.9f, 0.6f}, "already diagonal");
}

// ---- Shapes -----------------------------------------------------------------------------------

TEST(AnisotropyShape, UniformBallVarianceIsThreeTwentieths) {
    // Monte Carlo of the weighted per-axis variance of a uniform unit ball: the constant that
    // makes k_s dimensionless.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    double weight = 0.0, second = 0.0;
    for (int i = 0; i < 400000; ++i) {
        const glm::vec3 p(u(rng), u(rng), u(rng));
        const float q = glm::length(p);
        if (q >= 1.0f) continue;
        const double w = 1.0 - double(q) * q * q;
        weight += w;
        second += w * p.x * p.x;
    }
    EXPECT_NEAR(second / weight, shader::ANISO_UNIFORM_BALL_VARIANCE, 1.5e-3);
}

TEST(AnisotropyShape, FullInteriorNeighbourhoodIsASphereOfRadiusR) {
    std::mt19937 rng(11);
    const glm::mat3 rotation = random_rotation(rng);
    const std::vector<glm::vec3> points = lattice_ball(rotation, false);
    ShapeParams unit_scale;
    unit_scale.k_s = 1.0f;
    uint32_t count = 0;
    const AnisotropicShape s = shape_of(points, 0, unit_scale, &count);
    EXPECT_EQ(count, 27u);
    // k_s = 1: the lattice's variance is 0.964 of the continuous ball's.
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.axes[k], 0.964f, 0.005f) << "axis " << k;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            EXPECT_NEAR(s.g[c][r] * kRadius * 0.964f, c == r ? 1.0f : 0.0f, 0.01f) << "G at " << r << c;

    // The defaults (k_s = 1.25) clamp all three axes to exactly r: the isotropic kernel.
    const AnisotropicShape d = shape_of(points, 0, ShapeParams{});
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) EXPECT_NEAR(d.g[c][r] * kRadius, c == r ? 1.0f : 0.0f, 1.0e-5f);
    EXPECT_NEAR(d.det_g * kRadius * kRadius * kRadius, 1.0f, 1.0e-5f);
}

TEST(AnisotropyShape, FlatSurfaceHasItsShortAxisAlongTheNormal) {
    std::mt19937 rng(12);
    for (int trial = 0; trial < 10; ++trial) {
        const glm::mat3 rotation = random_rotation(rng);
        const glm::vec3 normal = rotation[1];  // the lattice's +y, rotated
        const std::vector<glm::vec3> points = lattice_ball(rotation, true);
        for (float k_s : {1.0f, shader::kDefaultAnisoKs}) {
            ShapeParams p;
            p.k_s = k_s;
            uint32_t count = 0;
            const AnisotropicShape s = shape_of(points, 0, p, &count);
            EXPECT_EQ(count, 18u);
            const float along_normal = support_along(s, normal);
            // (The half ball's normalised variance along the normal is 0.402.)
            EXPECT_NEAR(along_normal, 0.402f * k_s, 0.005f) << "k_s " << k_s;
            EXPECT_NEAR(along_normal, s.axes.z, 1.0e-4f) << "the normal is the shortest axis";
            // Tangents keep (nearly) the full radius.
            EXPECT_GT(support_along(s, rotation[0]), 0.97f);
            EXPECT_GT(support_along(s, rotation[2]), 0.97f);
            // G n is parallel to n: n is an eigenvector of G.
            EXPECT_NEAR(std::abs(glm::dot(glm::normalize(s.g * normal), normal)), 1.0f, 1.0e-5f);
            EXPECT_NEAR(s.det_g, std::abs(glm::determinant(s.g)), 1.0e-3f * s.det_g);
        }
    }
}

TEST(AnisotropyShape, SparseNeighbourhoodIsASphereOfRadiusKnR) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    ShapeParams p;
    p.k_n = 0.7f;
    std::vector<glm::vec3> points{glm::vec3(0.0f)};
    while (points.size() < p.n_eps) points.push_back(kRadius * glm::vec3(u(rng), u(rng), u(rng)));
    uint32_t count = 0;
    const AnisotropicShape s = shape_of(points, 0, p, &count);
    EXPECT_EQ(count, p.n_eps);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) EXPECT_NEAR(s.g[c][r] * kRadius * p.k_n, c == r ? 1.0f : 0.0f, 1.0e-5f);
    EXPECT_NEAR(s.det_g, 1.0f / std::pow(p.k_n * kRadius, 3.0f), 1.0e-5f * s.det_g);

    // One more neighbour and the PCA decides: these points are anything but a full ball.
    points.push_back(glm::vec3(0.3f * kRadius, 0.0f, 0.0f));
    const AnisotropicShape shaped = shape_of(points, 0, p, &count);
    EXPECT_EQ(count, p.n_eps + 1);
    EXPECT_GT(shaped.axes.x - shaped.axes.z, 0.05f);

    // A lone particle, and particles piled on one spot (no spread to measure), stay spheres too.
    const AnisotropicShape lone = shape_of({glm::vec3(1.0f)}, 0, p);
    EXPECT_NEAR(lone.det_g, 1.0f / std::pow(p.k_n * kRadius, 3.0f), 1.0e-5f * lone.det_g);
    const std::vector<glm::vec3> pile(20, glm::vec3(0.5f));
    const AnisotropicShape piled = shape_of(pile, 0, p, &count);
    EXPECT_EQ(count, 20u);
    EXPECT_NEAR(piled.det_g, 1.0f / std::pow(p.k_n * kRadius, 3.0f), 1.0e-5f * piled.det_g);
}

TEST(AnisotropyShape, AxesNeverExceedTheRadius) {
    // Whatever k_s and k_n ask for, the support stays inside the ball of radius r (the grid
    // query's 27 cells), and k_r bounds the ratio of the axes.
    std::mt19937 rng(14);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<glm::vec3> points{glm::vec3(0.0f)};
    for (int i = 0; i < 30; ++i) points.push_back(kRadius * glm::vec3(u(rng), 0.2f * u(rng), 0.05f * u(rng)));
    for (float k_s : {0.5f, 1.0f, 3.0f, 100.0f}) {
        ShapeParams p;
        p.k_s = k_s;
        p.k_n = 5.0f;
        const AnisotropicShape s = shape_of(points, 0, p);
        EXPECT_LE(s.axes.x, 1.0f);
        EXPECT_GE(s.axes.z * p.k_r, s.axes.x * (1.0f - 1.0e-5f)) << "k_s " << k_s;
        for (int i = 0; i < 50; ++i) {
            const glm::vec3 n = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
            EXPECT_LE(support_along(s, n), 1.0f + 1.0e-5f);
        }
    }
    ShapeParams big_sphere;
    big_sphere.k_n = 5.0f;
    EXPECT_NEAR(shape_of({glm::vec3(0.0f)}, 0, big_sphere).det_g * kRadius * kRadius * kRadius, 1.0f, 1.0e-5f);
}

// ---- Kernel -----------------------------------------------------------------------------------

TEST(AnisotropyKernel, ReducesToTheIsotropicKernel) {
    const AnisotropicShape iso = shader::isotropic_shape(kRadius);
    for (float t : {0.0f, 0.1f, 0.3f, 0.5f, 0.7f, 0.99f, 1.0f, 1.5f}) {
        const glm::vec3 d = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f)) * (t * kRadius);
        const float expected = shader::cubic_kernel(glm::dot(d, d), 1.0f / kRadius, shader::cubic_coefficient(kRadius));
        const float tolerance = 1.0e-5f * shader::cubic_coefficient(kRadius);
        EXPECT_NEAR(shader::anisotropic_kernel(d, iso.g, iso.det_g), expected, tolerance) << "q = " << t;
    }
}

TEST(AnisotropyKernel, FlattenedKernelStillIntegratesToOne) {
    std::mt19937 rng(15);
    const glm::mat3 rotation = random_rotation(rng);
    const AnisotropicShape s = shape_of(lattice_ball(rotation, true), 0, ShapeParams{});
    ASSERT_LT(s.axes.z, 0.6f);
    // Midpoint sum over the cube [-r, r]^3 that holds the support.
    const int cells = 96;
    const float h = 2.0f * kRadius / cells;
    double sum = 0.0;
    for (int z = 0; z < cells; ++z)
        for (int y = 0; y < cells; ++y)
            for (int x = 0; x < cells; ++x) {
                const glm::vec3 d = (glm::vec3(x, y, z) + 0.5f) * h - glm::vec3(kRadius);
                sum += shader::anisotropic_kernel(d, s.g, s.det_g);
            }
    EXPECT_NEAR(sum * h * h * h, 1.0, 2.0e-3);
}

// ---- Classification (CPU) -------------------------------------------------------------------

struct Classification {
    std::vector<AnisotropicShape> shapes;
    std::vector<uint32_t> counts;
    std::vector<float> density;
    std::vector<uint32_t> aggregate;
};

/// The two passes on the CPU, by brute force over all pairs (the GPU sums the 27 cells; pairs
/// beyond r add exact zeros).
Classification classify_cpu(const std::vector<glm::vec3>& x, bool anisotropic, const ShapeParams& p = {},
                            float aggregate_density = shader::kDefaultAggregateDensity) {
    Classification c;
    const size_t n = x.size();
    c.counts.resize(n);
    for (size_t i = 0; i < n; ++i) c.shapes.push_back(shape_of(x, i, p, &c.counts[i]));
    const float coefficient = shader::cubic_coefficient(kRadius);
    for (size_t i = 0; i < n; ++i) {
        float sum = 0.0f;
        float iso_sum = 0.0f;
        for (size_t j = 0; j < n; ++j) {
            const glm::vec3 d = x[i] - x[j];
            sum += anisotropic ? shader::anisotropic_kernel(d, c.shapes[j].g, c.shapes[j].det_g) : 0.0f;
            iso_sum += shader::cubic_kernel(glm::dot(d, d), 1.0f / kRadius, coefficient);
        }
        // classify_density.comp: the anisotropic density never falls below the isotropic one.
        c.density.push_back(kVolume * std::max(sum, iso_sum));
        c.aggregate.push_back(c.density.back() >= aggregate_density ? 1u : 0u);
    }
    return c;
}

/// A slab of nx x ny x nz lattice particles at `origin`, plus splashes well apart from it.
struct SlabScene {
    int nx, ny, nz;
    std::vector<glm::vec3> positions;
    size_t lone = 0, clump = 0, droplet = 0;  ///< first index of each splash group

    SlabScene(int nx_, int ny_, int nz_, glm::vec3 origin) : nx(nx_), ny(ny_), nz(nz_) {
        for (int z = 0; z < nz; ++z)
            for (int y = 0; y < ny; ++y)
                for (int x = 0; x < nx; ++x) positions.push_back(origin + glm::vec3(x, y, z) * kSpacing);
        const glm::vec3 above = origin + glm::vec3(0.0f, float(ny + 6) * kSpacing, 0.0f);
        lone = positions.size();
        positions.push_back(above + glm::vec3(2.0f, 0.0f, 2.0f) * kSpacing);
        clump = positions.size();  // three particles a spacing apart
        const glm::vec3 c = above + glm::vec3(6.0f, 0.3f, 2.0f) * kSpacing;
        positions.push_back(c);
        positions.push_back(c + glm::vec3(kSpacing, 0.0f, 0.0f));
        positions.push_back(c + glm::vec3(0.5f, 0.8f, 0.1f) * kSpacing);
        droplet = positions.size();  // 2x2x2
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 corner(k & 1, (k >> 1) & 1, k >> 2);
            positions.push_back(above + (glm::vec3(2.0f, 4.0f, 7.0f) + corner) * kSpacing);
        }
    }
    size_t index(int x, int y, int z) const { return size_t(x + nx * (y + ny * z)); }
    /// Lattice distance to the nearest face of the slab (0: on the surface).
    int depth(int x, int y, int z) const { return std::min({x, nx - 1 - x, y, ny - 1 - y, z, nz - 1 - z}); }
};

TEST(AnisotropyClassification, AnisotropicKernelsKeepTheSurfaceAggregated) {
    const SlabScene scene(12, 6, 12, glm::vec3(1.0f));
    const Classification aniso = classify_cpu(scene.positions, true);
    const Classification iso = classify_cpu(scene.positions, false);
    const int top = scene.ny - 1;
    int checked_top = 0, checked_interior = 0;
    for (int z = 0; z < scene.nz; ++z)
        for (int x = 0; x < scene.nx; ++x) {
            const size_t i = scene.index(x, top, z);
            // Every particle of the top layer, edges and corners included...
            EXPECT_EQ(aniso.aggregate[i], 1u) << "top (" << x << ", " << z << "): rho " << aniso.density[i];
            // ... and none with the isotropic kernel: a flat surface has 0.85 of the bulk's
            // density, under the threshold. This is the failure Wu et al. fix (their figure 4).
            EXPECT_EQ(iso.aggregate[i], 0u) << "top (" << x << ", " << z << "): rho " << iso.density[i];
            ++checked_top;
        }
    for (int z = 0; z < scene.nz; ++z)
        for (int y = 0; y < scene.ny; ++y)
            for (int x = 0; x < scene.nx; ++x) {
                if (scene.depth(x, y, z) < 2) continue;  // see anisotropy.h on the layer below the surface
                const size_t i = scene.index(x, y, z);
                EXPECT_EQ(aniso.aggregate[i], 1u) << "interior (" << x << ", " << y << ", " << z << ")";
                EXPECT_EQ(iso.aggregate[i], 1u) << "interior (" << x << ", " << y << ", " << z << ")";
                ++checked_interior;
            }
    EXPECT_EQ(checked_top, 144);
    EXPECT_EQ(checked_interior, 8 * 2 * 8);
    for (const Classification* c : {&aniso, &iso}) {
        EXPECT_EQ(c->aggregate[scene.lone], 0u) << "lone particle: rho " << c->density[scene.lone];
        for (size_t i = scene.clump; i < scene.clump + 3; ++i)
            EXPECT_EQ(c->aggregate[i], 0u) << "clump particle " << i - scene.clump << ": rho " << c->density[i];
        for (size_t i = scene.droplet; i < scene.droplet + 8; ++i)
            EXPECT_EQ(c->aggregate[i], 0u) << "2x2x2 droplet particle: rho " << c->density[i];
    }
}

TEST(AnisotropyClassification, DensitiesMatchTheDocumentedDefaults) {
    // The numbers in the comment block of anisotropy.h that justify the defaults.
    const SlabScene scene(12, 6, 12, glm::vec3(1.0f));
    const Classification aniso = classify_cpu(scene.positions, true);
    const Classification iso = classify_cpu(scene.positions, false);
    struct Expected {
        const char* what;
        size_t index;
        uint32_t count;
        float iso, aniso;
    };
    const int top = scene.ny - 1;
    const Expected rows[] = {
        {"interior", scene.index(6, 3, 6), 27, 1.000f, 1.000f},
        {"surface, face centre", scene.index(6, top, 6), 18, 0.850f, 1.543f},
        {"surface, beside the edges", scene.index(1, top, 1), 18, 0.850f, 1.111f},
        {"surface edge", scene.index(6, top, 0), 12, 0.720f, 2.331f},
        {"surface corner", scene.index(0, top, 0), 8, 0.607f, 1.349f},
        {"layer below the surface", scene.index(6, top - 1, 6), 27, 1.000f, 1.000f},  // eq. 8 alone: 0.850
        {"below a corner", scene.index(1, top - 1, 1), 27, 1.000f, 1.000f},           // eq. 8 alone: 0.608
        {"2x2x2 droplet", scene.droplet, 8, 0.607f, 0.607f},
        {"lone particle", scene.lone, 1, 1.0f / shader::RENDER_PI, 1.0f / shader::RENDER_PI},
    };
    for (const Expected& e : rows) {
        EXPECT_EQ(aniso.counts[e.index], e.count) << e.what;
        EXPECT_NEAR(iso.density[e.index], e.iso, 0.0015f) << e.what;
        EXPECT_NEAR(aniso.density[e.index], e.aniso, 0.0015f) << e.what;
    }
    for (size_t i = scene.clump; i < scene.clump + 3; ++i) {
        EXPECT_GT(iso.density[i], 0.48f);
        EXPECT_LT(iso.density[i], 0.52f);
        EXPECT_NEAR(aniso.density[i], iso.density[i], 1.0e-5f) << "a sparse clump keeps the isotropic sphere";
    }
    float top_min = 1.0e9f, iso_top_max = 0.0f;
    for (int z = 0; z < scene.nz; ++z)
        for (int x = 0; x < scene.nx; ++x) {
            top_min = std::min(top_min, aniso.density[scene.index(x, top, z)]);
            iso_top_max = std::max(iso_top_max, iso.density[scene.index(x, top, z)]);
        }
    EXPECT_NEAR(top_min, 1.111f, 0.0015f);
    EXPECT_NEAR(iso_top_max, 0.850f, 0.0015f);
}

TEST(AnisotropyClassification, OneParticleThickSheetIsAggregated) {
    // A thin sheet is fluid, not spray: the PCA sees a plane and the kernels flatten into it.
    std::vector<glm::vec3> sheet;
    for (int z = 0; z < 8; ++z)
        for (int x = 0; x < 8; ++x) sheet.push_back(glm::vec3(x, 0, z) * kSpacing);
    const Classification aniso = classify_cpu(sheet, true);
    const Classification iso = classify_cpu(sheet, false);
    const size_t middle = 3 + 8 * 3;
    EXPECT_EQ(aniso.aggregate[middle], 1u) << aniso.density[middle];
    EXPECT_EQ(iso.aggregate[middle], 0u) << iso.density[middle];
}

// ---- GPU passes against the CPU ---------------------------------------------------------------

class AnisotropyGpuTest : public testing::GpuTest {
protected:
    struct Result {
        std::vector<glm::vec4> shape;
        std::vector<glm::vec4> centres;
        std::vector<float> density;
        std::vector<uint32_t> aggregate;
    };

    /// Runs classify_shape + classify_density on `sorted` (positions already in `grid`'s order).
    Result run(gpu::BufferSet& buffers, const NeighborGrid& grid, const std::vector<glm::vec3>& sorted,
               bool anisotropic) {
        const uint32_t n = static_cast<uint32_t>(sorted.size());
        shader::SurfaceParams params{};
        const GridGeometry& g = grid.geometry();
        params.grid_origin_cell = glm::vec4(g.origin, g.cell_size);
        params.grid_dims = glm::uvec4(g.dims, g.cell_count());
        params.radius = kRadius;
        params.inv_radius = 1.0f / kRadius;
        params.kernel_coeff = shader::cubic_coefficient(kRadius);
        params.volume = kVolume;
        params.particle_count = n;
        params.flags = anisotropic ? SURFACE_ANISOTROPIC : 0u;
        params.aniso_kr = shader::kDefaultAnisoKr;
        params.aniso_ks = shader::kDefaultAnisoKs;
        params.aniso_kn = shader::kDefaultAnisoKn;
        params.aniso_neps = shader::kDefaultAnisoNeps;
        params.aggregate_density = shader::kDefaultAggregateDensity;
        params.centre_smoothing = shader::kDefaultCentreSmoothing;

        std::vector<glm::vec4> sorted4;
        for (const glm::vec3& p : sorted) sorted4.push_back(glm::vec4(p, 0.0f));
        gpu::Buffer& params_buffer = buffers.add("params", sizeof(params));
        gpu::Buffer& positions = buffers.add("sorted", n * sizeof(glm::vec4));
        gpu::Buffer& shape = buffers.add("shape", uint64_t(n) * 3 * sizeof(glm::vec4));
        gpu::Buffer& dummy_shape = buffers.add("dummy_shape", sizeof(glm::vec4));
        gpu::Buffer& centres = buffers.add("centres", n * sizeof(glm::vec4));
        gpu::Buffer& density = buffers.add("class_density", n * sizeof(float));
        gpu::Buffer& aggregate = buffers.add("aggregate", n * sizeof(uint32_t));
        gpu::upload(ctx(), params_buffer, &params, sizeof(params));
        gpu::upload(ctx(), positions, sorted4.data(), n * sizeof(glm::vec4));

        gpu::ComputePass shape_pass(ctx(), {"render/classify_shape.comp", 6, 0});
        gpu::ComputePass density_pass(ctx(), {"render/classify_density.comp", 7, 0});
        ctx().submit_and_wait([&](VkCommandBuffer cmd) {
            if (anisotropic)
                gpu::dispatch(ctx(), cmd, shape_pass, n,
                              {{"params", &params_buffer},
                               {"sorted", &positions},
                               {"cell_rank", &grid.cell_rank()},
                               {"cell_start", &grid.cell_start()},
                               {"shape", &shape},
                               {"centres", &centres}});
            gpu::dispatch(ctx(), cmd, density_pass, n,
                          {{"params", &params_buffer},
                           {"sorted", &positions},
                           {"cell_rank", &grid.cell_rank()},
                           {"cell_start", &grid.cell_start()},
                           {"shape", anisotropic ? &shape : &dummy_shape},
                           {"class_density", &density},
                           {"aggregate", &aggregate}});
        });
        Result r;
        if (anisotropic) r.shape = gpu::download_vector<glm::vec4>(ctx(), shape, uint64_t(n) * 3);
        if (anisotropic) r.centres = gpu::download_vector<glm::vec4>(ctx(), centres, n);
        r.density = gpu::download_vector<float>(ctx(), density, n);
        r.aggregate = gpu::download_vector<uint32_t>(ctx(), aggregate, n);
        return r;
    }
};

TEST_F(AnisotropyGpuTest, ShapesDensitiesAndClassesMatchTheCpu) {
    // A slab with splashes, and a jittered block whose neighbourhoods are irregular (every
    // eigen-configuration, not only the lattice's symmetric ones).
    SlabScene scene(12, 4, 12, glm::vec3(0.5f));
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> jitter(-0.2f, 0.2f);
    for (int z = 0; z < 6; ++z)
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 6; ++x) {
                const glm::vec3 offset(jitter(rng), jitter(rng), jitter(rng));
                scene.positions.push_back(glm::vec3(3.0f, 0.5f, 0.5f) + (glm::vec3(x, y, z) + offset) * kSpacing);
            }
    const std::vector<glm::vec3>& positions = scene.positions;
    const uint32_t n = static_cast<uint32_t>(positions.size());

    auto geometry = grid_for_domain(glm::vec3(0.0f), glm::vec3(4.0f, 3.0f, 3.0f), kRadius);
    ASSERT_TRUE(geometry.ok());
    gpu::BufferSet buffers(ctx());
    NeighborGrid grid(ctx(), buffers, geometry.value(), n);
    gpu::Buffer& unsorted = buffers.add("positions", n * sizeof(glm::vec4));
    std::vector<glm::vec4> positions4;
    for (const glm::vec3& p : positions) positions4.push_back(glm::vec4(p, 0.0f));
    gpu::upload(ctx(), unsorted, positions4.data(), n * sizeof(glm::vec4));
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { grid.build(cmd, unsorted, n, nullptr); });
    const std::vector<uint32_t> order = gpu::download_vector<uint32_t>(ctx(), grid.order(), n);
    std::vector<glm::vec3> sorted(n);
    for (uint32_t s = 0; s < n; ++s) sorted[s] = positions[order[s]];

    for (bool anisotropic : {true, false}) {
        SCOPED_TRACE(anisotropic ? "anisotropic" : "isotropic");
        const Classification cpu = classify_cpu(sorted, anisotropic);
        const Result gpu_result = run(buffers, grid, sorted, anisotropic);
        int mismatches = 0, aggregated = 0;
        for (uint32_t i = 0; i < n && mismatches < 10; ++i) {
            const glm::vec3& p = sorted[i];
            if (anisotropic) {
                const AnisotropicShape& s = cpu.shapes[i];
                const float g_scale = glm::length(s.g[0]) + glm::length(s.g[1]) + glm::length(s.g[2]);
                for (int row = 0; row < 3; ++row)
                    for (int col = 0; col < 3; ++col)
                        if (std::abs(gpu_result.shape[3 * i + row][col] - s.g[col][row]) > 1.0e-4f * g_scale) {
                            ++mismatches;
                            ADD_FAILURE()
                                << "G[" << row << "][" << col << "] of particle at (" << p.x << ", " << p.y << ", "
                                << p.z << "): GPU " << gpu_result.shape[3 * i + row][col] << ", CPU " << s.g[col][row];
                        }
                EXPECT_NEAR(gpu_result.shape[3 * i].w, s.det_g, 1.0e-4f * s.det_g);
                EXPECT_EQ(gpu_result.shape[3 * i + 1].w, float(cpu.counts[i]));
                EXPECT_NEAR(gpu_result.shape[3 * i + 2].w, s.axes.x * kRadius, 1.0e-5f) << "the largest semi-axis";
                // Yu & Turk eq. 6: the centre pulled lambda of the way to the weighted mean.
                glm::vec3 mean(0.0f);
                float weight = 0.0f;
                for (const glm::vec3& q : sorted) {
                    const float u = glm::length(q - p) / kRadius;
                    if (u < 1.0f) weight += 1.0f - u * u * u, mean += (1.0f - u * u * u) * q;
                }
                const glm::vec3 centre = cpu.counts[i] > shader::kDefaultAnisoNeps
                                             ? p + shader::kDefaultCentreSmoothing * (mean / weight - p)
                                             : p;
                EXPECT_LT(glm::length(glm::vec3(gpu_result.centres[i]) - centre), 1.0e-4f * kRadius)
                    << "centre of the particle at (" << p.x << ", " << p.y << ", " << p.z << ")";
            }
            const float expected = cpu.density[i];
            if (std::abs(gpu_result.density[i] - expected) > 1.0e-4f * std::max(expected, 0.1f)) {
                ++mismatches;
                ADD_FAILURE() << "density of particle at (" << p.x << ", " << p.y << ", " << p.z << "): GPU "
                              << gpu_result.density[i] << ", CPU " << expected;
            }
            // (A density within rounding of the threshold may go either way.)
            if (std::abs(expected - shader::kDefaultAggregateDensity) > 1.0e-3f) {
                EXPECT_EQ(gpu_result.aggregate[i], cpu.aggregate[i]) << "density " << expected;
            }
            aggregated += gpu_result.aggregate[i];
        }
        // Both classes occur, so the comparison means something.
        EXPECT_GT(aggregated, 100);
        EXPECT_LT(aggregated, int(n) - 5);
    }
}

}  // namespace
}  // namespace aquaform
