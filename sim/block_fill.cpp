#include "sim/block_fill.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

namespace aquaform {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The plastic number, whose powers make Roberts's R2 sequence: a 2D Kronecker pattern, any
/// leading share of which is spread evenly over the plane (the golden ratio's is its 1D sibling).
constexpr double kPlastic = 1.32471795724474602596;

/// A column's rank: frac(inner / rho + outer / rho^2). Any leading share of the columns in rank
/// order is spread evenly over the block's top.
double column_rank(uint64_t inner, uint64_t outer) {
    const double v = double(inner) / kPlastic + double(outer) / (kPlastic * kPlastic);
    return v - std::floor(v);
}

/// The particles of each column (index outer * n_inner + inner), `count` in all: each column its
/// share of the volume (`heights`: the column's height, in any unit), rounded with the error
/// carried on to the next column in rank order. The carried error keeps every stretch of columns
/// at its share (rounding each alone would flatten a surface wave of one or two layers by a fifth),
/// and a flat block's extra particles land on columns spread evenly over its top.
std::vector<uint64_t> column_counts(const std::vector<double>& heights, uint64_t n_inner, uint64_t count) {
    double total = 0.0;
    for (const double h : heights) total += h;
    std::vector<uint64_t> order(heights.size());
    std::iota(order.begin(), order.end(), uint64_t{0});
    std::stable_sort(order.begin(), order.end(), [&](uint64_t a, uint64_t b) {
        return column_rank(a % n_inner, a / n_inner) < column_rank(b % n_inner, b / n_inner);
    });
    std::vector<uint64_t> counts(heights.size());
    double carried = 0.0;
    uint64_t placed = 0;
    for (const uint64_t c : order) {
        const double wanted = double(count) * heights[c] / total + carried;
        counts[c] = uint64_t(std::max(0.0, std::floor(wanted + 0.5)));
        carried = wanted - double(counts[c]);
        placed += counts[c];
    }
    // Rounding in double can leave the total a particle off: the last column in rank order mends it.
    if (!order.empty()) {
        uint64_t& last = counts[order.back()];
        last = uint64_t(std::max<int64_t>(0, int64_t(last) + int64_t(count) - int64_t(placed)));
    }
    return counts;
}

/// A box: columns, each filled from the bottom (block_fill.h).
void fill_box(const Box& box, const BlockFill& fill, double s, const glm::vec3& gravity, uint64_t count,
              const std::function<void(const glm::vec3&)>& fn) {
    int up = 1;  // the axis along gravity; y without gravity, and for a block with a surface wave
    if (gravity != glm::vec3(0.0f) && !fill.wave)
        for (int a = 0; a < 3; ++a)
            if (std::abs(gravity[a]) > std::abs(gravity[up])) up = a;
    const bool falls_to_max = gravity[up] > 0.0f && !fill.wave;
    const int inner = up == 0 ? 1 : 0, outer = up == 2 ? 1 : 2;
    const glm::dvec3 lo(box.min), hi(box.max), size = hi - lo;
    const uint64_t n_inner = std::max<uint64_t>(1, std::llround(size[inner] / s));
    const uint64_t n_outer = std::max<uint64_t>(1, std::llround(size[outer] / s));
    // A side that is a whole number of spacings (to a relative 1e-4) keeps the pitch s itself, so
    // such a block is the very lattice of pitch s, to the bit.
    auto pitch_of = [&](double side, uint64_t n) {
        return std::abs(side / s - double(n)) < 1e-4 * double(n) ? s : side / double(n);
    };
    const double pitch_inner = pitch_of(size[inner], n_inner), pitch_outer = pitch_of(size[outer], n_outer);
    // Each particle's cell is s^3: the layers' pitch makes up for the columns' pitch.
    const double pitch_up = pitch_inner == s && pitch_outer == s ? s : s * s * s / (pitch_inner * pitch_outer);
    auto centre = [&](int axis, uint64_t column) {
        const double pitch = axis == inner ? pitch_inner : pitch_outer;
        return lo[axis] + pitch * (double(column) + 0.5);
    };
    std::vector<double> heights(n_inner * n_outer, size[up]);
    if (fill.wave) {
        const SurfaceWave& w = *fill.wave;
        for (uint64_t o = 0; o < n_outer; ++o)
            for (uint64_t i = 0; i < n_inner; ++i) {
                const double u = w.along == inner ? centre(inner, i) : centre(outer, o);
                const double phase = 2.0 * kPi * (u - lo[w.along]) / double(w.length);
                heights[o * n_inner + i] = size[up] + double(w.amplitude) * std::cos(phase);
            }
    }
    const std::vector<uint64_t> counts = column_counts(heights, n_inner, count);
    uint64_t tallest = 0;
    for (const uint64_t n : counts) tallest = std::max(tallest, n);
    // Rows along the inner axis, layer by layer, slab by slab along the outer axis (z, y, x for
    // gravity along -y: the order of the lattice this fill replaced).
    for (uint64_t o = 0; o < n_outer; ++o)
        for (uint64_t layer = 0; layer < tallest; ++layer)
            for (uint64_t i = 0; i < n_inner; ++i) {
                const uint64_t column = o * n_inner + i, n = counts[column];
                if (layer >= n) continue;
                // A column whose top particle would stand above its height closes up to keep it
                // within (a compression of under a layer that the relaxed start lets out).
                const double pitch = std::min(pitch_up, heights[column] / (double(n) - 0.5));
                const double height = (double(layer) + 0.5) * pitch;
                glm::dvec3 p;
                p[up] = falls_to_max ? hi[up] - height : lo[up] + height;
                p[inner] = centre(inner, i);
                p[outer] = centre(outer, o);
                fn(glm::vec3(p));
            }
}

/// A ball: the `count` points of a lattice about its centre (within its box) nearest to the
/// centre. The lattice has a point at the centre, or the centre between points where that fits
/// more points in the box (a ball of radius 1.9 s holds 29 particles; 27 points of the first kind
/// fit its box, 64 of the second). In half spacings every coordinate is a whole number, so are the
/// squared distances: the shells are counted first, and the last one's share is spread evenly over
/// it in lattice order.
void fill_ball(const Box& box, double s, uint64_t count, const std::function<void(const glm::vec3&)>& fn) {
    const glm::dvec3 lo(box.min), hi(box.max), centre = 0.5 * (lo + hi);
    const double half_side = 0.5 * std::min({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) / s;
    const int64_t on_point = 2 * int64_t(std::floor(half_side)) + 1, between = 2 * int64_t(std::floor(half_side + 0.5));
    const int64_t offset = between > on_point ? 1 : 0;  // coordinates 2i + offset half spacings
    const int64_t m = int64_t(std::ceil(half_side)) + 1;
    auto for_each_point = [&](auto visit) {
        for (int64_t k = -m; k <= m; ++k)
            for (int64_t j = -m; j <= m; ++j)
                for (int64_t i = -m; i <= m; ++i) {
                    const int64_t ux = 2 * i + offset, uy = 2 * j + offset, uz = 2 * k + offset;  // half spacings
                    const glm::dvec3 p = centre + 0.5 * s * glm::dvec3(double(ux), double(uy), double(uz));
                    if (glm::all(glm::greaterThanEqual(p, lo)) && glm::all(glm::lessThanEqual(p, hi)))
                        visit(p, uint64_t(ux * ux + uy * uy + uz * uz));
                }
    };
    std::vector<uint64_t> shell(uint64_t(3 * (2 * m + 1) * (2 * m + 1)) + 1, 0);
    for_each_point([&](const glm::dvec3&, uint64_t d2) { ++shell[d2]; });
    uint64_t last = 0, inside = 0;  // every shell below `last` is taken whole
    while (last + 1 < shell.size() && inside + shell[last] < count) inside += shell[last++];
    const uint64_t share = std::min(count - inside, shell[last]), on_last = std::max<uint64_t>(shell[last], 1);
    uint64_t seen = 0;
    for_each_point([&](const glm::dvec3& p, uint64_t d2) {
        if (d2 < last) return fn(glm::vec3(p));
        if (d2 != last) return;
        // Bresenham over the shell: `share` of its `on_last` points, evenly in lattice order.
        const bool take = (seen + 1) * share / on_last > seen * share / on_last;
        ++seen;
        if (take) fn(glm::vec3(p));
    });
}

}  // namespace

double block_volume(const Box& box, const BlockFill& fill) {
    if (fill.sphere_radius) {
        const double r = *fill.sphere_radius;
        return 4.0 / 3.0 * kPi * r * r * r;
    }
    const glm::dvec3 size = glm::dvec3(box.max) - glm::dvec3(box.min);
    double volume = size.x * size.y * size.z;
    if (fill.wave) {  // the wave's crests less its troughs, over the block's top (y)
        const SurfaceWave& w = *fill.wave;
        const double k = 2.0 * kPi / double(w.length), across = w.along == 0 ? size.z : size.x;
        volume += double(w.amplitude) * std::sin(k * size[w.along]) / k * across;
    }
    return volume;
}

uint64_t block_particle_count(const Box& box, const BlockFill& fill, float spacing) {
    if (!(spacing > 0.0f)) return 0;
    const double s = spacing;
    const double n = std::round(block_volume(box, fill) / (s * s * s));
    if (!(n >= 0.0)) return 0;
    if (n >= 18446744073709551616.0) return std::numeric_limits<uint64_t>::max();
    return uint64_t(n);
}

void for_each_block_particle(const Box& box, const BlockFill& fill, float spacing, const glm::vec3& gravity,
                             const std::function<void(const glm::vec3&)>& fn) {
    const uint64_t count = block_particle_count(box, fill, spacing);
    if (count == 0) return;
    if (fill.sphere_radius) return fill_ball(box, spacing, count, fn);
    fill_box(box, fill, spacing, gravity, count, fn);
}

}  // namespace aquaform
