// A CPU reference of the GPU solver: the same equations (the shared headers in
// shaders/shared/), the same pass order and the same neighbour rule (cells assigned from the
// predicted positions when the grid is built, queried around each particle's current cell).
// Only the order of floating-point sums differs, so GPU and CPU agree to rounding.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "shaders/shared/pbf_layout.h"

namespace aquaform {

struct CpuParticles {
    std::vector<glm::vec4> x;  ///< w: id
    std::vector<glm::vec4> v;  ///< w: tag
    std::vector<float> density;
};

struct ReferenceSettings {
    uint32_t iterations = 4;
    bool xsph = true;
    bool vorticity = false;
};

/// Advances `particles` by one solver step.
void reference_step(const shader::SimParams& params, const ReferenceSettings& settings, CpuParticles& particles);

/// Brute-force neighbour lists: every j != i with |x_i - x_j| < radius (O(n^2), for tests).
std::vector<std::vector<uint32_t>> brute_force_neighbors(const std::vector<glm::vec4>& positions, float radius);

}  // namespace aquaform
