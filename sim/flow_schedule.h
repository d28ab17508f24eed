// The nozzles' layers, step by step, on the host (the GPU side is sim/fluid_flow.h). A nozzle's
// water has travelled D(t) = the integral of its speed out of it by t; layer k leaves it when D
// passes k times its layer spacing and stands D(t) - k layer spacings out at t. So the layers a
// step emits and where every layer stands are a function of time alone: two runs emit the same
// particles at the same places, and nothing is read back from the GPU.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "shaders/shared/sim/flow_layout.h"
#include "sim/flow_spec.h"

namespace aquaform {

struct Scene;

/// What one step does with the nozzles.
struct FlowStep {
    /// The table of the step (shader::FlowLayer): first the layers it emits (ids.w: their slots
    /// from the alive count on), then the layers held on the nozzles at its end.
    std::vector<shader::FlowLayer> layers;
    uint32_t emitted_layers = 0;
    uint32_t emitted = 0;      ///< particles emitted
    uint32_t not_emitted = 0;  ///< particles of layers that did not fit the capacity (or the ids)
    uint32_t min_held_id = 0;  ///< the smallest id of a held particle
};

class FlowSchedule {
public:
    /// `first_id`: the id of the first emitted particle (the scene's start particles take those below).
    FlowSchedule(const Scene& scene, uint32_t first_id);

    bool empty() const { return nozzles_.empty(); }
    /// The step that ends at t1 (the layers due by then and not yet emitted are its), with `alive`
    /// particles in slots for `capacity`. Steps are planned in order.
    FlowStep plan_step(double t1, uint32_t alive, uint32_t capacity);
    /// The largest nozzle speed over [t0, t1] (the time-step rule counts it).
    float max_speed(double t0, double t1) const;
    /// Every nozzle's lattice offsets, one after the other (FlowLayer::ids.y indexes them).
    const std::vector<glm::vec2>& lattice() const { return lattice_; }
    /// The tag of a nozzle's particles: after the fluid blocks'.
    uint32_t tag_of(size_t emitter) const { return first_tag_ + uint32_t(emitter); }
    /// A held layer stands within this of its nozzle (the kernel radius: the first free layer has
    /// a full neighbourhood of nozzle water behind it).
    float hold_depth() const { return hold_depth_; }

    /// Live changes (the viewer's nozzle tools), from the next planned step on. Moving or aiming
    /// a nozzle lets its held layers go where they stand (they were held on the old pose) and
    /// starts the hold anew; a nozzle shut emits nothing and holds nothing, and when opened again
    /// goes on from the layer it had begun, as if the shut time had not been.
    void steer(size_t nozzle, const glm::vec3& position, const glm::vec3& direction);
    void set_open(size_t nozzle, bool open);
    bool is_open(size_t nozzle) const { return nozzles_[nozzle].open; }

private:
    struct Emitted {
        uint64_t layer;  ///< k
        uint32_t first_id;
    };
    struct Nozzle {
        EmitterSpec spec;
        NozzleLattice lattice;
        uint32_t first_offset = 0;   ///< in lattice_
        uint64_t layers_due = 0;     ///< layers whose time has come (emitted or not)
        std::deque<Emitted> recent;  ///< emitted layers that may still be held
        bool open = true;
        /// The distance the nozzle's water did not travel while it was shut: its layers go by
        /// travelled(t) = spec.distance_at(t) - shut_distance.
        double shut_distance = 0.0;
        double shut_at = 0.0;  ///< spec.distance_at when it was last shut
        double travelled(double t) const { return spec.distance_at(t) - shut_distance; }
    };
    shader::FlowLayer layer_of(const Nozzle& n, size_t index, uint64_t k, uint32_t first_id, double t) const;

    std::vector<Nozzle> nozzles_;
    std::vector<glm::vec2> lattice_;
    uint64_t next_id_;
    double last_t_ = 0.0;  ///< the end of the last planned step
    uint32_t first_tag_;
    float hold_depth_;
};

}  // namespace aquaform
