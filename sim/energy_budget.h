// Where a step's mechanical energy goes, pass by pass (docs/solver.md "The energy budget"). An
// EnergyBudget watches a pressure solve (PressureSolve::watch): after each of its passes the
// particles' x, v and p are copied into host memory in the same submission, and after the frame
// each copy's kinetic and potential energy is summed in double precision. Between the prediction
// and the velocity update the state is the prediction: the particles stand at p, moving at
// (p - x) / dt, where the step would leave them if it ended there.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/buffer.h"
#include "sim/pressure_solve.h"

namespace aquaform {

namespace gpu {
class Context;
}

/// The fluid's energy after one pass of one step.
struct PassEnergy {
    uint32_t step = 0;                      ///< within the frame, from 0
    std::string pass;                       ///< "start" (the step's x and v), then its passes' names
    double kinetic = 0.0, potential = 0.0;  ///< [J]; potential from y = 0 against gravity
    double total() const { return kinetic + potential; }
};

class EnergyBudget : public PassObserver {
public:
    /// Room for `max_records` copies of `particles` particles (the passes a step is watched after,
    /// times the steps of a frame).
    EnergyBudget(gpu::Context& ctx, uint32_t particles, uint32_t max_records);
    ~EnergyBudget() override;
    EnergyBudget(const EnergyBudget&) = delete;
    EnergyBudget& operator=(const EnergyBudget&) = delete;

    /// Records the copies into the next free room ("start" begins a step); past `max_records` in a
    /// frame it throws Failure (a bug of the caller's sizing).
    void after(VkCommandBuffer cmd, const char* pass, const FluidArrays& fluid, PassState state) override;

    /// The frame's records, once its submission has completed: each particle of mass `mass` in
    /// `gravity`, the frame's steps `dt` long. Clears them for the next frame.
    std::vector<PassEnergy> collect(double mass, const glm::dvec3& gravity, double dt);

private:
    struct Record {
        uint32_t step;
        std::string pass;
        PassState state;
        uint32_t count;
    };
    gpu::Context* ctx_;
    uint32_t particles_;
    std::vector<gpu::Buffer> copies_;  ///< per record: x, v, p one after another
    std::vector<Record> records_;
};

}  // namespace aquaform
