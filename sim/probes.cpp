#include "sim/probes.h"

#include <algorithm>
#include <cmath>

#include "gpu/barriers.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"
#include "grid/neighbor_grid.h"
#include "sim/boundary.h"
#include "sim/scene.h"

namespace aquaform {

namespace {
uint32_t force_groups(uint32_t count) { return (count + PROBE_FORCE_WORKGROUP - 1) / PROBE_FORCE_WORKGROUP; }
}  // namespace

double gauge_height(const std::vector<float>& samples, float lowest_y, float spacing, float floor_y) {
    size_t k = 0;
    while (k < samples.size() && samples[k] == PROBE_IN_SOLID) ++k;  // standing on a solid's top
    if (k == samples.size() || samples[k] < 0.5f) return 0.0;
    for (; k + 1 < samples.size(); ++k) {
        if (samples[k + 1] >= 0.5f) continue;
        // The column's top: where the fraction crosses a half between samples k and k + 1.
        const float a = samples[k], b = std::max(samples[k + 1], 0.0f);
        const double t = (a - 0.5) / std::max(1e-6, double(a - b));
        return lowest_y + spacing * (double(k) + t) - floor_y;
    }
    return lowest_y + spacing * double(samples.size() - 1) - floor_y;
}

ProbeRecorder::ProbeRecorder(gpu::Context& ctx, const Scene& scene, const std::vector<std::string>& solid_names,
                             uint32_t max_steps)
    : ctx_(&ctx),
      spec_(scene.probes.value_or(ProbeSpec{})),
      solid_names_(solid_names),
      max_steps_(std::max(max_steps, 1u)),
      buffers_(ctx) {
    if (!spec_.forces) solid_names_.clear();
    floor_y_ = scene.domain.min.y;
    // Gauge samples every half spacing from a quarter spacing above the floor to the top (at most
    // PROBE_MAX_GAUGE_SAMPLES: a tall tank is sampled more coarsely).
    const float height = scene.domain.max.y - scene.domain.min.y;
    const float spacing = std::max(0.5f * scene.particle_spacing, height / float(PROBE_MAX_GAUGE_SAMPLES - 1));
    samples_per_gauge_ =
        spec_.gauges.empty() ? 0u : std::min<uint32_t>(PROBE_MAX_GAUGE_SAMPLES, uint32_t(height / spacing) + 1);
    for (size_t s = 0; s < spec_.sensors.size(); ++s)
        params_.sensors[s] = glm::vec4(spec_.sensors[s].position, 0.5f * spec_.sensors[s].size);
    for (size_t g = 0; g < spec_.gauges.size(); ++g)
        params_.gauges[g] =
            glm::vec4(spec_.gauges[g].x, floor_y_ + 0.25f * scene.particle_spacing, spec_.gauges[g].z, spacing);
    params_.counts = glm::uvec4(uint32_t(spec_.sensors.size()), uint32_t(spec_.gauges.size()), samples_per_gauge_,
                                uint32_t(solid_names_.size()));
    probe_params_ = &buffers_.add("sim.probes.params", sizeof(shader::ProbeParams));
    gpu::upload(ctx, *probe_params_, &params_, sizeof params_);
    const uint64_t per_step = spec_.sensors.size() + uint64_t(spec_.gauges.size()) * samples_per_gauge_;
    readings_ = &buffers_.add("sim.probes.readings", std::max<uint64_t>(per_step * max_steps_, 1) * sizeof(float),
                              gpu::MemoryUse::host);
    const uint64_t count = scene.particle_capacity();
    partials_ = &buffers_.add(
        "sim.probes.loads",
        std::max<uint64_t>(uint64_t(force_groups(uint32_t(count))) * solid_names_.size() * 2, 1) * sizeof(glm::vec4),
        gpu::MemoryUse::host);
    if (per_step) sample_ = gpu::ComputePass(ctx, {"sim/probe_sample.comp", 8, sizeof(shader::ProbePush)});
    if (!solid_names_.empty())
        forces_ = gpu::ComputePass(ctx, {"sim/probe_forces.comp", 6, sizeof(shader::ProbePush), PROBE_FORCE_WORKGROUP});
}

void ProbeRecorder::record_step(VkCommandBuffer cmd, uint32_t slot, double time_s, const gpu::Buffer& params,
                                const gpu::Buffer& x, const gpu::Buffer& pressure, const NeighborGrid& grid,
                                const gpu::Buffer& boundary_nodes, uint32_t count) {
    if (slot == 0) step_times_.clear(), loads_recorded_ = false;
    if (slot >= max_steps_) return;  // the solver never takes more steps than it was made for
    step_times_.push_back(time_s);
    const uint32_t readings = params_.counts.x + params_.counts.y * params_.counts.z;
    if (readings == 0) return;
    const shader::ProbePush push{slot, count, 0u, 0u};
    gpu::dispatch(*ctx_, cmd, sample_, readings, push,
                  {{"params", &params},
                   {"probes", probe_params_},
                   {"x", &x},
                   {"pressure", &pressure},
                   {"cell_rank", &grid.cell_rank()},
                   {"cell_start", &grid.cell_start()},
                   {"boundary_nodes", &boundary_nodes},
                   {"readings", readings_}});
}

void ProbeRecorder::record_step(VkCommandBuffer cmd, const StepState& fluid) {
    gpu::GpuScope s(fluid.timer, cmd, "sim_probes");
    record_step(cmd, fluid.step_in_frame, fluid.time, fluid.params, fluid.x, fluid.pressure, fluid.grid,
                fluid.boundary_nodes, fluid.count);
}

void ProbeRecorder::record_frame_end(VkCommandBuffer cmd, const StepState& fluid) {
    gpu::GpuScope s(fluid.timer, cmd, "sim_probes");
    record_loads(cmd, fluid.params, fluid.x, fluid.pressure, fluid.boundary_nodes, fluid.count,
                 fluid.boundary.centres(fluid.time));
}

void ProbeRecorder::record_loads(VkCommandBuffer cmd, const gpu::Buffer& params, const gpu::Buffer& x,
                                 const gpu::Buffer& pressure, const gpu::Buffer& boundary_nodes, uint32_t count,
                                 const std::vector<glm::vec3>& centres) {
    if (solid_names_.empty()) return;
    for (size_t o = 0; o < centres.size() && o < PBF_MAX_SOLIDS; ++o) params_.centres[o] = glm::vec4(centres[o], 0.0f);
    gpu::record_upload(*ctx_, cmd, *probe_params_, &params_, sizeof params_);
    const shader::ProbePush push{0u, count, 0u, 0u};
    gpu::dispatch(*ctx_, cmd, forces_, force_groups(count) * PROBE_FORCE_WORKGROUP, push,
                  {{"params", &params},
                   {"probes", probe_params_},
                   {"x", &x},
                   {"pressure", &pressure},
                   {"boundary_nodes", &boundary_nodes},
                   {"partials", partials_}});
    loads_recorded_ = true;
}

ProbeFrame ProbeRecorder::collect() {
    ProbeFrame frame;
    const float* r = static_cast<const float*>(readings_->mapped);
    const size_t sensors = spec_.sensors.size(), gauges = spec_.gauges.size();
    const size_t per_step = sensors + gauges * samples_per_gauge_;
    for (size_t slot = 0; slot < step_times_.size(); ++slot) {
        ProbeStep step;
        step.time_s = step_times_[slot];
        const float* at = r + slot * per_step;
        for (size_t s = 0; s < sensors; ++s) step.pressures.push_back(at[s]);
        for (size_t g = 0; g < gauges; ++g) {
            const std::vector<float> samples(at + sensors + g * samples_per_gauge_,
                                             at + sensors + (g + 1) * samples_per_gauge_);
            step.heights.push_back(gauge_height(samples, params_.gauges[g].y, params_.gauges[g].w, floor_y_));
        }
        frame.steps.push_back(std::move(step));
    }
    if (loads_recorded_) {
        const glm::vec4* p = static_cast<const glm::vec4*>(partials_->mapped);
        const size_t solids = solid_names_.size();
        const size_t groups = partials_->size / sizeof(glm::vec4) / std::max<size_t>(solids * 2, 1);
        for (size_t o = 0; o < solids; ++o) {
            SolidLoad load{solid_names_[o]};
            for (size_t g = 0; g < groups; ++g) {
                load.force += glm::dvec3(p[(g * solids + o) * 2]);
                load.torque += glm::dvec3(p[(g * solids + o) * 2 + 1]);
            }
            frame.loads.push_back(load);
        }
    }
    return frame;
}

}  // namespace aquaform
