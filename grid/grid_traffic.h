// A byte model of the neighbour grid's passes: what each must read and write per step, from
// device-independent counts of the grid's state (particles, cells, candidates, list entries).
// It makes the distance to a device's memory floor visible without that device: modelled bytes
// over measured time is the bandwidth a pass reaches, and bytes over a copy bandwidth the least
// time it could take. The solver adds its own passes (sim/pbf_traffic.h).
//
// Two figures per pass, bounding the memory traffic from both sides:
// - `bytes`: every load and store the shader makes, counted once per invocation as written
//   (a neighbour's position once per list entry that names it): traffic with no cache at all.
// - `unique_bytes`: the distinct bytes the pass touches (each buffer element once): traffic
//   when caches serve every reuse within the pass, the floor for a pass that starts cold.
// vec4 elements count 16 B even where a shader stores only .xyz (a sector is written either way);
// texel loads count their whole texel (16 B for a 4-entry list group, even when part-filled).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace aquaform {

class NeighborGrid;
struct GridGeometry;

namespace gpu {
class Context;
}

/// One pass's modelled traffic per step (summed over its `runs` dispatches in a step).
struct PassTraffic {
    std::string name;           ///< the pass's GPU timer scope
    uint32_t runs = 1;          ///< dispatches of it per step (the constraint iterations)
    uint64_t bytes = 0;         ///< every load and store
    uint64_t unique_bytes = 0;  ///< distinct bytes touched, summed over runs
    /// Neighbours visited, summed over runs: a neighbour loop's list entries (or a cell scan's
    /// candidates); the list fill's candidates tested.
    uint64_t neighbor_visits = 0;
};

/// Device-independent counts of the grid's state after a build and a list fill.
struct GridCounts {
    uint64_t particles = 0;
    uint64_t cells = 0;
    uint64_t occupied_cells = 0;
    uint32_t capacity = 0;            ///< list entries per particle
    uint64_t cell_visits = 0;         ///< in-grid cells of the 27 around each particle (a rank and two starts each)
    uint64_t candidates = 0;          ///< particles in those cells, self included: positions the list fill loads
    uint64_t cell_member_reads = 0;   ///< the stable order's loop: sum over cells of members^2 (cells of <= 256)
    uint64_t list_entries = 0;        ///< neighbours listed, over particles whose list holds them all
    uint64_t list_texels = 0;         ///< their 4-entry groups: what a list visit loads
    uint64_t stored_texels = 0;       ///< groups the fill stores (overflowing lists cut at capacity)
    uint64_t overflow_particles = 0;  ///< particles past their list, which scan cells instead
    uint64_t overflow_cell_visits = 0;
    uint64_t overflow_visits = 0;  ///< candidates other than self of those particles
    uint64_t neighbor_pairs = 0;   ///< sum of the true counts, listed or not

    /// Neighbours one neighbour loop (common/neighbor_list.glsl) visits over all particles.
    uint64_t visits() const { return list_entries + overflow_visits; }
};

/// Counts from the grid's tables as read back: cell_start (ranks, cells + 1 entries),
/// neighbor_count and list_cell (per particle, as grid/neighbor_lists.comp wrote them).
GridCounts count_grid_work(const GridGeometry& geometry, uint32_t capacity, const std::vector<uint32_t>& cell_start,
                           const std::vector<uint32_t>& neighbor_count, const std::vector<uint32_t>& list_cell);
/// The same from the device (reads the three tables back: 8 B per particle and 4 B per cell).
GridCounts count_grid_work(gpu::Context& ctx, const NeighborGrid& grid, uint32_t particles);

/// grid_count (with the fill of the counts), grid_scan, grid_scatter (with the stable order)
/// and neighbor_lists, as NeighborGrid::build and record_neighbor_lists record them; each named
/// `timer_prefix` + the pass, as a NeighborGrid made with that timer_prefix times it.
std::vector<PassTraffic> grid_pass_traffic(const GridCounts& counts, const std::string& timer_prefix = "");

/// What one pass over common/neighbor_list.glsl's loop reads for the lists themselves: the
/// count per particle, the listed groups, and for overflowing particles their cell and the 27
/// cells' ranges. `per_neighbor` is what the pass's visit() loads at each neighbour, counted in
/// `bytes` per visit; its unique bytes are the buffers', counted once: `neighbor_only` is the
/// bytes per particle of arrays the pass reads only at neighbours (those the pass also reads
/// at its own particle are counted there).
PassTraffic neighbor_loop_traffic(const GridCounts& counts, uint64_t per_neighbor, uint64_t neighbor_only = 0);

/// The exclusive scan of `count` uints (grid/prefix_sum.cpp's levels of block scans and adds),
/// named `name`.
PassTraffic prefix_sum_traffic(uint64_t count, const std::string& name);

}  // namespace aquaform
