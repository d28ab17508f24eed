// The probes of a scene (sim/probe_spec.h) measured on the GPU: after every solver step the
// gauges' samples and the sensors' pressures (shaders/sim/probe_sample.comp) go to a slot of a
// host-visible buffer; at the end of each frame the force and torque on each solid
// (shaders/sim/probe_forces.comp). Nothing is read back until the frame's fence.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "shaders/shared/sim/probe_layout.h"
#include "sim/probe_spec.h"
#include "sim/scene.h"
#include "sim/solver_stage.h"

namespace aquaform {

class NeighborGrid;

/// One step's readings.
struct ProbeStep {
    double time_s = 0.0;
    std::vector<double> heights;    ///< per gauge: the water's height above the floor [m] (0: dry)
    std::vector<double> pressures;  ///< per sensor [Pa]
};

/// The force and torque on one solid at the end of a frame.
struct SolidLoad {
    std::string name;
    glm::dvec3 force{0.0};   ///< [N]
    glm::dvec3 torque{0.0};  ///< [N m] about the solid's centre
};

struct ProbeFrame {
    std::vector<ProbeStep> steps;
    std::vector<SolidLoad> loads;  ///< empty unless the probes ask for forces
};

/// The height of the water column a gauge's samples show: from the lowest sample outside every
/// solid (the floor, or a solid's top) up to where the volume fraction first falls below a half,
/// linearly between samples; 0 when the lowest sample is already dry. `floor_y` is the tank's
/// floor the height is measured from.
double gauge_height(const std::vector<float>& samples, float lowest_y, float spacing, float floor_y);

/// A stage after the pressure solve (sim/solver_stage.h): readings every step, loads at a frame's end.
class ProbeRecorder : public SolverStage {
public:
    /// `max_steps`: the most steps a frame can take (the solver's max_substeps).
    ProbeRecorder(gpu::Context& ctx, const Scene& scene, const std::vector<std::string>& solid_names,
                  uint32_t max_steps);

    /// After step `slot` of the frame (time `time_s` at its end): the readings into that slot.
    void record_step(VkCommandBuffer cmd, uint32_t slot, double time_s, const gpu::Buffer& params, const gpu::Buffer& x,
                     const gpu::Buffer& pressure, const NeighborGrid& grid, const gpu::Buffer& boundary_nodes,
                     uint32_t count);
    /// At the end of the frame: the loads on the solids, about `centres` (one per solid).
    void record_loads(VkCommandBuffer cmd, const gpu::Buffer& params, const gpu::Buffer& x, const gpu::Buffer& pressure,
                      const gpu::Buffer& boundary_nodes, uint32_t count, const std::vector<glm::vec3>& centres);
    std::string pass_name() const override { return "sim_probes"; }
    /// The step's readings, timed as "sim_probes".
    void record_step(VkCommandBuffer cmd, const StepState& fluid) override;
    /// The loads on the solids about their centres at the frame's end, timed as "sim_probes".
    void record_frame_end(VkCommandBuffer cmd, const StepState& fluid) override;
    /// Keeps the frame's readings for frame().
    void collect(FrameStats&) override { frame_ = collect(); }
    /// The readings of the frame last collected.
    const ProbeFrame& frame() const { return frame_; }
    /// Once the frame's submission has completed: its steps' readings and loads.
    ProbeFrame collect();

    const ProbeSpec& spec() const { return spec_; }
    std::vector<gpu::BufferReport> memory_report() const override { return buffers_.report(); }

private:
    gpu::Context* ctx_;
    ProbeSpec spec_;
    std::vector<std::string> solid_names_;
    float floor_y_ = 0.0f;
    uint32_t samples_per_gauge_ = 0;
    uint32_t max_steps_ = 0;
    shader::ProbeParams params_{};
    std::vector<double> step_times_;  ///< of the slots recorded this frame
    bool loads_recorded_ = false;
    ProbeFrame frame_;
    gpu::BufferSet buffers_;
    gpu::Buffer* probe_params_ = nullptr;
    gpu::Buffer* readings_ = nullptr;  ///< host-visible
    gpu::Buffer* partials_ = nullptr;  ///< host-visible
    gpu::ComputePass sample_, forces_;
};

}  // namespace aquaform
