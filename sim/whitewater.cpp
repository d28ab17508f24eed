#include "sim/whitewater.h"

#include <algorithm>
#include <array>
#include <cstring>

#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"
#include "grid/neighbor_grid.h"
#include "sim/boundary.h"
#include "sim/scene.h"

namespace aquaform {

Whitewater::Whitewater(gpu::Context& ctx, const Scene& scene, uint32_t fluid_particles, bool solids)
    : ctx_(&ctx), buffers_(ctx) {
    const WhitewaterSettings s = scene.whitewater.value_or(WhitewaterSettings{});
    capacity_ = whitewater_capacity(s, fluid_particles, ctx.info().device_local_bytes);
    params_.trapped_air = glm::vec4(s.trapped_air, s.k_trapped_air, 0.5f * scene.particle_spacing);
    params_.wave_crest = glm::vec4(s.wave_crest, s.k_wave_crest, 0.6f);
    params_.kinetic = glm::vec4(s.kinetic_energy, s.lifetime);
    params_.motion = glm::vec4(s.air_drag, s.buoyancy, s.bubble_drag, float(s.emit_min_neighbors));
    params_.kinds = glm::uvec4(s.spray_below, s.bubble_above, capacity_, 0u);

    const uint64_t n = std::max<uint64_t>(fluid_particles, 1);
    params_buf_ = &buffers_.add("sim.whitewater.params", sizeof(shader::WhitewaterParams));
    counters_ = &buffers_.add("sim.whitewater.counters", WW_COUNTERS * sizeof(uint32_t), gpu::MemoryUse::host);
    groups_ = &buffers_.add("sim.whitewater.groups", 4 * sizeof(uint32_t));
    normals_ = &buffers_.add("sim.whitewater.normals", n * 16);
    potentials_ = &buffers_.add("sim.whitewater.potentials", n * 16);
    for (int g = 0; g < 2; ++g) {
        pool_x_[g] = &buffers_.add("sim.whitewater.x" + std::to_string(g), uint64_t(capacity_) * 16);
        pool_v_[g] = &buffers_.add("sim.whitewater.v" + std::to_string(g), uint64_t(capacity_) * 16);
    }
    std::memset(counters_->mapped, 0, WW_COUNTERS * sizeof(uint32_t));

    const uint32_t local = gpu::kDefaultLocalSize;
    args_ = gpu::ComputePass(ctx, {"sim/whitewater_args.comp", 3, sizeof(shader::WhitewaterPush), 1, {local}});
    normals_pass_ = gpu::ComputePass(ctx, {"sim/whitewater_normals.comp", 8, sizeof(shader::CountPush)});
    emit_ = gpu::ComputePass(
        ctx, {"sim/whitewater_emit.comp", 15, sizeof(shader::WhitewaterPush), local, solid_constants({}, solids)});
    advect_ = gpu::ComputePass(ctx, {"sim/whitewater_advect.comp", 12, 0, local, solid_constants({}, solids)});
}

std::string Whitewater::pass_name() const {
    return "sim_whitewater (spray, foam, bubbles: up to " + std::to_string(capacity_) + ")";
}

void Whitewater::record_step(VkCommandBuffer cmd, const StepState& fluid) {
    gpu::GpuScope s(fluid.timer, cmd, "sim_whitewater");
    record_step(cmd, fluid.params, fluid.x, fluid.v, fluid.grid, fluid.boundary_nodes, fluid.count);
}

void Whitewater::record_step(VkCommandBuffer cmd, const gpu::Buffer& sim_params, const gpu::Buffer& x,
                             const gpu::Buffer& v, const NeighborGrid& grid, const gpu::Buffer& boundary_nodes,
                             uint32_t count) {
    params_.kinds.w = ++steps_ * 2654435761u;  // each step draws afresh
    gpu::record_upload(*ctx_, cmd, *params_buf_, &params_, sizeof params_);
    const int next = 1 - current_;
    const shader::WhitewaterPush generation{uint32_t(next), 0u, 0u, 0u};
    gpu::dispatch(*ctx_, cmd, args_, 1, generation,
                  {{"ww", params_buf_}, {"counters", counters_}, {"groups", groups_}});
    gpu::dispatch_indirect(*ctx_, cmd, advect_, *groups_,
                           {{"params", &sim_params},
                            {"ww", params_buf_},
                            {"x", &x},
                            {"v", &v},
                            {"cell_rank", &grid.cell_rank()},
                            {"cell_start", &grid.cell_start()},
                            {"boundary_nodes", &boundary_nodes},
                            {"live_x", pool_x_[current_]},
                            {"live_v", pool_v_[current_]},
                            {"next_x", pool_x_[next]},
                            {"next_v", pool_v_[next]},
                            {"counters", counters_}});
    const shader::CountPush push{count, 0u, 0u, 0u};
    gpu::dispatch(*ctx_, cmd, normals_pass_, count, push,
                  {{"params", &sim_params},
                   {"x", &x},
                   {"cell_rank", &grid.cell_rank()},
                   {"cell_start", &grid.cell_start()},
                   {"list_cell", &grid.list_cell()},
                   {"neighbor_count", &grid.neighbor_count()},
                   {"neighbors", &grid.neighbors()},
                   {"normals", normals_}});
    const shader::WhitewaterPush emit_push{count, 0u, 0u, 0u};
    gpu::dispatch(*ctx_, cmd, emit_, count, emit_push,
                  {{"params", &sim_params},
                   {"ww", params_buf_},
                   {"x", &x},
                   {"v", &v},
                   {"cell_rank", &grid.cell_rank()},
                   {"cell_start", &grid.cell_start()},
                   {"list_cell", &grid.list_cell()},
                   {"neighbor_count", &grid.neighbor_count()},
                   {"neighbors", &grid.neighbors()},
                   {"normals", normals_},
                   {"potentials", potentials_},
                   {"pool_x", pool_x_[next]},
                   {"pool_v", pool_v_[next]},
                   {"counters", counters_},
                   {"boundary_nodes", &boundary_nodes}});
    current_ = next;
}

WhitewaterCounts Whitewater::collect() {
    auto* c = static_cast<uint32_t*>(counters_->mapped);
    WhitewaterCounts counts;
    counts.spray = c[WW_KINDS + WHITEWATER_SPRAY];
    counts.foam = c[WW_KINDS + WHITEWATER_FOAM];
    counts.bubbles = c[WW_KINDS + WHITEWATER_BUBBLE];
    // The last step's newborn have not been classified yet: they are foam until the next step.
    const uint32_t live = std::min(c[WW_NEXT], capacity_);
    counts.foam += live - std::min(live, counts.live());
    counts.emitted = c[WW_EMITTED];
    counts.dropped = c[WW_DROPPED];
    c[WW_EMITTED] = c[WW_DROPPED] = 0;
    return counts;
}

WhitewaterSnapshot Whitewater::snapshot() {
    ctx_->wait_queue_idle();
    const uint32_t live = std::min(static_cast<const uint32_t*>(counters_->mapped)[WW_NEXT], capacity_);
    WhitewaterSnapshot s;
    s.x.resize(live);
    s.v.resize(live);
    if (live) {
        gpu::download(*ctx_, *pool_x_[current_], s.x.data(), uint64_t(live) * 16);
        gpu::download(*ctx_, *pool_v_[current_], s.v.data(), uint64_t(live) * 16);
    }
    // By the bits of position, life, velocity and kind: a total order that needs no tie-break.
    const auto bits = [&](uint32_t i) {
        std::array<uint32_t, 8> key;
        std::memcpy(key.data(), &s.x[i], 16);
        std::memcpy(key.data() + 4, &s.v[i], 16);
        return key;
    };
    std::vector<uint32_t> order(live);
    for (uint32_t i = 0; i < live; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return bits(a) < bits(b); });
    WhitewaterSnapshot sorted;
    sorted.x.reserve(live);
    sorted.v.reserve(live);
    for (uint32_t i : order) sorted.x.push_back(s.x[i]), sorted.v.push_back(s.v[i]);
    return sorted;
}

std::vector<glm::vec4> Whitewater::potentials() {
    ctx_->wait_queue_idle();
    std::vector<glm::vec4> out(potentials_->size / 16);
    gpu::download(*ctx_, *potentials_, out.data(), potentials_->size);
    return out;
}

}  // namespace aquaform
