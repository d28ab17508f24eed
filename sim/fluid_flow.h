// Water that comes and goes, on the GPU: the scene's nozzles emit into free slots after the alive
// particles in every step, and its sinks remove the particles inside them between frames
// (shaders/shared/sim/flow_layout.h has the passes' data, sim/flow_schedule.h the layers' times).
//
// The alive count is known to the host at every recording, as every pass and renderer needs it:
// emission is scheduled on the host, so a step's new count is known when it is recorded; the
// removed are counted at a frame's end and come back with its statistics, and they leave the
// arrays at the next frame's start (a stable compaction: a prefix sum over the kept, then the
// solver's gather), before its steps. So a particle that entered a sink during a frame is in that
// frame's pictures and files, and gone from the next.
#pragma once

#include <cstdint>
#include <optional>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "grid/prefix_sum.h"
#include "sim/flow_schedule.h"
#include "sim/frame_stats.h"

namespace aquaform {

namespace gpu {
class GpuTimer;
}

class FluidFlow {
public:
    /// Sized for `capacity` particles; the nozzles' ids start at `first_id`.
    FluidFlow(gpu::Context& ctx, const Scene& scene, uint32_t capacity, uint32_t first_id);

    bool emits() const { return !schedule_.empty(); }
    bool removes() const { return sinks_in_use_ > 0; }
    float max_speed(double t0, double t1) const { return schedule_.max_speed(t0, t1); }
    /// The nozzles' schedule, for live changes (FlowSchedule::steer, set_open).
    FlowSchedule& schedule() { return schedule_; }
    const FlowSchedule& schedule() const { return schedule_; }

    /// The step ending at t1: uploads its layer table and writes its new particles into x, v
    /// (and zeroes their `carry`, where there is one) from slot `alive` on. Returns how many.
    uint32_t record_emit(VkCommandBuffer cmd, const gpu::Buffer& params, gpu::Buffer& x, gpu::Buffer& v,
                         gpu::Buffer* carry, double t1, uint32_t alive, gpu::GpuTimer* timer);
    /// After the step's pressure solve: the held layers put back on their lattices.
    void record_hold(VkCommandBuffer cmd, gpu::Buffer& x, gpu::Buffer& v, uint32_t alive, gpu::GpuTimer* timer);

    /// At a frame's end: marks the particles inside a sink and ranks the kept.
    void record_mark(VkCommandBuffer cmd, const gpu::Buffer& x, uint32_t alive, gpu::GpuTimer* timer);
    /// Once the marking frame's submission has completed: how many it marked (0 before any mark).
    uint32_t collect_marked();
    /// At the next frame's start: the order of the kept particles (the first alive - marked
    /// entries), for the solver's gather; the marks are used up.
    const gpu::Buffer& record_kept_order(VkCommandBuffer cmd, const gpu::Buffer& x, uint32_t alive,
                                         gpu::GpuTimer* timer);
    /// Particles the last recorded step held on the nozzles.
    uint32_t held_particles() const;
    /// Marked at the last collected frame's end and not yet compacted (0: nothing to do).
    uint32_t pending_removal() const { return pending_; }
    /// A new state replaces the arrays (PbfSolver::set_state): marks of the old one are dropped.
    void drop_marks() { pending_ = 0, mark_in_flight_ = false; }

    /// Totals since the start (those marked at the last collected frame's end included).
    const FlowCounts& totals() const { return totals_; }
    /// When a layer first found the capacity full [s]; empty: never.
    std::optional<double> first_full_time() const { return first_full_time_; }
    std::vector<gpu::BufferReport> memory_report() const { return buffers_.report(); }

private:
    /// flow_sinks.comp over the alive particles, in `phase` (FLOW_MARK or FLOW_ORDER).
    void dispatch_sinks(VkCommandBuffer cmd, const gpu::Buffer& x, uint32_t alive, uint32_t phase);
    gpu::Context* ctx_;
    FlowSchedule schedule_;
    uint32_t capacity_;
    uint32_t sinks_in_use_ = 0;
    uint32_t pending_ = 0;
    bool mark_in_flight_ = false;  ///< a mark was recorded and not yet collected
    FlowStep step_;                ///< the step being recorded (its hold follows its emission)
    FlowCounts totals_;
    std::optional<double> first_full_time_;
    gpu::BufferSet buffers_;
    gpu::Buffer* layers_ = nullptr;
    gpu::Buffer* lattice_ = nullptr;
    gpu::Buffer* sinks_ = nullptr;
    gpu::Buffer* sink_nodes_ = nullptr;  ///< the mesh sinks' distances
    gpu::Buffer* keep_ = nullptr;
    gpu::Buffer* rank_ = nullptr;
    gpu::Buffer* order_ = nullptr;
    gpu::Buffer* removed_ = nullptr;  ///< host-visible: the count marked
    gpu::PrefixSum scan_;
    gpu::ComputePass emit_, hold_, sinks_pass_;
};

}  // namespace aquaform
