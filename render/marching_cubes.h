// Marching cubes (Lorensen and Cline 1987) over a DensityVolume: the case table, and the CPU
// reference of the GPU mesher (render/surface_mesher.h). Both follow the lattice conventions of
// shaders/shared/render/mesh_layout.h, so the CPU and GPU meshes agree index for index.
//
// The table is generated here rather than typed in. For each of the 256 inside/outside patterns
// of a cell's corners, the surface's outline is traced on each of the six faces (a segment
// between the two crossing edges of a face, or two segments on a face with four), the segments
// are chained into closed loops (each crossing edge lies on exactly two faces), and each loop is
// triangulated as a fan from its first vertex.
//
// Choice (the ambiguous faces, which the papers leave open): a face whose two inside corners sit
// on a diagonal has its inside corners kept apart, each cut off by its own segment. The rule
// looks at the face alone, so the two cells that share a face draw the same segments on it, in
// opposite directions: the mesh has no cracks and is consistently oriented, and it is closed
// wherever the fluid does not reach the lattice's border (the lattice is padded so that it never
// does). The classic table's holes came from resolving a face one way in one cell and the other
// way in its neighbour. The price: two fluid regions that touch a face only diagonally are drawn
// apart where the field's bilinear saddle on that face is above iso (the asymptotic decider would
// join them): a difference within one voxel.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "render/density_volume.h"
#include "shaders/shared/render/mesh_layout.h"

namespace aquaform {

/// A welded triangle mesh of the fluid's surface.
struct SurfaceMesh {
    std::vector<glm::vec3> vertices;    ///< [m]; one per lattice edge that crosses the surface
    std::vector<glm::vec3> normals;     ///< unit, outward: -grad phi (the lattice's central differences)
    std::vector<glm::uvec3> triangles;  ///< counter-clockwise seen from outside the fluid
    // The lattice it came from.
    glm::vec3 origin{0.0f};
    float voxel = 0.0f;
    glm::uvec3 dims{0u};
};

/// The case table: row c (MESH_TABLE_ROW entries) holds, for corner pattern c (bit k set where
/// corner k is inside), the triangle count and then three cell edges per triangle.
using MarchingCubesTable = std::array<uint32_t, 256 * MESH_TABLE_ROW>;
const MarchingCubesTable& marching_cubes_table();

/// The CPU reference: the mesh of phi = iso over `volume`, with the GPU's vertex numbering
/// (per sample, its +x, +y, +z edges) and triangle order (per cell, the table's order).
SurfaceMesh marching_cubes(const DensityVolume& volume);

}  // namespace aquaform
