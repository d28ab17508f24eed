// The Morton-sorted neighbour grid: a counting sort of particles by the Morton rank of their
// cell (cell size = kernel radius h) over a grid sized to the scene's domain. It is a reusable
// object: the solver physically reorders its arrays by `order()`, other passes (the renderer)
// can query it in place through `order()`, `cell_rank()` and `cell_start()`.
// Layout and query rules: shaders/shared/grid/grid_layout.h and shaders/common/grid_query.glsl.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "grid/prefix_sum.h"
#include "shaders/shared/grid/grid_layout.h"

namespace aquaform {

namespace gpu {
class GpuTimer;
}

struct GridGeometry {
    glm::vec3 origin{0.0f};
    float cell_size = 1.0f;
    glm::uvec3 dims{1u};

    uint32_t cell_count() const { return dims.x * dims.y * dims.z; }
    shader::GridPush push(uint32_t particle_count) const;
};

/// A grid of cells of `cell_size` covering [min, max] (one extra cell of slack on each axis
/// end, so particles resting exactly on a wall share a cell layer with their neighbours).
/// Fails, naming the axis and the fix, when an axis would need more than 1024 cells.
Result<GridGeometry> grid_for_domain(glm::vec3 min, glm::vec3 max, float cell_size);

/// rank[linear cell index] = position of that cell in Morton order among the grid's cells.
std::vector<uint32_t> morton_rank_table(const GridGeometry& grid);

/// Neighbour-list entries per particle for a radius of `radius_in_spacings` particle spacings:
/// the particles of a rest lattice within that radius, (4/3) pi f^3, with 90 % to spare,
/// rounded up to a multiple of 8 (33 neighbours and 64 entries at the solver's usual h = 2
/// spacings). A particle beyond it is still handled, by a slower cell scan.
uint32_t neighbor_list_capacity(float radius_in_spacings);

/// GPU memory of the grid: per particle the sort (keys, slots, arrival, order) and, with lists,
/// the neighbour cell and count and the list of `capacity` entries; per cell (rank, start).
constexpr uint32_t kGridSortBytesPerParticle = 4 * sizeof(uint32_t);
constexpr uint32_t grid_bytes_per_particle(uint32_t capacity) {
    return kGridSortBytesPerParticle + (2 + capacity) * sizeof(uint32_t);
}
constexpr uint32_t kGridBytesPerCell = 2 * sizeof(uint32_t);

class NeighborGrid {
public:
    /// Allocates the grid's buffers in `buffers` (named with `prefix` for the memory report:
    /// "sim.grid" gives "sim.grid.keys"). With a `neighbor_capacity` of 0 (queries that search
    /// cells themselves, like the renderer's) the per-step list buffers are not allocated and
    /// record_neighbor_lists must not be called. Its timed scopes are its user's:
    /// `timer_prefix` + grid_count, grid_scan, grid_scatter and neighbor_lists ("sim_" gives
    /// "sim_grid_count"; grid_pass_traffic names its passes the same way).
    NeighborGrid(gpu::Context& ctx, gpu::BufferSet& buffers, const GridGeometry& geometry, uint32_t max_particles,
                 const std::string& prefix = "grid", uint32_t neighbor_capacity = 0,
                 const std::string& timer_prefix = "");

    /// Records the build: count per cell, exclusive scan into starts, scatter into `arrival`,
    /// then the stable order: a cell's particles by ascending index, the same on every run.
    /// Timed (with a timer) as timer_prefix + grid_count, grid_scan and grid_scatter.
    void build(VkCommandBuffer cmd, const gpu::Buffer& positions, uint32_t count, gpu::GpuTimer* timer);
    /// Records the last step of build() alone (`order` from `arrival`), for tests.
    void record_stable_order(VkCommandBuffer cmd, uint32_t count);

    /// Records the neighbour lists of `sorted_positions` (particles already in this grid's
    /// order, as the solver keeps them): the particles of the 27 surrounding cells that lie
    /// within `radius` <= cell size. Passes then visit them with common/neighbor_list.glsl.
    /// Timed (with a timer) as timer_prefix + neighbor_lists.
    void record_neighbor_lists(VkCommandBuffer cmd, const gpu::Buffer& sorted_positions, uint32_t count, float radius,
                               gpu::GpuTimer* timer);
    uint32_t neighbor_capacity() const { return neighbor_capacity_; }
    const gpu::Buffer& list_cell() const { return *list_cell_; }
    const gpu::Buffer& neighbor_count() const { return *neighbor_count_; }
    const gpu::Buffer& neighbors() const { return *neighbors_; }
    /// A neighbour pass's bindings: `own`, then the grid's tables and lists as
    /// common/neighbor_list.glsl names them (cell_rank, cell_start, list_cell, neighbor_count,
    /// neighbors).
    gpu::BindingList with_lists(gpu::Bindings own) const;

    /// Records a query of the built grid: for every particle of `positions` (the buffer given
    /// to build(), in its own order), the indices of the others within `radius` <= cell size.
    /// counts[i] is the true count; lists hold at most `capacity` entries per particle.
    void record_list_neighbors(VkCommandBuffer cmd, const gpu::Buffer& positions, uint32_t count, float radius,
                               uint32_t capacity, gpu::Buffer& counts, gpu::Buffer& lists);

    const GridGeometry& geometry() const { return geometry_; }
    const gpu::Buffer& cell_rank() const { return *cell_rank_; }
    const gpu::Buffer& cell_start() const { return *cell_start_; }
    /// order[sorted index] = index in the positions given to build().
    const gpu::Buffer& order() const { return *order_; }
    const gpu::Buffer& keys() const { return *keys_; }
    /// The scatter's order, before the stable pass: a cell's particles in the order the device ran them.
    gpu::Buffer& arrival() { return *arrival_; }

private:
    void check_radius(float radius) const;

    gpu::Context* ctx_;
    GridGeometry geometry_;
    std::string timer_prefix_;
    gpu::Buffer* cell_rank_;
    gpu::Buffer* cell_start_;  // cells + 1 entries; holds counts until the scan
    gpu::Buffer* keys_;
    gpu::Buffer* slots_;
    gpu::Buffer* arrival_;
    gpu::Buffer* order_;
    uint32_t neighbor_capacity_ = 0;
    gpu::Buffer* list_cell_ = nullptr;
    gpu::Buffer* neighbor_count_ = nullptr;
    gpu::Buffer* neighbors_ = nullptr;
    gpu::PrefixSum scan_;
    gpu::ComputePass count_pass_;
    gpu::ComputePass scatter_pass_;
    gpu::ComputePass stable_pass_;
    gpu::ComputePass neighbors_pass_;
    gpu::ComputePass list_pass_;  // created on first use
};

}  // namespace aquaform
