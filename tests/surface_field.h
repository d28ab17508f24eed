// The surface renderer's field computed on the host by brute force, for tests that check what
// the GPU passes find against it.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "render/surface_renderer.h"
#include "shaders/shared/render/anisotropy.h"
#include "shaders/shared/render/render_kernels.h"
#include "shaders/shared/render/surface_layout.h"

namespace aquaform::testing {

/// What the field of the last frame a renderer drew is made of: the particles themselves (the
/// isotropic surface; `shapes` empty), or the anisotropic surface's kernels as the GPU made them.
struct FieldKernels {
    std::vector<glm::vec4> centres;
    std::vector<glm::vec4> shapes;  ///< 3 rows of G per kernel, row 0's w = |det G|
};

inline FieldKernels field_kernels(SurfaceRenderer& renderer, const std::vector<glm::vec4>& particles) {
    if (!(renderer.params().flags & SURFACE_ANISOTROPIC_FIELD)) return {particles, {}};
    return {renderer.kernel_centres(), renderer.kernel_shapes()};
}

/// The kernel j's G (the rows as the GPU stores them).
inline glm::mat3 kernel_shape(const FieldKernels& k, size_t j) {
    return glm::transpose(
        glm::mat3(glm::vec3(k.shapes[3 * j]), glm::vec3(k.shapes[3 * j + 1]), glm::vec3(k.shapes[3 * j + 2])));
}

/// phi(x) = V sum_j W(x - x_j, r) over every particle, or V sum_j W(x - x_bar_j, G_j) over
/// every kernel.
inline float cpu_field(const shader::SurfaceParams& p, const FieldKernels& kernels, const glm::vec3& x) {
    float sum = 0.0f;
    for (size_t j = 0; j < kernels.centres.size(); ++j) {
        const glm::vec3 d = x - glm::vec3(kernels.centres[j]);
        sum += kernels.shapes.empty()
                   ? shader::cubic_kernel(glm::dot(d, d), p.inv_radius, p.kernel_coeff)
                   : shader::anisotropic_kernel(d, kernel_shape(kernels, j), kernels.shapes[3 * j].w);
    }
    return p.volume * sum;
}

inline float cpu_field(const shader::SurfaceParams& p, const std::vector<glm::vec4>& particles, const glm::vec3& x) {
    return cpu_field(p, FieldKernels{particles, {}}, x);
}

}  // namespace aquaform::testing
