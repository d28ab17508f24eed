// A solid's place in the GPU tables, seen alike by the solver (shared/sim/pbf_layout.h's
// SimParams.solids, shared/sim/pbf_boundary.h) and the renderers (shared/solids/tank_layout.h's
// TankParams.solids): the frame and grid of its maps (SolidParams) and how the maps' nodes
// lie in the node buffer (geometry/boundary_map.h makes the maps, sim/boundary.h places them).
// Sampling the maps is shared/solids/solid_map.h's.
#ifndef AQUAFORM_SOLID_LAYOUT_H
#define AQUAFORM_SOLID_LAYOUT_H
#include "../core/compat.h"

/// Interleaved node data of the solids' maps (boundary_nodes): per node, these two vec4s.
#define PBF_NODE_DISTANCE 0u  ///< xyz: unit normal out of the solid (local frame); w: signed distance [m]
#define PBF_NODE_DENSITY 1u   ///< xyz: grad m (local frame) [1/m]; w: m = the solid's rho / rho0
#define PBF_NODE_VEC4S 2u

AF_BEGIN

/// One solid of the solver (pbf_boundary.h: a static box or a mesh obstacle): its maps, made in
/// its own frame, and where that frame stands now. The frame is rigid (rotation and translation),
/// so distances and densities sampled in it hold in the world.
struct SolidParams {
    vec4 to_local[3];  ///< rows of the world-to-local map: local = (dot(row, (p, 1)) for each row)
    vec4 map_origin;   ///< xyz: the first node (local) [m]; w: node spacing [m]
    uvec4 map_dims;    ///< xyz: nodes along each axis; w: the first node's index in boundary_nodes
};

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::SolidParams) == 5 * 16);
#endif

#endif
