// The surface renderer's field computed on the host by brute force, for tests that check what
// the GPU passes find against it.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "shaders/shared/render_kernels.h"
#include "shaders/shared/surface_layout.h"

namespace aquaform::testing {

/// phi(x) = V sum_j W(x - x_j, r) over every particle.
inline float cpu_field(const shader::SurfaceParams& p, const std::vector<glm::vec4>& particles, const glm::vec3& x) {
    float sum = 0.0f;
    for (const auto& q : particles) {
        const glm::vec3 d = x - glm::vec3(q);
        sum += shader::cubic_kernel(glm::dot(d, d), p.inv_radius, p.kernel_coeff);
    }
    return p.volume * sum;
}

}  // namespace aquaform::testing
