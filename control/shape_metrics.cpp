#include "control/shape_metrics.h"

#include <cmath>
#include <unordered_map>

#include "shaders/shared/control/control_layout.h"
#include "shaders/shared/core/sph_kernels.h"

namespace aquaform::control {

glm::ivec3 VoxelLattice::index_of(const glm::vec3& p) const { return glm::ivec3(glm::floor((p - origin) / spacing)); }

glm::vec3 VoxelLattice::centre(const glm::ivec3& index) const { return origin + spacing * (glm::vec3(index) + 0.5f); }

uint64_t VoxelLattice::key(const glm::ivec3& index) {
    constexpr int64_t kOffset = 1 << 20;
    auto axis = [](int v) { return uint64_t(int64_t(v) + kOffset) & 0x1fffffu; };
    return axis(index.x) | axis(index.y) << 21 | axis(index.z) << 42;
}

namespace {
bool controlled(const FluidField& fluid, size_t i) {
    return (fluid.tag_mask & shader::control_tag_bit((*fluid.v)[i].w)) != 0u;
}
}  // namespace

std::unordered_set<uint64_t> fluid_voxels(const FluidField& fluid, const VoxelLattice& lattice) {
    const float h = fluid.kernel_radius, h2 = h * h;
    const float coeff = shader::poly6_coefficient(h);
    const int reach = int(std::ceil(h / lattice.spacing));
    std::unordered_map<uint64_t, float> density;
    for (size_t i = 0; i < fluid.x->size(); ++i) {
        if (!controlled(fluid, i)) continue;
        const glm::vec3 p((*fluid.x)[i]);
        const glm::ivec3 c = lattice.index_of(p);
        for (int dz = -reach; dz <= reach; ++dz)
            for (int dy = -reach; dy <= reach; ++dy)
                for (int dx = -reach; dx <= reach; ++dx) {
                    const glm::ivec3 n = c + glm::ivec3(dx, dy, dz);
                    const glm::vec3 d = lattice.centre(n) - p;
                    const float r2 = glm::dot(d, d);
                    if (r2 < h2) density[VoxelLattice::key(n)] += fluid.mass * shader::poly6(r2, h2, coeff);
                }
    }
    std::unordered_set<uint64_t> occupied;
    for (const auto& [key, rho] : density)
        if (rho >= 0.5f * fluid.rest_density) occupied.insert(key);
    return occupied;
}

ShapeMetrics shape_metrics(const FluidField& fluid, const VoxelLattice& lattice,
                           const std::unordered_set<uint64_t>& shape_voxels) {
    ShapeMetrics m;
    const auto occupied = fluid_voxels(fluid, lattice);
    size_t both = 0;
    for (uint64_t key : occupied) both += shape_voxels.count(key);
    m.shape_voxels = shape_voxels.size();
    m.fluid_voxels = occupied.size();
    const size_t either = occupied.size() + shape_voxels.size() - both;
    m.iou = either ? double(both) / double(either) : 0.0;
    m.fill_fraction = shape_voxels.empty() ? 0.0 : double(both) / double(shape_voxels.size());
    size_t total = 0, outside = 0;
    for (size_t i = 0; i < fluid.x->size(); ++i) {
        if (!controlled(fluid, i)) continue;
        ++total;
        outside += !shape_voxels.count(VoxelLattice::key(lattice.index_of(glm::vec3((*fluid.x)[i]))));
    }
    m.outside_fraction = total ? double(outside) / double(total) : 0.0;
    return m;
}

std::unordered_set<uint64_t> voxel_keys(const VoxelLattice& lattice, const std::vector<glm::vec3>& centres) {
    std::unordered_set<uint64_t> keys;
    for (const glm::vec3& c : centres) keys.insert(VoxelLattice::key(lattice.index_of(c)));
    return keys;
}

}  // namespace aquaform::control
