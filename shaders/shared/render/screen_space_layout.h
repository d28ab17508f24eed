// Layout of the screen-space fluid renderer (render/screen_space.h): sphere-sprite depth
// filtered in screen space by one of three filters. Binding 0 of every filter pass is the
// ScreenSpaceParams block; the splat, normal and compose passes are the surface renderer's
// own and read its SurfaceParams (shared/render/surface_layout.h).
//
// Depth maps follow surface_layout.h: eye depth (along `forward`) as float bits, DEPTH_EMPTY
// where no sprite covers the pixel, row-major. Every filter keeps the set of empty pixels: it
// smooths the depth of covered pixels and never grows or shrinks the silhouette.
#ifndef AQUAFORM_SCREEN_SPACE_LAYOUT_H
#define AQUAFORM_SCREEN_SPACE_LAYOUT_H
#include "../core/compat.h"

// Filters (ScreenSpaceParams.filter).
#define SS_FILTER_BILATERAL 0u       // Green 2010
#define SS_FILTER_CURVATURE_FLOW 1u  // van der Laan, Green, Sainz 2009
#define SS_FILTER_NARROW_RANGE 2u    // Truong, Yuksel 2018

AF_BEGIN

struct ScreenSpaceParams {
    uvec4 screen;           ///< x: width, y: height, z: filter (SS_FILTER_*), w: max kernel half-width [px]
    float pixel_scale;      ///< px per unit tangent: a length L at eye depth d spans L pixel_scale / d px
    float particle_radius;  ///< [m]
    float sigma;            ///< spatial sigma of the bilateral / narrow-range kernel [m], projected per pixel
    float depth_sigma;      ///< bilateral: range sigma [m]
    float range;            ///< narrow range: half-width delta of the accepted depth range [m]
    float clamp_offset;     ///< narrow range: mu, far samples are clamped to centre + mu [m]
    float flow_step;        ///< curvature flow: kappa, diffusion per iteration at small slopes [px^2]
    float flow_jump;        ///< curvature flow: depth step to a neighbour that counts as a discontinuity [m]
    float cx;               ///< curvature flow: C_x = 2 tan(fov_x / 2) / width (pixel size per metre of depth)
    float cy;               ///< C_y = 2 tan(fov_y / 2) / height
    float pad0;
    float pad1;
};

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::ScreenSpaceParams) == 16 + 12 * 4);
#endif

#endif
