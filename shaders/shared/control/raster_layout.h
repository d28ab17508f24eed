// Layout of the rasterising control-particle placement, method (c) of Karpati et al. section 3.2
// (control/raster_placement.h, shaders/control/raster_layers.comp and raster_fill.comp).
//
// Pixels are lattice columns: an orthographic view along +z whose pixel (px, py) is the ray
// x = origin.x + (rect.x + px) * spacing, y = origin.y + (rect.y + py) * spacing. Instead of K
// graphics passes of depth peeling, one geometry pass captures every depth layer of a pixel in a
// fixed-capacity list, k-buffer style (Bavoil et al. 2007): a per-pixel atomic counter hands out
// slots, and a counter past RASTER_MAX_LAYERS marks the pixel as overflowed (nothing is written
// past the capacity). Layers are stored slot-major, layers[slot * pixels + pixel], so that the fill
// pass (one thread per pixel) reads consecutive pixels from consecutive addresses.
//
// The fill runs twice (raster_fill.comp): a count pass writes each column's point count into
// column_offsets (pixels + 1 entries), an exclusive prefix sum turns the counts into offsets (the
// last entry the total) and an emit pass writes each column's points from its offset on, so the
// point list is in column order, the same from run to run (no atomic hands out output slots).
//
// A layer is (z, step): step = +1 where the ray enters the mesh through a face whose normal faces
// -z (towards the ray's origin at z = -inf), -1 where it leaves through a face whose normal faces
// +z. The winding count after a layer is the sum of the steps so far; |winding| > 0 is inside, so
// meshes with inward-facing normals (winding -1 inside) give the same points.
#ifndef AQUAFORM_RASTER_LAYOUT_H
#define AQUAFORM_RASTER_LAYOUT_H
#include "../core/compat.h"

/// Depth layers one lattice column can hold (a convex mesh needs 2, a torus seen edge-on 4).
#define RASTER_MAX_LAYERS 16u
#define RASTER_LAYERS_WORKGROUP 64
#define RASTER_FILL_WORKGROUP 64

// Indices into the counters buffer, zeroed before every placement.
#define RASTER_COUNTER_POINTS 0      // points wanted, the scan's total (may exceed max_points: the excess is dropped)
#define RASTER_COUNTER_OVERFLOWED 1  // pixels with more than RASTER_MAX_LAYERS layers (left empty)
#define RASTER_COUNTER_OPEN 2        // pixels whose winding does not return to 0 (left empty)
#define RASTER_COUNTERS 4

AF_BEGIN

/// Push constants of the layer, count and emit passes.
struct RasterPush {
    vec4 origin_spacing;  ///< xyz: lattice origin; w: spacing (points at origin + spacing * (i, j, k))
    ivec4 pixel_rect;     ///< xy: lattice indices (i, j) of pixel 0; z: width, w: height in pixels
    uint triangle_count;
    uint max_points;      ///< capacity of the point buffer
    float w_value;        ///< written into every point's w (e.g. a control-set index)
    uint pad0;
};

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::RasterPush) == 48);
#endif

#endif
