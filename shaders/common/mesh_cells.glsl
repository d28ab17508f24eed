// Marching-cubes helpers over the sampled lattice (layout in shared/render/mesh_layout.h). Include
// after declaring `params` (MeshParams), `lattice` (MeshLattice) and `values`, phi per sample as
// a texel buffer (`layout(binding = N, r32f) readonly uniform imageBuffer values;`): each pass
// reads a sample's neighbours, which on the software device is far quicker through texel fetches
// (common/grid_query.glsl says why).

float mesh_value(uvec3 c) { return imageLoad(values, int(mesh_index(c, lattice.dims))).x; }
bool mesh_inside(uvec3 c) { return mesh_value(c) >= params.iso; }

/// Bits 0, 1, 2: the edges from sample c along +x, +y, +z that cross the surface.
uint mesh_edge_mask(uvec3 c) {
    bool in0 = mesh_inside(c);
    uint mask = 0u;
    for (uint a = 0u; a < 3u; ++a) {
        uvec3 n = c;
        n[a] += 1u;
        if (n[a] < lattice.dims[a] && mesh_inside(n) != in0) mask |= 1u << a;
    }
    return mask;
}

/// The corner pattern of the cell whose lowest sample is c (bit k: corner k inside).
uint mesh_cell_pattern(uvec3 c) {
    uint pattern = 0u;
    for (uint k = 0u; k < 8u; ++k)
        if (mesh_inside(c + mesh_corner(k))) pattern |= 1u << k;
    return pattern;
}

/// Whether c is the lowest sample of a cell (not on the highest layer of any axis).
bool mesh_owns_cell(uvec3 c) { return all(lessThan(c + 1u, lattice.dims.xyz)); }
