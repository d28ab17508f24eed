#include "sim/frame_stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace aquaform {

double full_neighbor_count(float kernel_radius_factor) {
    const double f = kernel_radius_factor;
    return 4.0 * 3.14159265358979323846 / 3.0 * f * f * f - 1.0;
}

FrameStats reduce_stats(std::span<const shader::StatsPartial> partials, uint32_t particles,
                        std::optional<float> front_wall_x, float runup_offset) {
    FrameStats s;
    s.particles = particles;
    double sum_err = 0.0, sum_dev = 0.0, outside = 0.0, in_solid = 0.0, non_finite = 0.0, splash = 0.0, overflow = 0.0;
    double front = -1.0e30, runup = -1.0e30;
    for (const auto& p : partials) {
        sum_err += p.sum_density_error;
        sum_dev += p.sum_abs_density_dev;
        s.max_density_error = std::max<double>(s.max_density_error, p.max_density_error);
        s.kinetic_energy += p.sum_kinetic_energy;
        s.max_speed = std::max<double>(s.max_speed, p.max_speed);
        outside += p.outside;
        in_solid += p.in_solid;
        non_finite += p.non_finite;
        front = std::max<double>(front, p.front);
        splash += p.splash;
        overflow += p.list_overflow;
        runup = std::max<double>(runup, p.runup);
    }
    if (particles) {
        s.mean_density_error = sum_err / particles;
        s.mean_density_deviation = sum_dev / particles;
        s.splash_fraction = splash / particles;
        s.list_overflow_fraction = overflow / particles;
    }
    s.outside = static_cast<uint32_t>(outside + 0.5);
    s.in_solid = static_cast<uint32_t>(in_solid + 0.5);
    s.non_finite = static_cast<uint32_t>(non_finite + 0.5);
    if (front_wall_x && front > -1.0e29) s.front = front - *front_wall_x;
    if (runup > -1.0e29) s.runup = runup + runup_offset;
    return s;
}

uint32_t droplet_size_limit(uint32_t particles) { return std::max<uint32_t>(2, (particles + 99) / 100); }

namespace {

struct UnionFind {
    std::vector<uint32_t> parent, size;
    explicit UnionFind(size_t n) : parent(n), size(n, 1) { std::iota(parent.begin(), parent.end(), 0u); }
    uint32_t find(uint32_t a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];  // path halving
        return a;
    }
    void unite(uint32_t a, uint32_t b) {
        a = find(a), b = find(b);
        if (a == b) return;
        if (size[a] < size[b]) std::swap(a, b);
        parent[b] = a;
        size[a] += size[b];
    }
};

}  // namespace

uint32_t count_droplets(std::span<const glm::vec4> positions, float link, uint32_t size_limit) {
    std::vector<uint32_t> finite;
    finite.reserve(positions.size());
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (uint32_t i = 0; i < positions.size(); ++i) {
        const glm::vec3 p(positions[i]);
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
        finite.push_back(i);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    if (finite.empty()) return 0;
    // Cells at least `link` wide, so a particle's links lie in the 27 cells around it; widened
    // until there are at most about two cells per particle, so that sparse spray keeps it O(N).
    const glm::dvec3 extent = glm::dvec3(hi - lo);
    double cell = link;
    uint64_t dims[3];
    const double budget = 2.0 * double(finite.size()) + 64.0;
    for (;;) {
        double cells = 1.0;
        for (int a = 0; a < 3; ++a) cells *= std::floor(extent[a] / cell) + 1.0;
        if (cells <= budget) break;
        cell *= 1.25;
    }
    for (int a = 0; a < 3; ++a) dims[a] = uint64_t(std::floor(extent[a] / cell)) + 1;
    auto cell_of = [&](const glm::vec4& p, int a) {
        return std::min<uint64_t>(uint64_t(std::max(0.0, (double(p[a]) - lo[a]) / cell)), dims[a] - 1);
    };
    const uint64_t cell_count = dims[0] * dims[1] * dims[2];
    std::vector<uint32_t> start(cell_count + 1, 0), key(finite.size());
    for (size_t k = 0; k < finite.size(); ++k) {
        const glm::vec4& p = positions[finite[k]];
        key[k] = uint32_t(cell_of(p, 0) + dims[0] * (cell_of(p, 1) + dims[1] * cell_of(p, 2)));
        ++start[key[k] + 1];
    }
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<uint32_t> sorted(finite.size()), fill(start.begin(), start.end() - 1);
    for (size_t k = 0; k < finite.size(); ++k) sorted[fill[key[k]]++] = uint32_t(k);

    UnionFind groups(finite.size());
    const float link2 = link * link;
    for (uint64_t c = 0; c < cell_count; ++c) {
        if (start[c] == start[c + 1]) continue;
        const int64_t cx = int64_t(c % dims[0]), cy = int64_t((c / dims[0]) % dims[1]),
                      cz = int64_t(c / (dims[0] * dims[1]));
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int64_t nx = cx + dx, ny = cy + dy, nz = cz + dz;
                    if (nx < 0 || ny < 0 || nz < 0 || nx >= int64_t(dims[0]) || ny >= int64_t(dims[1]) ||
                        nz >= int64_t(dims[2]))
                        continue;
                    const uint64_t n = uint64_t(nx) + dims[0] * (uint64_t(ny) + dims[1] * uint64_t(nz));
                    if (n < c) continue;  // each pair of cells once
                    for (uint32_t a = start[c]; a < start[c + 1]; ++a)
                        for (uint32_t b = n == c ? a + 1 : start[n]; b < start[n + 1]; ++b) {
                            const glm::vec3 d =
                                glm::vec3(positions[finite[sorted[a]]]) - glm::vec3(positions[finite[sorted[b]]]);
                            if (glm::dot(d, d) < link2) groups.unite(sorted[a], sorted[b]);
                        }
                }
    }
    uint32_t droplets = 0;
    for (uint32_t k = 0; k < finite.size(); ++k)
        if (groups.find(k) == k && groups.size[k] < size_limit) ++droplets;
    return droplets;
}

}  // namespace aquaform
