// The tank every renderer draws around the fluid (common/environment.glsl): the domain's floor
// as checker tiles, its four side walls as glass panels in a dark frame (the top stays open),
// the scene's static boxes as solid blocks and its mesh obstacles as solids. It is the same in every method, so it cancels
// out of every comparison with the reference; it only changes what a picture shows.
#ifndef AQUAFORM_TANK_LAYOUT_H
#define AQUAFORM_TANK_LAYOUT_H
#include "../core/compat.h"
#include "solid_layout.h"

#define TANK_MAX_BOXES 16  // the solver's PBF_MAX_SOLIDS (sim/pbf_params.cpp asserts they agree)

// TankParams.counts.y
#define TANK_GLASS_WALLS 1u  // draw the side walls (off: the open floor of earlier versions)

AF_BEGIN

struct TankParams {
    uvec4 counts;  ///< x: static boxes; y: TANK_* flags; z: mesh obstacles (solids[]); w: unused
    vec4 frame;    ///< x: width of the walls' frame [m]; yzw: unused
    vec4 box_min[TANK_MAX_BOXES];  ///< xyz [m]
    vec4 box_max[TANK_MAX_BOXES];
    /// The mesh obstacles as the solver has them at this frame (sim/boundary.h): traced through
    /// their distance maps, whose nodes the including shader binds as solid_nodes.
    SolidParams solids[TANK_MAX_BOXES];
};

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::TankParams) == 2 * 16 + 2 * 16 * 16 + 16 * 5 * 16);
#endif

#endif
