// A density volume: the renderer's field phi (render_kernels.h) sampled on a regular lattice,
// with the iso value the renderer draws. Marching-cubes meshes and OpenVDB exports are made
// from it, so a mesh or a volume shows the surface the frames show.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace aquaform {

struct DensityVolume {
    glm::vec3 origin{0.0f};  ///< world position of sample (0, 0, 0) [m]
    float voxel = 0.0f;      ///< lattice spacing [m]
    glm::uvec3 dims{0u};     ///< samples along x, y, z
    float iso = 0.0f;        ///< the renderer's iso value sigma: the surface is phi = iso
    /// phi at origin + voxel * (i, j, k), stored at index(i, j, k) (x fastest).
    std::vector<float> values;

    size_t index(uint32_t i, uint32_t j, uint32_t k) const { return i + size_t(dims.x) * (j + size_t(dims.y) * k); }
    float at(uint32_t i, uint32_t j, uint32_t k) const { return values[index(i, j, k)]; }
    glm::vec3 position(uint32_t i, uint32_t j, uint32_t k) const { return origin + voxel * glm::vec3(i, j, k); }
    size_t sample_count() const { return size_t(dims.x) * dims.y * dims.z; }
};

}  // namespace aquaform
