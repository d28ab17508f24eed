#include "grid/neighbor_grid.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"
#include "shaders/shared/grid/morton.h"

namespace aquaform {

shader::GridPush GridGeometry::push(uint32_t particle_count) const {
    shader::GridPush p{};
    p.origin_cell = glm::vec4(origin, cell_size);
    p.dims = glm::uvec4(dims, cell_count());
    p.count = particle_count;
    return p;
}

Result<GridGeometry> grid_for_domain(glm::vec3 min, glm::vec3 max, float cell_size) {
    GridGeometry g;
    g.cell_size = cell_size;
    g.origin = min - glm::vec3(cell_size);
    const char* axes = "xyz";
    for (int a = 0; a < 3; ++a) {
        // (the 1e-4 keeps float noise in extent / cell_size from adding a whole layer of cells)
        double cells = std::ceil(double(max[a] - min[a]) / cell_size - 1.0e-4) + 2.0;
        if (!(cells <= shader::MORTON_MAX_CELLS_PER_AXIS))
            return Error{"the domain is " + std::to_string(cells) + " kernel radii long on " + axes[a] +
                         "; the neighbour grid holds at most " + std::to_string(shader::MORTON_MAX_CELLS_PER_AXIS) +
                         " cells per axis: shrink the domain or increase particle_spacing"};
        g.dims[a] = static_cast<uint32_t>(cells);
    }
    return g;
}

uint32_t neighbor_list_capacity(float radius_in_spacings) {
    const double f = radius_in_spacings;
    const double lattice = 4.0 / 3.0 * 3.14159265358979 * f * f * f;
    // The spare, measured on the bench dam break mid-collapse (20 steps, 31k and 65k particles):
    // mean 32 neighbours at h = 2 spacings, but the count spreads to 60 where the column presses
    // on the floor. With 40 % to spare (48 entries) 1.3 % of the particles overflowed, and on
    // SIMD hardware one overflowing lane makes its whole group scan the cells: 158 ms a step at
    // 65k. With 90 % (64) none did, and the step took 103 ms. The trade: 64 B more per particle.
    return std::max(8u, uint32_t(std::ceil(1.9 * lattice / 8.0)) * 8u);
}

std::vector<uint32_t> morton_rank_table(const GridGeometry& grid) {
    const uint32_t n = grid.cell_count();
    std::vector<uint32_t> codes(n);
    for (uint32_t z = 0; z < grid.dims.z; ++z)
        for (uint32_t y = 0; y < grid.dims.y; ++y)
            for (uint32_t x = 0; x < grid.dims.x; ++x)
                codes[x + grid.dims.x * (y + grid.dims.y * z)] = shader::morton_encode(glm::uvec3(x, y, z));
    std::vector<uint32_t> by_code(n);
    std::iota(by_code.begin(), by_code.end(), 0u);
    std::sort(by_code.begin(), by_code.end(), [&](uint32_t a, uint32_t b) { return codes[a] < codes[b]; });
    std::vector<uint32_t> rank(n);
    for (uint32_t r = 0; r < n; ++r) rank[by_code[r]] = r;
    return rank;
}

NeighborGrid::NeighborGrid(gpu::Context& ctx, gpu::BufferSet& buffers, const GridGeometry& geometry,
                           uint32_t max_particles, const std::string& prefix, uint32_t neighbor_capacity,
                           const std::string& timer_prefix)
    : ctx_(&ctx), geometry_(geometry), timer_prefix_(timer_prefix), neighbor_capacity_(neighbor_capacity) {
    const uint32_t cells = geometry.cell_count();
    cell_rank_ = &buffers.add(prefix + ".cell_rank", uint64_t(cells) * 4);
    cell_start_ = &buffers.add(prefix + ".cell_start", (uint64_t(cells) + 1) * 4);
    keys_ = &buffers.add(prefix + ".keys", uint64_t(max_particles) * 4);
    slots_ = &buffers.add(prefix + ".slots", uint64_t(max_particles) * 4);
    arrival_ = &buffers.add(prefix + ".arrival", uint64_t(max_particles) * 4);
    order_ = &buffers.add(prefix + ".order", uint64_t(max_particles) * 4);
    if (neighbor_capacity) {
        list_cell_ = &buffers.add(prefix + ".list_cell", uint64_t(max_particles) * 4);
        neighbor_count_ = &buffers.add(prefix + ".neighbor_count", uint64_t(max_particles) * 4);
        // Read and written only as rgba32ui texels: it may be larger than a storage buffer can be
        // (256 B a particle: a million particles on lavapipe's 128 MiB storage range).
        neighbors_ = &buffers.add(prefix + ".neighbors", uint64_t(max_particles) * neighbor_capacity * 4,
                                  gpu::MemoryUse::device, true);
    }
    scan_ = gpu::PrefixSum(ctx, buffers, cells + 1, prefix);
    auto rank = morton_rank_table(geometry);
    gpu::upload(ctx, *cell_rank_, rank.data(), rank.size() * 4);

    using shader::GridPush;
    count_pass_ = gpu::ComputePass(ctx, {"grid/grid_count.comp", 5, sizeof(GridPush)});
    scatter_pass_ = gpu::ComputePass(ctx, {"grid/grid_scatter.comp", 4, sizeof(GridPush)});
    stable_pass_ = gpu::ComputePass(ctx, {"grid/grid_stable_order.comp", 4, sizeof(GridPush)});
    if (neighbor_capacity)
        neighbors_pass_ = gpu::ComputePass(ctx, {"grid/neighbor_lists.comp", 6, sizeof(shader::NeighborListPush)});
}

void NeighborGrid::build(VkCommandBuffer cmd, const gpu::Buffer& positions, uint32_t count, gpu::GpuTimer* timer) {
    const shader::GridPush push = geometry_.push(count);
    {
        gpu::GpuScope scope(timer, cmd, timer_prefix_ + "grid_count");
        gpu::fill(*ctx_, cmd, *cell_start_, 0);
        gpu::dispatch(*ctx_, cmd, count_pass_, count, push,
                      {{"positions", &positions},
                       {"cell_rank", cell_rank_},
                       {"cell_count", cell_start_},
                       {"keys", keys_},
                       {"slots", slots_}});
    }
    {
        gpu::GpuScope scope(timer, cmd, timer_prefix_ + "grid_scan");
        scan_.record(cmd, *cell_start_, geometry_.cell_count() + 1);
    }
    {
        gpu::GpuScope scope(timer, cmd, timer_prefix_ + "grid_scatter");
        gpu::dispatch(*ctx_, cmd, scatter_pass_, count, push,
                      {{"keys", keys_}, {"slots", slots_}, {"cell_start", cell_start_}, {"arrival", arrival_}});
        record_stable_order(cmd, count);
    }
}

void NeighborGrid::record_stable_order(VkCommandBuffer cmd, uint32_t count) {
    gpu::dispatch(*ctx_, cmd, stable_pass_, count, geometry_.push(count),
                  {{"keys", keys_}, {"cell_start", cell_start_}, {"arrival", arrival_}, {"order", order_}});
}

void NeighborGrid::record_neighbor_lists(VkCommandBuffer cmd, const gpu::Buffer& sorted_positions, uint32_t count,
                                         float radius, gpu::GpuTimer* timer) {
    if (!neighbors_) throw internal_failure("neighbour grid: built without neighbour lists, cannot record them");
    check_radius(radius);
    gpu::GpuScope scope(timer, cmd, timer_prefix_ + "neighbor_lists");
    shader::NeighborListPush push{};
    push.grid = geometry_.push(count);
    push.radius = radius;
    push.capacity = neighbor_capacity_;
    gpu::dispatch(*ctx_, cmd, neighbors_pass_, count, push,
                  {{"positions", &sorted_positions},
                   {"cell_rank", cell_rank_},
                   {"cell_start", cell_start_},
                   {"list_cell", list_cell_},
                   {"neighbor_count", neighbor_count_},
                   {"neighbors", neighbors_}});
}

void NeighborGrid::check_radius(float radius) const {
    if (radius > geometry_.cell_size)
        throw Failure("neighbour query radius " + std::to_string(radius) + " exceeds the grid's cell size " +
                      std::to_string(geometry_.cell_size) + "; build a grid with larger cells");
}

void NeighborGrid::record_list_neighbors(VkCommandBuffer cmd, const gpu::Buffer& positions, uint32_t count,
                                         float radius, uint32_t capacity, gpu::Buffer& counts, gpu::Buffer& lists) {
    check_radius(radius);
    if (!list_pass_.pipeline())
        list_pass_ = gpu::ComputePass(*ctx_, {"grid/grid_list_neighbors.comp", 6, sizeof(shader::NeighborListPush)});
    shader::NeighborListPush push{};
    push.grid = geometry_.push(count);
    push.radius = radius;
    push.capacity = capacity;
    gpu::dispatch(*ctx_, cmd, list_pass_, count, push,
                  {{"positions", &positions},
                   {"order", order_},
                   {"cell_rank", cell_rank_},
                   {"cell_start", cell_start_},
                   {"counts", &counts},
                   {"lists", &lists}});
}

gpu::BindingList NeighborGrid::with_lists(gpu::Bindings own) const {
    gpu::BindingList bindings(own);
    bindings.insert(bindings.end(), {{"cell_rank", &cell_rank()},
                                     {"cell_start", &cell_start()},
                                     {"list_cell", &list_cell()},
                                     {"neighbor_count", &neighbor_count()},
                                     {"neighbors", &neighbors()}});
    return bindings;
}

}  // namespace aquaform
