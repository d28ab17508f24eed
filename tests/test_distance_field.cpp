// Distance fields of meshes and boxes, and the density maps (Koschier & Bender 2017) integrated
// over them, against closed forms: the analytic box distance, the walls' half-space integral
// (shaders/shared/sim/pbf_physics.h) and the kernel's integral over a ball.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>

#include "core/error.h"
#include "geometry/boundary_map.h"
#include "geometry/distance_field.h"
#include "geometry/primitives.h"
#include "shaders/shared/core/sph_kernels.h"
#include "shaders/shared/sim/pbf_physics.h"

namespace {

using namespace aquaform;
using namespace aquaform::geometry;

std::vector<glm::vec3> box_soup(const Box& box) { return make_box(box).triangle_soup(); }

std::vector<glm::vec3> joined(std::vector<glm::vec3> a, const std::vector<glm::vec3>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

DistanceField built(const std::vector<glm::vec3>& soup, float cell, float margin) {
    Result<DistanceField> field = build_distance_field(soup, cell, margin);
    if (!field) throw std::runtime_error(field.error());
    return std::move(field).value();
}

// Every node of `field` against `exact` (clamped to the band as the field is); returns the largest gap.
template <typename Exact>
float largest_node_gap(const DistanceField& field, Exact&& exact) {
    float worst = 0.0f;
    for (size_t n = 0; n < field.distance.size(); ++n) {
        const float want = glm::clamp(exact(field.grid.position(field.grid.node_of(n))), -field.band, field.band);
        worst = std::max(worst, std::abs(field.distance[n] - want));
    }
    return worst;
}

TEST(DistanceField, ASolidOnTheWallsReachesThroughThem) {
    // A block standing on a tank's floor and against its left wall: with the tank as walls, its
    // floor and wall faces are no surface. Inside the tank the field is the distance to the
    // faces the fluid can reach (a particle caught near the floor is led out through the top or
    // the right face, not into the floor); beyond the walls, under the block, nodes are inside.
    const Box tank{glm::vec3(0.0f), glm::vec3(1.0f)};
    const Box block{glm::vec3(0.0f), glm::vec3(0.4f, 0.3f, 0.5f)};
    const GridSpec grid = GridSpec::covering(block, 0.02f, 0.1f);
    auto through = build_distance_field_on(box_soup(block), grid, 0.1f, {}, tank);
    auto closed = build_distance_field_on(box_soup(block), grid, 0.1f);
    ASSERT_TRUE(through.ok() && closed.ok());
    const glm::vec3 near_floor(0.3f, 0.01f, 0.25f);
    EXPECT_NEAR(closed.value().sample(near_floor), -0.01f, 1e-4f) << "the closed mesh's floor face";
    EXPECT_NEAR(through.value().sample(near_floor), -0.1f, 1e-4f) << "0.1 from the right face: the floor face is gone";
    const glm::vec3 near_left(0.01f, 0.15f, 0.25f);
    EXPECT_NEAR(through.value().sample(near_left), -0.1f, 1e-4f) << "beyond the band from every face left";
    EXPECT_NEAR(through.value().sample(glm::vec3(0.38f, 0.15f, 0.25f)), -0.02f, 1e-4f) << "the right face stays";
    EXPECT_LT(through.value().sample(glm::vec3(0.2f, -0.05f, 0.25f)), 0.0f) << "under the floor, under the block";
    EXPECT_GT(through.value().sample(glm::vec3(0.45f, -0.05f, 0.25f)), 0.0f) << "under the floor, beside the block";
    EXPECT_GT(closed.value().sample(glm::vec3(0.2f, -0.05f, 0.25f)), 0.0f);
}

TEST(DistanceField, CubeMeshMatchesTheAnalyticBoxDistance) {
    const Box cube{glm::vec3(0.0f), glm::vec3(1.0f)};
    const float cell = 0.045f, margin = 0.2f;  // nodes off the faces, so no node sits on the surface
    const DistanceField field = built(box_soup(cube), cell, margin);
    EXPECT_EQ(field.band, margin);
    EXPECT_LE(field.grid.origin.x, -margin);
    EXPECT_GE(field.grid.bounds().max.x, 1.0f + margin);
    // Exact (point-to-triangle) at the nodes, inside and outside alike.
    EXPECT_LT(largest_node_gap(field, [&](glm::vec3 p) { return box_signed_distance(cube, p); }), 1e-5f);
    // The analytic field on the same grid has the same nodes.
    const DistanceField analytic = box_distance_field(cube, cell, margin);
    ASSERT_EQ(analytic.grid.dims, field.grid.dims);
    for (size_t n = 0; n < field.distance.size(); ++n) ASSERT_NEAR(analytic.distance[n], field.distance[n], 1e-5f) << n;

    // Between nodes, trilinear interpolation: off by at most 3/8 of a cell where three inner creases
    // meet (7/8 against 1/2 at a cell's centre), exact where the distance is linear over a cell.
    std::mt19937 random(7);
    std::uniform_real_distribution<float> coordinate(-margin, 1.0f + margin), unit(0.0f, 1.0f);
    float worst = 0.0f;
    for (int i = 0; i < 4000; ++i) {
        const glm::vec3 p(coordinate(random), coordinate(random), coordinate(random));
        worst = std::max(worst, std::abs(field.sample(p) - glm::clamp(box_signed_distance(cube, p), -margin, margin)));
    }
    EXPECT_LE(worst, 0.375f * cell + 1e-5f);
    // Near a face's middle (|across - 0.5| < 0.25, within 0.15 of the face) every corner of the
    // point's cell is nearer that face than any other and inside the band: the field is that plane.
    float worst_flat = 0.0f;
    for (int i = 0; i < 3000; ++i) {
        const int axis = i % 3;
        const float side = (i / 3) % 2 ? 1.0f : 0.0f;
        glm::vec3 p(0.25f + 0.5f * unit(random), 0.25f + 0.5f * unit(random), 0.25f + 0.5f * unit(random));
        p[axis] = side + 0.3f * (unit(random) - 0.5f);
        worst_flat = std::max(worst_flat, std::abs(field.sample(p) - box_signed_distance(cube, p)));
        glm::vec3 normal(0.0f);
        normal[axis] = side > 0.5f ? 1.0f : -1.0f;
        ASSERT_LT(glm::length(field.gradient(p) - normal), 1e-3f) << p.x << " " << p.y << " " << p.z;
    }
    EXPECT_LT(worst_flat, 1e-5f);
}

TEST(DistanceField, SignHoldsAcrossASmallHole) {
    const float radius = 0.5f;
    Mesh sphere = make_sphere(radius, 3);  // 1280 faces
    // A hole: the face whose centre is nearest the +z pole (rays along z pass through it).
    size_t hole = 0;
    for (size_t f = 0; f < sphere.faces.size(); ++f) {
        const auto centre = [&](size_t i) {
            const glm::uvec3 v = sphere.faces[i];
            return (sphere.vertices[v.x] + sphere.vertices[v.y] + sphere.vertices[v.z]) / 3.0f;
        };
        if (centre(f).z > centre(hole).z) hole = f;
    }
    const glm::uvec3 removed = sphere.faces[hole];
    const glm::vec3 hole_centre =
        (sphere.vertices[removed.x] + sphere.vertices[removed.y] + sphere.vertices[removed.z]) / 3.0f;
    sphere.faces.erase(sphere.faces.begin() + long(hole));
    const float cell = 0.04f;
    const DistanceField field = built(sphere.triangle_soup(), cell, 0.12f);
    size_t inside = 0, checked = 0;
    for (size_t n = 0; n < field.distance.size(); ++n) {
        const glm::vec3 p = field.grid.position(field.grid.node_of(n));
        const float want = glm::length(p) - radius;
        if (std::abs(want) < 0.01f) continue;  // the facets lie up to 0.004 inside the sphere
        ++checked;
        inside += want < 0.0f;
        ASSERT_EQ(field.distance[n] < 0.0f, want < 0.0f) << p.x << " " << p.y << " " << p.z;
        // Magnitudes too, except next to the hole, where the nearest surface is the hole's rim.
        if (glm::length(p - hole_centre) > 0.15f) {
            ASSERT_NEAR(field.distance[n], glm::clamp(want, -field.band, field.band), 0.005f);
        }
    }
    EXPECT_GT(inside, 1000u);
    EXPECT_GT(checked, 10000u);
}

TEST(DistanceField, TwoPartsAndOverlappingPartsGiveTheUnionsDistance) {
    const float cell = 0.05f, margin = 0.25f;
    // Two separate cubes.
    const Box a{glm::vec3(0.0f), glm::vec3(1.0f)}, b{glm::vec3(1.5f, 0.0f, 0.0f), glm::vec3(2.5f, 1.0f, 1.0f)};
    const DistanceField apart = built(joined(box_soup(a), box_soup(b)), cell, margin);
    EXPECT_LT(largest_node_gap(
                  apart, [&](glm::vec3 p) { return std::min(box_signed_distance(a, p), box_signed_distance(b, p)); }),
              1e-5f);
    EXPECT_GT(apart.sample({1.25f, 0.5f, 0.5f}), 0.2f);  // the gap between them is outside
    // Two cubes that overlap into one box [0, 1.6] x [0, 1]^2: the faces hidden inside the other
    // part must not count as surface (the inner nodes near x = 1 and x = 0.6 are 0.3+ deep).
    const Box c{glm::vec3(0.6f, 0.0f, 0.0f), glm::vec3(1.6f, 1.0f, 1.0f)};
    const Box both{glm::vec3(0.0f), glm::vec3(1.6f, 1.0f, 1.0f)};
    const DistanceField overlapping = built(joined(box_soup(a), box_soup(c)), cell, margin);
    EXPECT_LT(largest_node_gap(overlapping, [&](glm::vec3 p) { return box_signed_distance(both, p); }), 1e-5f);
    EXPECT_NEAR(overlapping.sample({1.0f, 0.5f, 0.5f}), -0.25f, 1e-5f);  // clamped at the band, 0.5 deep
}

TEST(DistanceField, ThinPlateKeepsItsMiddleNegative) {
    const float cell = 0.02f, margin = 3.0f * cell;
    // Two cells thick: one layer of nodes inside, a cell from both faces.
    const Box plate{glm::vec3(0.0f), glm::vec3(1.0f, 1.0f, 2.0f * cell)};
    const DistanceField field = built(box_soup(plate), cell, margin);
    size_t middle = 0;
    for (size_t n = 0; n < field.distance.size(); ++n) {
        const glm::vec3 p = field.grid.position(field.grid.node_of(n));
        if (std::abs(p.z - cell) > 0.25f * cell || p.x < 0.5f * cell || p.x > 1.0f - 0.5f * cell || p.y < 0.5f * cell ||
            p.y > 1.0f - 0.5f * cell)
            continue;
        ++middle;
        ASSERT_NEAR(field.distance[n], -cell, 1e-5f) << p.x << " " << p.y;
    }
    EXPECT_GT(middle, 2000u);
    EXPECT_LT(field.sample({0.37f, 0.61f, cell}), -0.99f * cell);
    EXPECT_GT(field.sample({0.37f, 0.61f, 3.0f * cell}), 0.99f * cell);
}

TEST(DistanceField, RefusesEmptyOrNonFiniteSoupsAndBadCells) {
    const Result<DistanceField> empty = build_distance_field({}, 0.1f, 0.1f);
    ASSERT_FALSE(empty);
    EXPECT_NE(empty.error().find("no triangles"), std::string::npos) << empty.error();
    std::vector<glm::vec3> soup = box_soup({glm::vec3(0.0f), glm::vec3(1.0f)});
    soup[4].y = std::nanf("");
    const Result<DistanceField> nan = build_distance_field(soup, 0.1f, 0.1f);
    ASSERT_FALSE(nan);
    EXPECT_NE(nan.error().find("triangle 1 "), std::string::npos) << nan.error();
    EXPECT_NE(nan.error().find("finite"), std::string::npos) << nan.error();
    soup[4].y = INFINITY;
    EXPECT_FALSE(build_distance_field(soup, 0.1f, 0.1f));
    soup[4].y = 1.0f;
    soup.pop_back();
    const Result<DistanceField> partial = build_distance_field(soup, 0.1f, 0.1f);
    ASSERT_FALSE(partial);
    EXPECT_NE(partial.error().find("whole triangles"), std::string::npos) << partial.error();
    soup = box_soup({glm::vec3(0.0f), glm::vec3(1.0f)});
    EXPECT_FALSE(build_distance_field(soup, 0.0f, 0.1f));
    EXPECT_FALSE(build_distance_field(soup, NAN, 0.1f));
    EXPECT_FALSE(build_distance_field(soup, 0.1f, -1.0f));
    EXPECT_FALSE(build_distance_field(soup, 0.1f, 0.0f));  // no band to hold a distance
    EXPECT_TRUE(build_distance_field(soup, 0.1f, 0.0f, {}, 0.1f));
}

TEST(DistanceField, RefusesAGridOverTheNodeBudget) {
    const Box big{glm::vec3(0.0f), glm::vec3(10.0f)};
    const Result<DistanceField> field = build_distance_field(box_soup(big), 0.01f, 0.04f);  // ~1e9 nodes
    ASSERT_FALSE(field);
    EXPECT_NE(field.error().find("0.01 m"), std::string::npos) << field.error();
    EXPECT_NE(field.error().find("particle_spacing"), std::string::npos) << field.error();
    EXPECT_THROW(box_distance_field(big, 0.01f, 0.04f), Failure);
    // Just under the budget is built (a box of 400^3 nodes would be; a small one shows the count).
    EXPECT_LT(GridSpec::count_covering(big, 0.04f, 0.04f), double(kMaxDistanceFieldNodes));
}

// ---- density maps ----

constexpr float kH = 0.04f;
constexpr float kPhi = 1.3f;  // not 1, so that a map that forgets phi fails

BoundaryKernel kernel() { return {kH, shader::poly6_coefficient(kH), kPhi}; }

/// The walls' closed form: m at signed distance d from a half-space (d < 0: inside it), and the
/// derivative of m along the outward normal.
double half_space_m(double d) {
    if (d >= kH) return 0.0;
    d = std::max(d, -double(kH));
    const float h2 = kH * kH;
    const double scale = std::numbers::pi * shader::poly6_coefficient(kH) / 4.0;
    return kPhi * scale * (shader::pbf_wall_antiderivative(kH, h2) - shader::pbf_wall_antiderivative(float(d), h2));
}
double half_space_slope(double d) {
    if (std::abs(d) >= kH) return 0.0;
    const double u = double(kH) * kH - d * d;
    return -kPhi * std::numbers::pi * shader::poly6_coefficient(kH) / 4.0 * u * u * u * u;
}
double largest_slope() { return std::abs(half_space_slope(0.0)); }

TEST(BoundaryMap, CubeFractionIsTheVolumeBelowThePlane) {
    std::mt19937 random(3);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> offset(-0.9, 0.9);
    constexpr int kSamples = 96;
    for (int trial = 0; trial < 40; ++trial) {
        glm::dvec3 n(gauss(random), gauss(random), gauss(random));
        if (trial < 3) n = glm::dvec3(0.0), n[trial] = 1.0;  // axis-aligned: the division's floor
        n = glm::normalize(n);
        const double d = offset(random), side = 2.0;
        size_t below = 0;
        for (int k = 0; k < kSamples; ++k)
            for (int j = 0; j < kSamples; ++j)
                for (int i = 0; i < kSamples; ++i) {
                    const glm::dvec3 u = (glm::dvec3(i, j, k) + 0.5) / double(kSamples) - 0.5;
                    below += d + glm::dot(n, u * side) < 0.0;
                }
        const double counted = double(below) / (kSamples * kSamples * kSamples);
        EXPECT_NEAR(cube_fraction_below_plane(d, n, side), counted, 0.004) << trial;
    }
    EXPECT_EQ(cube_fraction_below_plane(2.0, glm::dvec3(0, 0, 1), 2.0), 0.0);
    EXPECT_EQ(cube_fraction_below_plane(-2.0, glm::dvec3(0, 0, 1), 2.0), 1.0);
}

// A map's nodes (and samples between them) that see only the face y = top of a large box, against
// the half-space closed form; returns the largest errors (m at nodes, grad at nodes, m sampled).
struct Errors {
    double m = 0.0, gradient = 0.0, sampled = 0.0;
    size_t nodes = 0;
};
Errors half_space_errors(float top) {
    const float cell = kH / 4.0f, half = 3.0f * kH;
    const Box box{glm::vec3(-half, -half, -half), glm::vec3(half, top, half)};
    const BoundaryMap map = build_boundary_map(box_distance_field(box, cell, kH + cell), kernel());
    Errors e;
    const auto sees_one_face = [&](glm::vec3 p) {
        return std::abs(p.x) <= half - kH - cell && std::abs(p.z) <= half - kH - cell && p.y >= -half + kH + cell;
    };
    for (size_t n = 0; n < map.density.size(); ++n) {
        const glm::vec3 p = map.grid.position(map.grid.node_of(n));
        if (!sees_one_face(p)) continue;
        const double d = double(p.y) - top;
        const glm::vec4 got = map.density[n];
        e.m = std::max(e.m, std::abs(got.w - half_space_m(d)));
        e.gradient = std::max(e.gradient, glm::length(glm::dvec3(got) - glm::dvec3(0.0, half_space_slope(d), 0.0)));
        ++e.nodes;
    }
    std::mt19937 random(11);
    std::uniform_real_distribution<float> across(-half + kH + cell, half - kH - cell),
        along(top - 1.2f * kH, top + 1.2f * kH);
    for (int i = 0; i < 3000; ++i) {
        const glm::vec3 p(across(random), along(random), across(random));
        e.sampled = std::max(e.sampled, std::abs(map.sample_density(p).w - half_space_m(double(p.y) - top)));
    }
    return e;
}

TEST(BoundaryMap, HalfSpaceMatchesTheWallsClosedForm) {
    // Faces at four offsets from the nodes, none on the octant planes of the sub-grid (which would
    // integrate exactly): node distances every h/16 over [-h, h].
    Errors worst;
    for (const float offset : {0.1f, 0.35f, 0.6f, 0.85f}) {
        const Errors e = half_space_errors(offset * kH / 4.0f);
        EXPECT_GT(e.nodes, 500u);
        worst.m = std::max(worst.m, e.m), worst.gradient = std::max(worst.gradient, e.gradient);
        worst.sampled = std::max(worst.sampled, e.sampled);
    }
    std::cout << "[ half-space, cell h/4: node m error " << worst.m / kPhi << " phi, grad error "
              << worst.gradient / largest_slope() << " of max |grad|, m sampled between nodes " << worst.sampled / kPhi
              << " phi ]\n";
    EXPECT_LT(worst.m, 0.01 * kPhi);
    EXPECT_LT(worst.gradient, 0.02 * largest_slope());
    // Between nodes the trilinear interpolation of m (degree 9 in d) errs by up to cell^2 / 8 max|m''|,
    // 1.8 % of phi at cell = h / 4.
    EXPECT_LT(worst.sampled, 0.025 * kPhi);
}

TEST(BoundaryMap, TiltedHalfSpaceMatchesTheClosedForm) {
    // A large box mesh turned off the axes: its top face is a plane no sub-grid cube is aligned with.
    const float half = 3.0f * kH, cell = kH / 4.0f;
    const glm::mat3 turn =
        glm::mat3(glm::vec3(0.8660254f, 0.5f, 0.0f), glm::vec3(-0.5f, 0.8660254f, 0.0f), glm::vec3(0, 0, 1)) *
        glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0.0f, 0.9396926f, 0.3420201f),
                  glm::vec3(0.0f, -0.3420201f, 0.9396926f));
    std::vector<glm::vec3> soup = box_soup({glm::vec3(-half), glm::vec3(half)});
    for (glm::vec3& p : soup) p = turn * p;
    const BoundaryMap map = build_boundary_map(built(soup, cell, kH + cell), kernel());
    const glm::vec3 normal = turn * glm::vec3(0, 1, 0);
    double worst_m = 0.0, worst_gradient = 0.0;
    size_t nodes = 0;
    for (size_t n = 0; n < map.density.size(); ++n) {
        const glm::vec3 p = map.grid.position(map.grid.node_of(n));
        const glm::vec3 local = glm::transpose(turn) * p;  // in the box's own frame
        if (std::abs(local.x) > half - kH - cell || std::abs(local.z) > half - kH - cell || local.y < -half + kH + cell)
            continue;
        const double d = double(local.y) - half;
        if (d > kH + cell) continue;
        ++nodes;
        worst_m = std::max(worst_m, std::abs(map.density[n].w - half_space_m(d)));
        worst_gradient = std::max(worst_gradient,
                                  glm::length(glm::dvec3(map.density[n]) - half_space_slope(d) * glm::dvec3(normal)));
        if (std::abs(d) < kH - cell) {
            EXPECT_LT(glm::length(glm::vec3(map.distance[n]) - normal), 1e-3f);
        }
    }
    std::cout << "[ tilted half-space, cell h/4: node m error " << worst_m / kPhi << " phi, grad error "
              << worst_gradient / largest_slope() << " of max |grad| over " << nodes << " nodes ]\n";
    EXPECT_GT(nodes, 1000u);
    EXPECT_LT(worst_m, 0.01 * kPhi);
    EXPECT_LT(worst_gradient, 0.02 * largest_slope());
}

TEST(BoundaryMap, DeepInsideIsPhiAndFarOutsideIsZero) {
    const float cell = kH / 4.0f;
    const Box box{glm::vec3(0.0f), glm::vec3(4.0f * kH)};
    const BoundaryMap map = build_boundary_map(box_distance_field(box, cell, 2.0f * kH), kernel());
    EXPECT_NEAR(kernel_volume_integral(kernel()), 1.0, 1e-5);
    size_t deep = 0, far = 0;
    for (size_t n = 0; n < map.density.size(); ++n) {
        const glm::vec3 p = map.grid.position(map.grid.node_of(n));
        const float d = box_signed_distance(box, p);
        EXPECT_NEAR(map.distance[n].w, glm::clamp(d, -2.0f * kH, 2.0f * kH), 1e-5f);
        if (d <= -kH) {
            ++deep;
            ASSERT_EQ(map.density[n], glm::vec4(0.0f, 0.0f, 0.0f, float(kPhi * kernel_volume_integral(kernel()))));
        }
        if (d >= kH) {
            ++far;
            ASSERT_EQ(map.density[n], glm::vec4(0.0f));
        }
        // Just inside the shortcut's reach the quadrature agrees with it (and with the closed form).
        if (d > -kH && d < -kH + 1.01f * cell && std::abs(p.x - 2.0f * kH) < 0.5f * cell &&
            std::abs(p.z - 2.0f * kH) < 0.5f * cell) {
            EXPECT_NEAR(map.density[n].w, half_space_m(d), 1e-3 * kPhi);
        }
    }
    EXPECT_GT(deep, 0u);
    EXPECT_GT(far, 1000u);
    // Out of the grid, the sampler clamps to its faces, where m is 0.
    EXPECT_EQ(map.sample_density(glm::vec3(-1.0f)), glm::vec4(0.0f));
    // A field whose grid stops short of h beyond the solid, or whose band is narrower than h, is refused.
    const auto refusal = [](const DistanceField& field) {
        try {
            build_boundary_map(field, kernel());
        } catch (const Failure& failure) {
            return std::string(failure.what());
        }
        return std::string("(built)");
    };
    DistanceField short_grid = box_distance_field(box, cell, 0.5f * kH);
    short_grid.band = kH;
    EXPECT_NE(refusal(short_grid).find("grid ends"), std::string::npos) << refusal(short_grid);
    DistanceField narrow = box_distance_field(box, cell, 2.0f * kH);
    narrow.band = 0.5f * kH;
    EXPECT_NE(refusal(narrow).find("band"), std::string::npos) << refusal(narrow);
}

/// m next to the edge of a quarter-space {x < 0, y < 0}, at x = a, y = b: the kernel integrated
/// along the edge is c (32/35) (h^2 - rho^2)^(7/2) in the cross-section, integrated here over the
/// quadrant with Simpson's rule in both directions.
double quarter_space_m(double a, double b) {
    const double c = shader::poly6_coefficient(kH), h2 = double(kH) * kH;
    constexpr int kSteps = 200;
    const auto simpson = [](double from, double to, auto&& f) {
        if (to <= from) return 0.0;
        double sum = 0.0;
        for (int i = 0; i <= kSteps; ++i)
            sum += (i == 0 || i == kSteps ? 1.0 : i % 2 ? 4.0 : 2.0) * f(from + (to - from) * i / kSteps);
        return sum * (to - from) / (3.0 * kSteps);
    };
    return kPhi * simpson(-double(kH), std::min(-a, double(kH)), [&](double u) {
               const double reach = std::sqrt(std::max(h2 - u * u, 0.0));
               return simpson(-reach, std::min(-b, reach), [&](double v) {
                   const double q = std::max(h2 - u * u - v * v, 0.0);
                   return c * 32.0 / 35.0 * q * q * q * std::sqrt(q);
               });
           });
}

// A box's edge x = y = top, with its faces on the nodes, at cell h/4 and h/8. The field's trilinear
// interpolation rounds the inner crease that runs from the edge (max(a, b) between nodes), so the
// map integrates an edge rounded over about a cell: its error shrinks with the cell.
double edge_errors(float cell, double tolerance) {
    const float top = 2.0f * kH;
    const Box box{glm::vec3(-top), glm::vec3(top)};
    const BoundaryMap map = build_boundary_map(box_distance_field(box, cell, kH + cell), kernel());
    size_t near_edge = 0, on_edge = 0, beside = 0;
    double worst = 0.0;
    for (size_t n = 0; n < map.density.size(); ++n) {
        const glm::vec3 p = map.grid.position(map.grid.node_of(n));
        if (std::abs(p.z) > top - kH - cell) continue;  // away from the box's corners
        const float a = p.x - top, b = p.y - top;       // outside the x face by a, the y face by b
        if (std::abs(a) > kH + cell || std::abs(b) > kH + cell) continue;
        ++near_edge;
        const float m = map.density[n].w;
        worst = std::max(worst, std::abs(m - quarter_space_m(a, b)));
        if (std::abs(a) < 1e-4f && std::abs(b) < 1e-4f) {
            ++on_edge;  // a quarter of the ball is solid; a half-space holds 0.5 phi there
            EXPECT_NEAR(m, 0.25 * kPhi, tolerance * kPhi);
        } else if (std::abs(b) < 1e-4f && a > 0.0f && a < kH) {
            ++beside;  // on the y face's plane, beyond the x face: half of what the x face alone gives
            EXPECT_NEAR(m, 0.5 * half_space_m(a), tolerance * kPhi) << a;
        }
    }
    std::cout << "[ convex edge, cell h/" << kH / cell << ": node m error " << worst / kPhi << " phi over " << near_edge
              << " nodes ]\n";
    EXPECT_GE(on_edge, 5u);
    EXPECT_GE(beside, 15u);
    return worst;
}

TEST(BoundaryMap, ConvexEdgeHoldsLessThanTheHalfSpace) {
    EXPECT_NEAR(quarter_space_m(0.0, -1.0), half_space_m(0.0), 1e-4);  // the reference itself
    EXPECT_LT(edge_errors(kH / 4.0f, 0.02), 0.02 * kPhi);
    EXPECT_LT(edge_errors(kH / 8.0f, 0.01), 0.01 * kPhi);
}

TEST(BoundaryMap, ClipKeepsOnlyTheSolidInsideTheTank) {
    // An obstacle half below the tank's floor (y = 0): below it the floor's own closed form counts.
    const float cell = kH / 4.0f, half = 3.0f * kH;
    const Box box{glm::vec3(-half), glm::vec3(half)};
    const Box tank{glm::vec3(-1.0f, 0.0f, -1.0f), glm::vec3(1.0f)};
    const DistanceField field = box_distance_field(box, cell, kH + cell);
    const BoundaryMap clipped = build_boundary_map(field, kernel(), tank);
    const BoundaryMap whole = build_boundary_map(field, kernel());
    size_t checked = 0;
    for (size_t n = 0; n < clipped.density.size(); ++n) {
        const glm::vec3 p = clipped.grid.position(clipped.grid.node_of(n));
        if (std::abs(p.x) > half - kH - cell || std::abs(p.z) > half - kH - cell || std::abs(p.y) > half - kH - cell)
            continue;
        ++checked;
        // Deep in the box the solid in the tank is the half-space y > 0: its closed form at d = -y.
        EXPECT_NEAR(clipped.density[n].w, half_space_m(-p.y), 0.01 * kPhi) << p.y;
        EXPECT_NEAR(clipped.density[n].y, -half_space_slope(-p.y), 0.02 * largest_slope()) << p.y;
        EXPECT_NEAR(whole.density[n].w, kPhi, 1e-4 * kPhi);
        if (std::abs(p.y) < 1e-4f) {
            EXPECT_NEAR(clipped.density[n].w, 0.5 * kPhi, 0.005 * kPhi);  // half the deep value
        }
        if (p.y <= -kH) {
            EXPECT_NEAR(clipped.density[n].w, 0.0f, 1e-6f);
        }
    }
    EXPECT_GT(checked, 1000u);
}

/// m at distance s from the centre of a solid ball of radius R: the kernel over the spherical
/// shells about x, each weighted by its area inside the ball (a cap: pi r (R^2 - (s - r)^2) / s).
double ball_m(double s, double radius) {
    const double c = shader::poly6_coefficient(kH), h2 = double(kH) * kH;
    constexpr int kSteps = 4000;  // Simpson's rule over r in [0, h]
    double sum = 0.0;
    for (int i = 0; i <= kSteps; ++i) {
        const double r = kH * double(i) / kSteps;
        double area = 0.0;
        if (r <= radius - s)
            area = 4.0 * std::numbers::pi * r * r;
        else if (r >= std::abs(s - radius) && s > 0.0)
            area = std::numbers::pi * r * (radius * radius - (s - r) * (s - r)) / s;
        const double q = h2 - r * r;
        sum += (i == 0 || i == kSteps ? 1.0 : i % 2 ? 4.0 : 2.0) * c * q * q * q * area;
    }
    return kPhi * sum * kH / (3.0 * kSteps);
}

TEST(BoundaryMap, SphereMeshMatchesTheBallIntegralAndReportsItsBuildTime) {
    // A 0.5 m sphere (20480 faces), h = 0.04, cell = h / 4: the build cost of a typical obstacle.
    const float radius = 0.25f, cell = kH / 4.0f;
    const std::vector<glm::vec3> soup = make_sphere(radius, 5).triangle_soup();
    const auto start = std::chrono::steady_clock::now();
    const DistanceField field = built(soup, cell, kH + cell);
    const auto middle = std::chrono::steady_clock::now();
    const BoundaryMap map = build_boundary_map(field, kernel(), {}, "boundary map");
    const auto end = std::chrono::steady_clock::now();
    const double field_s = std::chrono::duration<double>(middle - start).count();
    const double map_s = std::chrono::duration<double>(end - middle).count();
    ASSERT_TRUE(map.complete);
    double worst_m = 0.0, worst_gradient = 0.0;
    size_t band = 0;
    for (size_t n = 0; n < map.density.size(); ++n) {
        const glm::vec3 p = map.grid.position(map.grid.node_of(n));
        const double s = glm::length(glm::dvec3(p));
        if (std::abs(s - radius) > kH) continue;
        ++band;
        worst_m = std::max(worst_m, std::abs(map.density[n].w - ball_m(s, radius)));
        const double step = 1e-4;
        const double slope = (ball_m(s + step, radius) - ball_m(s - step, radius)) / (2.0 * step);
        worst_gradient = std::max(worst_gradient, glm::length(glm::dvec3(map.density[n]) - slope * glm::dvec3(p) / s));
    }
    std::cout << "[ sphere R = " << radius << " m (20480 faces), h = " << kH
              << ", cell = h/4: " << map.grid.node_count() << " nodes, " << band << " in the band; distance field "
              << field_s << " s, boundary map " << map_s << " s; node m error " << worst_m / kPhi << " phi, grad error "
              << worst_gradient / largest_slope() << " of max |grad| ]\n";
    ::testing::Test::RecordProperty("distance_field_seconds", std::to_string(field_s));
    ::testing::Test::RecordProperty("boundary_map_seconds", std::to_string(map_s));
    EXPECT_GT(band, 10000u);
    EXPECT_LT(worst_m, 0.01 * kPhi);
    EXPECT_LT(worst_gradient, 0.03 * largest_slope());
}

}  // namespace
