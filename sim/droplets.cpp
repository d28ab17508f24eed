#include "sim/droplets.h"

#include "gpu/barriers.h"
#include "gpu/context.h"
#include "gpu/timer.h"
#include "grid/neighbor_grid.h"
#include "shaders/shared/sim/pbf_layout.h"

namespace aquaform {

DropletCount::DropletCount(gpu::Context& ctx, uint32_t particles, float h2) : ctx_(&ctx), h2_(h2), buffers_(ctx) {
    parent_ = &buffers_.add("sim.droplets.parent", uint64_t(particles) * 4);
    sizes_ = &buffers_.add("sim.droplets.sizes", uint64_t(particles) * 4);
    found_ = &buffers_.add("sim.droplets.count", 4, gpu::MemoryUse::host);
    pass_ = gpu::ComputePass(ctx, {"sim/droplets.comp", 10, sizeof(shader::DropletPush)});
}

void DropletCount::record_measure(VkCommandBuffer cmd, const StepState& fluid) {
    using namespace shader;
    gpu::GpuScope scope(fluid.timer, cmd, "sim_droplets");
    gpu::fill(*ctx_, cmd, *found_, 0);
    gpu::fill(*ctx_, cmd, *sizes_, 0);
    const NeighborGrid& grid = fluid.grid;
    for (uint32_t phase :
         {DROPLET_INIT, DROPLET_COMPRESS, DROPLET_HOOK, DROPLET_COMPRESS, DROPLET_SIZE, DROPLET_COUNT}) {
        const DropletPush push{fluid.count, phase, droplet_size_limit(fluid.count), h2_};
        gpu::dispatch(*ctx_, cmd, pass_, fluid.count, push,
                      {{"params", &fluid.params},
                       {"x", &fluid.x},
                       {"cell_rank", &grid.cell_rank()},
                       {"cell_start", &grid.cell_start()},
                       {"list_cell", &grid.list_cell()},
                       {"neighbor_count", &grid.neighbor_count()},
                       {"neighbors", &grid.neighbors()},
                       {"parent", parent_},
                       {"sizes", sizes_},
                       {"droplets", found_}});
    }
}

void DropletCount::collect(FrameStats& stats) { stats.droplets = *static_cast<const uint32_t*>(found_->mapped); }

}  // namespace aquaform
