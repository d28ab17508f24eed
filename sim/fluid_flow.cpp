#include "sim/fluid_flow.h"

#include "gpu/barriers.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"
#include "sim/scene.h"

namespace aquaform {

namespace {

/// The sinks' table and their mesh nodes, one after another (one float, so that a scene
/// without mesh sinks still has a buffer to bind).
shader::FlowSinks sink_table(const std::vector<SinkSpec>& sinks, std::vector<float>& nodes) {
    shader::FlowSinks table{};
    table.count.x = uint32_t(sinks.size());
    nodes.clear();
    for (size_t i = 0; i < sinks.size(); ++i) {
        table.sinks[i] = sinks[i].packed(uint32_t(nodes.size()));
        nodes.insert(nodes.end(), sinks[i].nodes().begin(), sinks[i].nodes().end());
    }
    if (nodes.empty()) nodes.push_back(0.0f);
    return table;
}

}  // namespace

FluidFlow::FluidFlow(gpu::Context& ctx, const Scene& scene, uint32_t capacity, uint32_t first_id)
    : ctx_(&ctx), schedule_(scene, first_id), capacity_(capacity), buffers_(ctx) {
    if (emits()) {
        layers_ = &buffers_.add("sim.flow.layers", FLOW_MAX_LAYERS * sizeof(shader::FlowLayer));
        lattice_ = &buffers_.add("sim.flow.lattice", schedule_.lattice().size() * sizeof(glm::vec2));
        gpu::upload(ctx, *lattice_, schedule_.lattice().data(), lattice_->size);
        emit_ = gpu::ComputePass(ctx, {"sim/flow_emit.comp", 6, sizeof(shader::FlowPush)});
        hold_ = gpu::ComputePass(ctx, {"sim/flow_hold.comp", 4, sizeof(shader::FlowPush)});
    }
    sinks_in_use_ = uint32_t(scene.sinks.size());
    if (removes()) {
        std::vector<float> nodes;
        const shader::FlowSinks table = sink_table(scene.sinks, nodes);
        sinks_ = &buffers_.add("sim.flow.sinks", sizeof table);
        gpu::upload(ctx, *sinks_, &table, sizeof table);
        sink_nodes_ = &buffers_.add("sim.flow.sink_nodes", nodes.size() * sizeof(float));
        gpu::upload(ctx, *sink_nodes_, nodes.data(), sink_nodes_->size);
        keep_ = &buffers_.add("sim.flow.keep", uint64_t(capacity) * 4);
        rank_ = &buffers_.add("sim.flow.rank", uint64_t(capacity) * 4);
        order_ = &buffers_.add("sim.flow.order", uint64_t(capacity) * 4);
        removed_ = &buffers_.add("sim.flow.removed", 4, gpu::MemoryUse::host);
        scan_ = gpu::PrefixSum(ctx, buffers_, capacity, "sim.flow");
        sinks_pass_ = gpu::ComputePass(ctx, {"sim/flow_sinks.comp", 7, sizeof(shader::FlowPush)});
    }
}

uint32_t FluidFlow::record_emit(VkCommandBuffer cmd, const gpu::Buffer& params, gpu::Buffer& x, gpu::Buffer& v,
                                gpu::Buffer* carry, double t1, uint32_t alive, gpu::GpuTimer* timer) {
    step_ = schedule_.plan_step(t1, alive, capacity_);
    totals_.emitted += step_.emitted;
    totals_.not_emitted += step_.not_emitted;
    if (step_.not_emitted > 0 && !first_full_time_) first_full_time_ = t1;
    if (step_.layers.empty()) return 0;
    gpu::GpuScope scope(timer, cmd, "sim_emit");
    gpu::record_upload(*ctx_, cmd, *layers_, step_.layers.data(), step_.layers.size() * sizeof(shader::FlowLayer));
    if (step_.emitted == 0) return 0;
    const shader::FlowPush push{step_.emitted, 0u, step_.emitted_layers, 0u, carry ? 1u : 0u, 0u, 0u, 0u};
    gpu::dispatch(*ctx_, cmd, emit_, step_.emitted, push,
                  {{"params", &params},
                   {"layers", layers_},
                   {"lattice", lattice_},
                   {"x", &x},
                   {"v", &v},
                   {"carry", carry ? carry : lattice_}});  // a stand-in the pass does not write
    return step_.emitted;
}

void FluidFlow::record_hold(VkCommandBuffer cmd, gpu::Buffer& x, gpu::Buffer& v, uint32_t alive, gpu::GpuTimer* timer) {
    const uint32_t held = uint32_t(step_.layers.size()) - step_.emitted_layers;
    if (held == 0) return;
    gpu::GpuScope scope(timer, cmd, "sim_emit");
    const shader::FlowPush push{alive, step_.emitted_layers, held, step_.min_held_id, 0u, 0u, 0u, 0u};
    gpu::dispatch(*ctx_, cmd, hold_, alive, push, {{"layers", layers_}, {"lattice", lattice_}, {"x", &x}, {"v", &v}});
}

uint32_t FluidFlow::held_particles() const {
    uint32_t held = 0;
    for (size_t l = step_.emitted_layers; l < step_.layers.size(); ++l) held += step_.layers[l].ids.z;
    return held;
}

void FluidFlow::dispatch_sinks(VkCommandBuffer cmd, const gpu::Buffer& x, uint32_t alive, uint32_t phase) {
    const shader::FlowPush push{alive, 0u, 0u, 0u, 0u, phase, 0u, 0u};
    gpu::dispatch(*ctx_, cmd, sinks_pass_, alive, push,
                  {{"table", sinks_},
                   {"sink_nodes", sink_nodes_},
                   {"x", &x},
                   {"keep", keep_},
                   {"rank", rank_},
                   {"order", order_},
                   {"removed", removed_}});
}

void FluidFlow::record_mark(VkCommandBuffer cmd, const gpu::Buffer& x, uint32_t alive, gpu::GpuTimer* timer) {
    gpu::GpuScope scope(timer, cmd, "sim_sinks");
    gpu::fill(*ctx_, cmd, *removed_, 0u);
    mark_in_flight_ = true;
    dispatch_sinks(cmd, x, alive, FLOW_MARK);
    scan_.record(cmd, *rank_, alive);
    gpu::host_read_barrier(cmd);
}

uint32_t FluidFlow::collect_marked() {
    if (!mark_in_flight_) return 0;
    mark_in_flight_ = false;
    pending_ = *static_cast<const uint32_t*>(removed_->mapped);
    totals_.removed += pending_;
    return pending_;
}

const gpu::Buffer& FluidFlow::record_kept_order(VkCommandBuffer cmd, const gpu::Buffer& x, uint32_t alive,
                                                gpu::GpuTimer* timer) {
    gpu::GpuScope scope(timer, cmd, "sim_sinks");
    dispatch_sinks(cmd, x, alive, FLOW_ORDER);
    pending_ = 0;
    return *order_;
}

}  // namespace aquaform
