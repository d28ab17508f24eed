#include "geometry/boundary_map.h"

#include <array>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/format_text.h"
#include "geometry/parallel_work.h"

namespace aquaform::geometry {

namespace {

/// One cube of the sub-grid over the kernel's ball, at integer offset `offset` (in cubes) from
/// the node's corner of the cube grid: its kernel integral and its share of grad m, whole and
/// for each of its eight half-size octants (octant x + 2 y + 4 z, 0: the low half on that axis).
struct BallCube {
    glm::ivec3 offset;
    double weight = 0.0;       // Integral_cube W(|u|) du
    glm::dvec3 gradient{0.0};  // Integral_cube 6 c (h^2 - |u|^2)^2 u du
    std::array<double, 8> octant_weight{};
    std::array<glm::dvec3, 8> octant_gradient{};
};

// 4-point Gauss-Legendre on [-1, 1]: exact for polynomials up to degree 7 per axis, so for poly6
// (degree 6) and its gradient (degree 5) over any cube that lies inside the ball.
constexpr std::array<double, 4> kGaussPoint{-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                            0.8611363115940526};
constexpr std::array<double, 4> kGaussWeight{0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                             0.3478548451374538};

/// Adds the Gauss-Legendre integrals of W and of its gradient term over the box [low, low + size].
void integrate_box(const glm::dvec3& low, double size, double h2, double c, double& weight, glm::dvec3& gradient) {
    const double half = 0.5 * size, jacobian = half * half * half;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int k = 0; k < 4; ++k) {
                const glm::dvec3 u = low + half * (glm::dvec3(kGaussPoint[i], kGaussPoint[j], kGaussPoint[k]) + 1.0);
                const double q = std::max(h2 - glm::dot(u, u), 0.0);
                const double w = kGaussWeight[i] * kGaussWeight[j] * kGaussWeight[k] * jacobian;
                weight += w * c * q * q * q;
                gradient += w * 6.0 * c * q * q * u;
            }
}

double squared_distance_to_box(const glm::dvec3& low, const glm::dvec3& high) {
    const glm::dvec3 nearest = glm::clamp(glm::dvec3(0.0), low, high);
    return glm::dot(nearest, nearest);
}

/// The ball's cubes of side `cube` (node at a cube corner), integrated octant by octant. Octants
/// that the sphere r = h cuts are integrated on a finer sub-grid (the kernel is only C2 across
/// it); the weights are then scaled so that they sum to the exact volume integral, so that the
/// quadrature and the deep-inside shortcut agree.
std::vector<BallCube> ball_cubes(const BoundaryKernel& kernel, double cube, int reach) {
    const double h = kernel.h, h2 = h * h, c = kernel.poly6_coeff, octant = 0.5 * cube;
    constexpr int kSplit = 4;
    std::vector<BallCube> cubes;
    double total = 0.0;
    for (int z = -reach; z < reach; ++z)
        for (int y = -reach; y < reach; ++y)
            for (int x = -reach; x < reach; ++x) {
                const glm::dvec3 low = glm::dvec3(x, y, z) * cube;
                if (squared_distance_to_box(low, low + cube) >= h2) continue;
                BallCube entry{{x, y, z}};
                for (int o = 0; o < 8; ++o) {
                    const glm::dvec3 corner = low + octant * glm::dvec3(o & 1, (o >> 1) & 1, (o >> 2) & 1);
                    const glm::dvec3 far = glm::max(glm::abs(corner), glm::abs(corner + octant));
                    double& weight = entry.octant_weight[o];
                    glm::dvec3& gradient = entry.octant_gradient[o];
                    if (glm::dot(far, far) <= h2) {
                        integrate_box(corner, octant, h2, c, weight, gradient);
                        continue;
                    }
                    const double part = octant / kSplit;
                    for (int k = 0; k < kSplit; ++k)
                        for (int j = 0; j < kSplit; ++j)
                            for (int i = 0; i < kSplit; ++i) {
                                const glm::dvec3 sub = corner + part * glm::dvec3(i, j, k);
                                if (squared_distance_to_box(sub, sub + part) < h2)
                                    integrate_box(sub, part, h2, c, weight, gradient);
                            }
                }
                for (int o = 0; o < 8; ++o)
                    entry.weight += entry.octant_weight[o], entry.gradient += entry.octant_gradient[o];
                total += entry.weight;
                cubes.push_back(entry);
            }
    const double scale = kernel_volume_integral(kernel) / total;
    for (BallCube& entry : cubes) {
        entry.weight *= scale;
        for (double& weight : entry.octant_weight) weight *= scale;
    }
    return cubes;
}

/// Overlap of [low, low + size] with [from, to], as a fraction of size.
double overlap(double low, double size, double from, double to) {
    return std::clamp((std::min(low + size, to) - std::max(low, from)) / size, 0.0, 1.0);
}

}  // namespace

double kernel_volume_integral(const BoundaryKernel& kernel) {
    const double h = kernel.h, h3 = h * h * h;
    return double(kernel.poly6_coeff) * 64.0 * std::numbers::pi * h3 * h3 * h3 / 315.0;
}

double cube_fraction_below_plane(double distance, glm::dvec3 normal, double side) {
    // The region sum m_i u_i < alpha of the unit cube, the normal's axes mirrored to m_i >= 0
    // (a tiny floor on m_i keeps the division below defined; it tilts the plane by 1e-6 rad).
    const glm::dvec3 m = glm::max(glm::abs(normal), glm::dvec3(1e-6));
    const double sum = m.x + m.y + m.z;
    const double alpha = 0.5 * sum - distance / side;
    if (alpha <= 0.0) return 0.0;
    if (alpha >= sum) return 1.0;
    const auto cube = [](double v) { return v > 0.0 ? v * v * v : 0.0; };
    // Inclusion-exclusion over the corner simplex sum m_i u_i < alpha, u >= 0, less the parts
    // beyond u_i = 1 (Scardovelli & Zaleski 2000, J. Comput. Phys. 164, "Analytical relations
    // connecting linear interfaces and volume fractions in rectangular grids").
    const double volume = cube(alpha) - cube(alpha - m.x) - cube(alpha - m.y) - cube(alpha - m.z) +
                          cube(alpha - m.x - m.y) + cube(alpha - m.y - m.z) + cube(alpha - m.z - m.x);
    return std::clamp(volume / (6.0 * m.x * m.y * m.z), 0.0, 1.0);
}

BoundaryMap build_boundary_map(const DistanceField& sdf, const BoundaryKernel& kernel, std::optional<Box> clip,
                               const std::string& progress_label) {
    const GridSpec& grid = sdf.grid;
    const float h = kernel.h;
    if (!(h > 0.0f) || !(kernel.poly6_coeff > 0.0f))
        throw Failure(format_text("boundary map: the kernel radius %g and poly6 coefficient %g must be > 0", double(h),
                                  double(kernel.poly6_coeff)));
    if (glm::any(glm::lessThan(grid.dims, glm::uvec3(2u))) || sdf.distance.size() != grid.node_count())
        throw Failure(
            "boundary map: the distance field has no grid (fewer than 2 nodes on an axis, or values missing)");
    if (sdf.band < h)
        throw Failure(
            format_text("boundary map: the distance field's band (%g m) is narrower than the kernel radius h "
                        "(%g m); build it with a margin (or band) of at least h",
                        double(sdf.band), double(h)));

    const auto ball_in_clip = [&](const glm::vec3& p) {
        return !clip ||
               (glm::all(glm::greaterThanEqual(p - h, clip->min)) && glm::all(glm::lessThanEqual(p + h, clip->max)));
    };
    const auto ball_meets_clip = [&](const glm::vec3& p) {
        if (!clip) return true;
        const glm::vec3 nearest = glm::clamp(p, clip->min, clip->max);
        return glm::dot(p - nearest, p - nearest) < h * h;
    };
    // A node on the grid's faces with solid within h: the map would stop short of where m is > 0.
    for (size_t n = 0; n < grid.node_count(); ++n) {
        const glm::uvec3 node = grid.node_of(n);
        const bool face = glm::any(glm::equal(node, glm::uvec3(0u))) || glm::any(glm::equal(node, grid.dims - 1u));
        if (face && sdf.distance[n] < h && ball_meets_clip(grid.position(node)))
            throw Failure(
                format_text("boundary map: the distance field's grid ends %g m from the solid, within the "
                            "kernel radius h = %g m; build it with a margin of at least h",
                            double(std::max(sdf.distance[n], 0.0f)), double(h)));
    }

    BoundaryMap map;
    map.grid = grid;
    map.distance.resize(grid.node_count());
    map.density.assign(grid.node_count(), glm::vec4(0.0f));
    const double deep = double(kernel.phi) * kernel_volume_integral(kernel);

    // Normals by central differences of the node values (one-sided on the grid's faces).
    for (size_t n = 0; n < grid.node_count(); ++n) {
        const glm::uvec3 node = grid.node_of(n);
        glm::vec3 slope(0.0f);
        for (int a = 0; a < 3; ++a) {
            glm::uvec3 lo = node, hi = node;
            if (lo[a] > 0) --lo[a];
            if (hi[a] + 1 < grid.dims[a]) ++hi[a];
            slope[a] =
                (sdf.distance[grid.index(hi)] - sdf.distance[grid.index(lo)]) / (float(hi[a] - lo[a]) * grid.cell);
        }
        const float length = glm::length(slope);
        map.distance[n] = glm::vec4(length > 1e-6f ? slope / length : glm::vec3(0.0f), sdf.distance[n]);
    }

    // The sub-grid: cubes of side cell / split, at most h / 8, so that a curved surface is
    // resolved finer than the field's cells; node i sits on cube corner split * i.
    const int split = std::max(1, int(std::ceil(8.0 * double(grid.cell) / double(h) - 1e-6)));
    const double cube = double(grid.cell) / split;
    const int reach = int(std::ceil(double(h) / cube - 1e-9));
    // The table as the node loop reads it: compact, in float (a node sums about 2000 entries).
    std::vector<glm::ivec3> cube_offsets;
    std::vector<glm::vec4> cube_whole;  // xyz: gradient integral, w: weight
    std::vector<std::array<glm::vec4, 8>> cube_octants;
    for (const BallCube& entry : ball_cubes(kernel, cube, reach)) {
        cube_offsets.push_back(entry.offset);
        cube_whole.emplace_back(glm::vec3(entry.gradient), float(entry.weight));
        std::array<glm::vec4, 8>& octants = cube_octants.emplace_back();
        for (int o = 0; o < 8; ++o)
            octants[o] = glm::vec4(glm::vec3(entry.octant_gradient[o]), float(entry.octant_weight[o]));
    }
    const double half_diagonal = 0.5 * std::sqrt(3.0) * cube;

    // The solid fraction of each octant of one cube of the global sub-grid (cube f spans
    // origin + [f, f + 1] cube), under the plane the field gives at the cube's centre: the octants
    // let the kernel vary across a cube that the surface cuts (one fraction per cube would
    // weigh its solid part as if the kernel were flat there: 0.4 % of phi off for a plane
    // halfway through the cubes at cube = h / 8). Returns the cube's fraction.
    const auto octant_fractions = [&](const glm::ivec3& f, std::array<float, 8>& octants) {
        const glm::dvec3 low = glm::dvec3(grid.origin) + glm::dvec3(f) * cube;
        const glm::dvec3 centre = low + 0.5 * cube;
        const double d = sdf.sample(glm::vec3(centre));
        glm::dvec3 normal(0.0);
        if (std::abs(d) < half_diagonal) {
            const glm::vec3 slope = sdf.gradient(glm::vec3(centre));
            // A flat spot of the field (a plate's middle) keeps normal 0: a face-aligned estimate.
            if (glm::length(slope) > 1e-3f) normal = glm::normalize(glm::dvec3(slope));
        }
        double sum = 0.0;
        for (int o = 0; o < 8; ++o) {
            const glm::dvec3 step(o & 1, (o >> 1) & 1, (o >> 2) & 1);
            double fraction = 1.0;
            if (clip)
                for (int a = 0; a < 3; ++a)
                    fraction *= overlap(low[a] + 0.5 * cube * step[a], 0.5 * cube, clip->min[a], clip->max[a]);
            if (d >= half_diagonal)
                fraction = 0.0;
            else if (d > -half_diagonal && fraction > 0.0) {
                const double offset = d + glm::dot(normal, (step - 0.5) * (0.5 * cube));
                fraction *= normal == glm::dvec3(0.0) ? std::clamp(0.5 - d / cube, 0.0, 1.0)
                                                      : cube_fraction_below_plane(offset, normal, 0.5 * cube);
            }
            octants[o] = float(fraction);
            sum += fraction;
        }
        return sum / 8.0;
    };

    // Tiles of nodes, each with the fractions of the cubes its nodes' balls cover computed once.
    constexpr uint32_t kTile = 16;
    const glm::uvec3 tiles = (grid.dims + kTile - 1u) / kTile;
    const size_t tile_count = size_t(tiles.x) * tiles.y * tiles.z;
    const bool show = !progress_label.empty() && grid.node_count() > (size_t(1) << 21);
    map.complete = parallel_items(tile_count, show ? progress_label : std::string(), [&](size_t t) {
        const glm::uvec3 tile(t % tiles.x, t / tiles.x % tiles.y, t / tiles.x / tiles.y);
        const glm::uvec3 first = tile * kTile, last = glm::min(first + kTile, grid.dims) - 1u;
        std::vector<size_t> band_nodes;
        for (uint32_t k = first.z; k <= last.z; ++k)
            for (uint32_t j = first.y; j <= last.y; ++j)
                for (uint32_t i = first.x; i <= last.x; ++i) {
                    const glm::uvec3 node(i, j, k);
                    const size_t n = grid.index(node);
                    const float d = sdf.distance[n];
                    const glm::vec3 p = grid.position(node);
                    if (d >= h || !ball_meets_clip(p)) continue;  // stays 0
                    if (d <= -h && ball_in_clip(p))
                        map.density[n] = glm::vec4(0.0f, 0.0f, 0.0f, float(deep));
                    else
                        band_nodes.push_back(n);
                }
        if (band_nodes.empty()) return;
        // Whole cubes keep one fraction (0 or 1); cut ones (-1 - index) point to their octants.
        const glm::ivec3 low = glm::ivec3(first) * split - reach;
        const glm::ivec3 size = glm::ivec3(last - first) * split + 2 * reach;
        std::vector<float> fractions(size_t(size.x) * size.y * size.z);
        std::vector<std::array<float, 8>> cut;
        std::array<float, 8> octants;
        // The field's cells that these cubes lie in: one whose nodes are all at least a cube's
        // half-diagonal out of the solid holds no solid anywhere (trilinear values lie between
        // the nodes'), so its cubes need no sample.
        const glm::ivec3 first_cell = glm::ivec3(first) - (reach + split - 1) / split;
        const glm::ivec3 cells = glm::ivec3(last - first) + 2 * ((reach + split - 1) / split) + 1;
        std::vector<signed char> empty(size_t(cells.x) * cells.y * cells.z, -1);  // -1: not yet known
        const auto empty_cell = [&](const glm::ivec3& f) {
            const glm::ivec3 c = glm::ivec3(glm::floor(glm::vec3(f) / float(split))), at = c - first_cell;
            signed char& known = empty[at.x + size_t(cells.x) * (at.y + size_t(cells.y) * at.z)];
            if (known < 0) {
                known = 0;
                if (glm::all(glm::greaterThanEqual(c, glm::ivec3(0))) &&
                    glm::all(glm::lessThan(c, glm::ivec3(grid.dims) - 1))) {
                    float nearest = sdf.distance[grid.index(glm::uvec3(c))];
                    for (int corner = 1; corner < 8; ++corner)
                        nearest = std::min(nearest, sdf.distance[grid.index(glm::uvec3(
                                                        c + glm::ivec3(corner & 1, (corner >> 1) & 1, corner >> 2)))]);
                    known = nearest >= half_diagonal;
                }
            }
            return known == 1;
        };
        for (int z = 0; z < size.z; ++z)
            for (int y = 0; y < size.y; ++y)
                for (int x = 0; x < size.x; ++x) {
                    const glm::ivec3 f = low + glm::ivec3(x, y, z);
                    if (empty_cell(f)) continue;  // fraction 0
                    const double fraction = octant_fractions(f, octants);
                    float& slot = fractions[x + size_t(size.x) * (y + size_t(size.y) * z)];
                    if (fraction > 0.0 && fraction < 1.0)
                        slot = -1.0f - float(cut.size()), cut.push_back(octants);
                    else
                        slot = float(fraction);
                }
        std::vector<int64_t> steps(cube_offsets.size());  // the table's offsets as steps in `fractions`
        for (size_t e = 0; e < steps.size(); ++e)
            steps[e] = cube_offsets[e].x + int64_t(size.x) * (cube_offsets[e].y + int64_t(size.y) * cube_offsets[e].z);
        for (const size_t n : band_nodes) {
            const glm::ivec3 base = glm::ivec3(grid.node_of(n)) * split - low;
            const float* at = fractions.data() + base.x + int64_t(size.x) * (base.y + int64_t(size.y) * base.z);
            glm::dvec4 sum(0.0);
            for (size_t e = 0; e < steps.size(); ++e) {
                const float fraction = at[steps[e]];
                if (fraction == 0.0f) continue;
                if (fraction == 1.0f) {
                    sum += glm::dvec4(cube_whole[e]);
                    continue;
                }
                const std::array<float, 8>& parts = cut[size_t(-1.0f - fraction)];
                for (int o = 0; o < 8; ++o) sum += glm::dvec4(cube_octants[e][o]) * double(parts[o]);
            }
            const double m = sum.w;
            const glm::dvec3 gradient(sum);
            map.density[n] = glm::vec4(glm::vec3(gradient * double(kernel.phi)), float(m * double(kernel.phi)));
        }
    });
    return map;
}

}  // namespace aquaform::geometry
