#version 460
#extension GL_GOOGLE_include_directive : require
// Placement method (c), after raster_layers.comp: one thread per lattice column sorts the column's
// depth layers, walks them with a winding count and finds the lattice points strictly inside every
// run where the winding is non-zero (see shared/control/raster_layout.h). Two pipelines of this
// shader, told apart by kEmit, with an exclusive prefix sum over the columns between them:
//   count (kEmit false): column_offsets[pixel] = the column's point count (the buffer is zeroed
//                        before, so empty, overflowed and open columns stay 0);
//   scan (grid/prefix_sum.h): column_offsets becomes the exclusive sum, entry `pixels` the total;
//   emit (kEmit true):   writes the column's points from column_offsets[pixel] on.
// The points therefore come out in column order (pixel = py * width + px, then z up), a function
// of the input alone rather than of the order the device ran its threads in: sums over the point
// list (the control force) are then the same from run to run.
#include "shared/control/raster_layout.h"

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const bool kEmit = false;
layout(std430, binding = 0) readonly buffer LayerCount { uint layer_count[]; };
layout(std430, binding = 1) readonly buffer Layers { vec2 layers[]; };  // (z, step), slot-major
layout(std430, binding = 2) buffer Counters { uint counters[]; };      // RASTER_COUNTER_*, zeroed before
layout(std430, binding = 3) writeonly buffer Points { vec4 points[]; };
layout(std430, binding = 4) buffer ColumnOffsets { uint column_offsets[]; };  // pixels + 1 entries
layout(push_constant) uniform Push { RasterPush pc; };

vec2 layer[RASTER_MAX_LAYERS];

float lattice(int k, int axis) {
    // The same expression as the CPU lattice (placement.cpp), without fma.
    precise float x = pc.origin_spacing[axis] + float(k) * pc.origin_spacing.w;
    return x;
}

// Lattice indices k with z0 < z(k) < z1, keeping clear of the surface by a 1e-4 spacing margin:
// a lattice point on the surface (a mesh vertex on the lattice, common with analytic meshes) is
// not inside, whatever the rounding of the interpolated depth (which differs, for one, between a
// mesh and its flipped copy). The division can round across an integer, so each end is checked
// against the lattice position itself.
ivec2 inside_range(float z0, float z1) {
    float o = pc.origin_spacing.z, spacing = pc.origin_spacing.w;
    z0 += 1e-4 * spacing;
    z1 -= 1e-4 * spacing;
    int k0 = int(ceil((z0 - o) / spacing));
    if (lattice(k0 - 1, 2) > z0) --k0;
    if (lattice(k0, 2) <= z0) ++k0;
    int k1 = int(floor((z1 - o) / spacing));
    if (lattice(k1 + 1, 2) < z1) ++k1;
    if (lattice(k1, 2) >= z1) --k1;
    return ivec2(k0, k1);
}

// Walks the sorted layers; consecutive non-zero intervals merge into one run, so overlapping
// or self-intersecting parts give their union. Counts the run points, and writes them from
// `base` on when `emit` (never past max_points). Returns the count; `closed` is false when
// the winding does not come back to 0 after the last layer.
uint walk(uint n, bool emit, uint base, ivec2 column, out bool closed) {
    int winding = 0;
    float run_start = 0.0;
    uint count = 0;
    for (uint i = 0; i < n; ++i) {
        int before = winding;
        winding += int(layer[i].y);
        if (before == 0 && winding != 0) run_start = layer[i].x;
        if (before == 0 || winding != 0) continue;
        ivec2 k = inside_range(run_start, layer[i].x);
        for (int z = k.x; z <= k.y; ++z, ++count) {
            if (emit && base + count < pc.max_points)
                points[base + count] = vec4(lattice(column.x, 0), lattice(column.y, 1), lattice(z, 2), pc.w_value);
        }
    }
    closed = winding == 0;
    return count;
}

void main() {
    uint pixels = uint(pc.pixel_rect.z * pc.pixel_rect.w);
    uint pixel = gl_GlobalInvocationID.x;
    // The scan's end is the total wanted, which may exceed max_points (the excess is dropped).
    if (kEmit && pixel == 0) counters[RASTER_COUNTER_POINTS] = column_offsets[pixels];
    if (pixel >= pixels) return;
    uint base = 0;
    if (kEmit) {
        // Empty, overflowed and open columns were counted 0; a column past the capacity is dropped.
        base = column_offsets[pixel];
        if (column_offsets[pixel + 1] == base || base >= pc.max_points) return;
    }
    uint n = layer_count[pixel];
    if (n == 0) return;
    // An overflowed list holds an arbitrary subset of the layers: leave the column empty.
    if (n > RASTER_MAX_LAYERS) {
        if (!kEmit) atomicAdd(counters[RASTER_COUNTER_OVERFLOWED], 1u);
        return;
    }
    for (uint i = 0; i < n; ++i) {  // insertion sort by z; n is small
        vec2 l = layers[i * pixels + pixel];
        uint j = i;
        for (; j > 0 && layer[j - 1].x > l.x; --j) layer[j] = layer[j - 1];
        layer[j] = l;
    }
    ivec2 column = pc.pixel_rect.xy + ivec2(int(pixel % uint(pc.pixel_rect.z)), int(pixel / uint(pc.pixel_rect.z)));
    bool closed;
    if (kEmit) {
        walk(n, true, base, column, closed);
        return;
    }
    uint count = walk(n, false, 0u, column, closed);
    // A ray through a hole misses one of its layers and the winding does not return to 0; its
    // runs could then reach outside the mesh, so the column is left empty (and counted).
    if (!closed) {
        atomicAdd(counters[RASTER_COUNTER_OPEN], 1u);
        return;
    }
    column_offsets[pixel] = count;
}
