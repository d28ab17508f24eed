// A CPU reference of the GPU solver, either pressure solve: the same equations (the shared
// headers in shaders/shared/), the same pass order and the same neighbour rule (neighbours
// within h of the predicted positions, or for DFSPH of the step's start positions, found once
// per step and kept through the iterations). Only the
// order of floating-point sums differs, so GPU and CPU agree to rounding. (One case differs
// by design: a GPU cell holding more than 16 particles, twice the rest density, treats its
// extra particles as candidates each pass; the test scenes never reach it.)
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "shaders/shared/sim/pbf_boundary.h"
#include "sim/scene_basics.h"

namespace aquaform {

struct CpuParticles {
    std::vector<glm::vec4> x;  ///< w: id
    std::vector<glm::vec4> v;  ///< w: tag
    std::vector<float> density;
    std::vector<glm::vec4> carry;  ///< DFSPH's sums of k carried to the next step (x, y); empty: zeros
};

struct ReferenceSettings {
    PressureMethod method = PressureMethod::pbf;
    uint32_t divergence_iterations = 2;  ///< DFSPH's
    uint32_t iterations = 4;
    bool xsph = true;
    bool vorticity = false;
};

/// Advances `particles` by one solver step. `boundary_nodes`: the solids' maps the params'
/// table points into (sim/boundary.h, Boundary::nodes); empty when the table is.
void reference_step(const shader::SimParams& params, const ReferenceSettings& settings, CpuParticles& particles,
                    const std::vector<glm::vec4>& boundary_nodes = {});

/// Brute-force neighbour lists: every j != i with |x_i - x_j| < radius (O(n^2), for tests).
std::vector<std::vector<uint32_t>> brute_force_neighbors(const std::vector<glm::vec4>& positions, float radius);

}  // namespace aquaform
