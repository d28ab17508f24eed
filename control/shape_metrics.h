// How well the fluid takes a control shape, per frame (the columns of stats.csv): voxels of one
// particle spacing, fluid voxels against voxels inside the mesh.
#pragma once

#include <cstdint>
#include <unordered_set>
#include <vector>

#include <glm/glm.hpp>

namespace aquaform::control {

/// The voxel lattice the metrics use: voxel (i, j, k) is the cube origin + spacing * [i, i+1) ...
/// Its centres, origin + spacing * (index + 0.5), are where the inside test is taken.
struct VoxelLattice {
    glm::vec3 origin{0.0f};
    float spacing = 1.0f;

    glm::ivec3 index_of(const glm::vec3& p) const;
    glm::vec3 centre(const glm::ivec3& index) const;
    /// A 64-bit key of an index (21 bits per axis, offset so negative indices work).
    static uint64_t key(const glm::ivec3& index);
};

/// Inputs of the fluid side: particles (x, and v.w = tag) and the SPH constants that turn them
/// into a density field.
struct FluidField {
    const std::vector<glm::vec4>* x = nullptr;
    const std::vector<glm::vec4>* v = nullptr;  ///< w: tag
    uint32_t tag_mask = ~0u;                    ///< which tags count as the controlled fluid
    float kernel_radius = 0.0f;                 ///< h
    float mass = 0.0f;
    float rest_density = 1000.0f;
};

struct ShapeMetrics {
    double iou = 0.0;               ///< |fluid ∩ shape| / |fluid ∪ shape|
    double fill_fraction = 0.0;     ///< |fluid ∩ shape| / |shape|
    double outside_fraction = 0.0;  ///< controlled particles whose voxel is outside the shape
    size_t shape_voxels = 0;
    size_t fluid_voxels = 0;
};

/// Voxels occupied by the controlled fluid: those whose centre has a poly6 density of at least
/// half the rest density. Counting voxels that hold a particle instead would leave holes in a
/// perfectly filled shape (a disordered fluid at one particle per voxel leaves about a third of
/// them empty), and the half-density level is where the fluid's surface lies.
std::unordered_set<uint64_t> fluid_voxels(const FluidField& fluid, const VoxelLattice& lattice);

ShapeMetrics shape_metrics(const FluidField& fluid, const VoxelLattice& lattice,
                           const std::unordered_set<uint64_t>& shape_voxels);

/// Keys of the voxels whose centres are the given points (points on the lattice's centres, such
/// as placement on that lattice produces).
std::unordered_set<uint64_t> voxel_keys(const VoxelLattice& lattice, const std::vector<glm::vec3>& centres);

}  // namespace aquaform::control
