#include "grid/grid_traffic.h"

#include <algorithm>

#include "core/error.h"
#include "gpu/buffer.h"
#include "gpu/staging.h"
#include "grid/neighbor_grid.h"
#include "shaders/shared/grid/scan_layout.h"

namespace aquaform {

namespace {

// A neighbour cell's range: cell_rank[linear] and cell_start[rank], cell_start[rank + 1]
// (grid_neighbor_range in common/grid_query.glsl). Unique bytes cannot pass the tables' size.
void add_cell_ranges(PassTraffic& t, uint64_t visits, uint64_t cells) {
    t.bytes += 12 * visits;
    t.unique_bytes += std::min(4 * visits, 4 * cells) + std::min(8 * visits, 4 * (cells + 1));
}

}  // namespace

GridCounts count_grid_work(const GridGeometry& geometry, uint32_t capacity, const std::vector<uint32_t>& cell_start,
                           const std::vector<uint32_t>& neighbor_count, const std::vector<uint32_t>& list_cell) {
    GridCounts c;
    c.particles = neighbor_count.size();
    c.cells = geometry.cell_count();
    c.capacity = capacity;
    if (cell_start.size() != c.cells + 1 || list_cell.size() != c.particles)
        throw internal_failure("count_grid_work: " + std::to_string(cell_start.size()) + " cell starts for " +
                               std::to_string(c.cells) + " cells, " + std::to_string(list_cell.size()) +
                               " list cells for " + std::to_string(c.particles) + " particles");
    auto members = [&](uint32_t rank) { return uint64_t(cell_start[rank + 1] - cell_start[rank]); };
    for (uint32_t r = 0; r < c.cells; ++r) {
        const uint64_t m = members(r);
        c.occupied_cells += m > 0;
        if (m <= shader::GRID_STABLE_MAX_CELL) c.cell_member_reads += m * m;
    }
    const std::vector<uint32_t> rank = morton_rank_table(geometry);
    const glm::ivec3 dims(geometry.dims);
    for (uint64_t i = 0; i < c.particles; ++i) {
        const glm::ivec3 cell(int(list_cell[i] % dims.x), int((list_cell[i] / dims.x) % dims.y),
                              int(list_cell[i] / (uint32_t(dims.x) * dims.y)));
        uint64_t cells = 0, candidates = 0;
        for (int k = 0; k < 27; ++k) {
            const glm::ivec3 n = cell + glm::ivec3(k % 3, (k / 3) % 3, k / 9) - glm::ivec3(1);
            if (glm::any(glm::lessThan(n, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(n, dims))) continue;
            ++cells;
            candidates +=
                members(rank[uint32_t(n.x) + uint32_t(dims.x) * (uint32_t(n.y) + uint32_t(dims.y) * uint32_t(n.z))]);
        }
        c.cell_visits += cells;
        c.candidates += candidates;
        const uint64_t n = neighbor_count[i];
        const uint64_t groups = (n + 3) / 4;
        c.neighbor_pairs += n;
        c.stored_texels += std::min<uint64_t>(groups, capacity / 4);
        if (n <= capacity) {
            c.list_entries += n;
            c.list_texels += groups;
        } else {
            ++c.overflow_particles;
            c.overflow_cell_visits += cells;
            c.overflow_visits += candidates - 1;
        }
    }
    return c;
}

GridCounts count_grid_work(gpu::Context& ctx, const NeighborGrid& grid, uint32_t particles) {
    const uint32_t cells = grid.geometry().cell_count();
    return count_grid_work(grid.geometry(), grid.neighbor_capacity(),
                           gpu::download_vector<uint32_t>(ctx, grid.cell_start(), cells + 1),
                           gpu::download_vector<uint32_t>(ctx, grid.neighbor_count(), particles),
                           gpu::download_vector<uint32_t>(ctx, grid.list_cell(), particles));
}

PassTraffic prefix_sum_traffic(uint64_t count, const std::string& name) {
    PassTraffic t{name};
    // gpu::PrefixSum::record_level: scan_blocks loads and stores every element and stores one
    // sum a block; with more than one block, the sums are scanned the same way and scan_add
    // loads and stores every element again with its block's sum (one load per element).
    for (uint64_t n = count; n > 0;) {
        const uint64_t blocks = (n + SCAN_BLOCK - 1) / SCAN_BLOCK;
        t.bytes += 8 * n + 4 * blocks;
        t.unique_bytes += 8 * n + 4 * blocks;
        if (blocks <= 1) break;
        t.bytes += 12 * n;
        t.unique_bytes += 8 * n + 4 * blocks;
        n = blocks;
    }
    return t;
}

PassTraffic neighbor_loop_traffic(const GridCounts& c, uint64_t per_neighbor, uint64_t neighbor_only) {
    PassTraffic t;
    // neighbor_count[i], the listed groups; past capacity: list_cell[i] and the 27 cells' ranges.
    t.bytes = 4 * c.particles + 16 * c.list_texels + 4 * c.overflow_particles + per_neighbor * c.visits();
    t.neighbor_visits = c.visits();
    t.unique_bytes = (4 + neighbor_only) * c.particles + 16 * c.list_texels + 4 * c.overflow_particles;
    add_cell_ranges(t, c.overflow_cell_visits, c.cells);
    return t;
}

std::vector<PassTraffic> grid_pass_traffic(const GridCounts& c, const std::string& timer_prefix) {
    const uint64_t n = c.particles;
    std::vector<PassTraffic> passes;
    // grid_count: the fill of cell_start, then per particle its position, its cell's rank, the
    // atomic add on the cell's count (a load and a store), its key and slot.
    PassTraffic count{timer_prefix + "grid_count"};
    count.bytes = 4 * (c.cells + 1) + n * (16 + 4 + 8 + 8);
    count.unique_bytes = 4 * (c.cells + 1) + n * (16 + 8) + c.occupied_cells * (4 + 8);
    passes.push_back(count);
    passes.push_back(prefix_sum_traffic(c.cells + 1, timer_prefix + "grid_scan"));
    // grid_scatter: key, slot, the cell's start, the arrival store; then the stable order:
    // arrival, key, the cell's two starts, the cell's members' arrival (the loop), the order store.
    PassTraffic scatter{timer_prefix + "grid_scatter"};
    scatter.bytes = n * (4 + 4 + 4 + 4) + n * (4 + 4 + 8 + 4) + 4 * c.cell_member_reads;
    scatter.unique_bytes = n * (4 + 4 + 4) + 4 * c.occupied_cells + n * (4 + 4 + 4) + 8 * c.occupied_cells;
    passes.push_back(scatter);
    // neighbor_lists: its own position, every candidate's, the 27 cells' ranges; stores its
    // cell, its count and its groups of four.
    PassTraffic lists{timer_prefix + "neighbor_lists"};
    lists.bytes = 16 * n + 16 * c.candidates + 8 * n + 16 * c.stored_texels;
    lists.unique_bytes = 16 * n + 8 * n + 16 * c.stored_texels;
    lists.neighbor_visits = c.candidates;
    add_cell_ranges(lists, c.cell_visits, c.cells);
    passes.push_back(lists);
    return passes;
}

}  // namespace aquaform
