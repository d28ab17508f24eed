#include "sim/flow_schedule.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "sim/scene.h"

namespace aquaform {

FlowSchedule::FlowSchedule(const Scene& scene, uint32_t first_id)
    : next_id_(first_id), first_tag_(uint32_t(scene.fluid_blocks.size())), hold_depth_(scene.kernel_radius()) {
    for (const EmitterSpec& spec : scene.emitters) {
        Nozzle n{spec, nozzle_lattice(spec, scene.particle_spacing), uint32_t(lattice_.size())};
        lattice_.insert(lattice_.end(), n.lattice.offsets.begin(), n.lattice.offsets.end());
        nozzles_.push_back(std::move(n));
    }
}

float FlowSchedule::max_speed(double t0, double t1) const {
    float top = 0.0f;
    for (const Nozzle& n : nozzles_) top = std::max(top, n.spec.max_speed(t0, t1));
    return top;
}

shader::FlowLayer FlowSchedule::layer_of(const Nozzle& n, size_t index, uint64_t k, uint32_t first_id, double t) const {
    const EmitterSpec& e = n.spec;
    const double along = n.travelled(t) - double(k) * double(n.lattice.layer_spacing);
    // A layer that left in the step the nozzle shut keeps the speed it left with.
    const float speed = e.speed_at(std::min(t, std::nextafter(e.stop, 0.0)));
    const auto [across, up] = e.across_axes();
    shader::FlowLayer layer{};
    layer.origin = glm::vec4(glm::dvec3(e.position) + along * glm::dvec3(e.direction), 0.0);
    layer.velocity = glm::vec4(speed * e.direction, float(tag_of(index)));
    layer.across = glm::vec4(across, 0.0f);
    layer.up = glm::vec4(up, 0.0f);
    layer.ids = glm::uvec4(first_id, n.first_offset, uint32_t(n.lattice.offsets.size()), 0u);
    return layer;
}

void FlowSchedule::steer(size_t nozzle, const glm::vec3& position, const glm::vec3& direction) {
    Nozzle& n = nozzles_.at(nozzle);
    n.spec.position = position;
    n.spec.direction = glm::normalize(direction);
    n.recent.clear();
}

void FlowSchedule::set_open(size_t nozzle, bool open) {
    Nozzle& n = nozzles_.at(nozzle);
    if (open == n.open) return;
    if (open)
        n.shut_distance += n.spec.distance_at(last_t_) - n.shut_at;
    else
        n.shut_at = n.spec.distance_at(last_t_);
    n.open = open;
    n.recent.clear();
}

FlowStep FlowSchedule::plan_step(double t1, uint32_t alive, uint32_t capacity) {
    last_t_ = t1;
    FlowStep step;
    std::vector<shader::FlowLayer> held;
    uint32_t slot = alive;
    step.min_held_id = std::numeric_limits<uint32_t>::max();
    for (size_t i = 0; i < nozzles_.size(); ++i) {
        Nozzle& n = nozzles_[i];
        const EmitterSpec& e = n.spec;
        const double spacing = n.lattice.layer_spacing;
        if (!n.open) continue;
        const uint64_t due =
            t1 >= e.start && e.start < e.stop ? uint64_t(std::floor(n.travelled(t1) / spacing)) + 1 : 0;
        const uint32_t points = uint32_t(n.lattice.offsets.size());
        for (uint64_t k = n.layers_due; k < due; ++k) {
            if (uint64_t(slot) + points > capacity || next_id_ + points > kMaxSceneParticles + 1) {
                // Full, or out of ids (kMaxSceneParticles is the last id the solver can index): the
                // layer is skipped, counted and said by the run.
                step.not_emitted += points;
                continue;
            }
            shader::FlowLayer layer = layer_of(n, i, k, uint32_t(next_id_), t1);
            layer.ids.w = slot;
            step.layers.push_back(layer);
            ++step.emitted_layers;
            step.emitted += points;
            slot += points;
            n.recent.push_back({k, uint32_t(next_id_)});
            next_id_ += points;
        }
        n.layers_due = std::max(n.layers_due, due);
        // Held while the nozzle runs and within hold_depth of it; the oldest leave first.
        if (e.speed_at(t1) <= 0.0f) n.recent.clear();
        const double travelled = n.travelled(t1);
        while (!n.recent.empty() && travelled - double(n.recent.front().layer) * spacing >= hold_depth_)
            n.recent.pop_front();
        for (const Emitted& r : n.recent) {
            held.push_back(layer_of(n, i, r.layer, r.first_id, t1));
            step.min_held_id = std::min(step.min_held_id, r.first_id);
        }
    }
    step.layers.insert(step.layers.end(), held.begin(), held.end());
    if (step.layers.size() > FLOW_MAX_LAYERS)
        throw internal_failure("FlowSchedule: a step's " + std::to_string(step.layers.size()) +
                               " nozzle layers overflow the table of " + std::to_string(FLOW_MAX_LAYERS) +
                               " (the time-step rule keeps a step's layers few)");
    return step;
}

}  // namespace aquaform
