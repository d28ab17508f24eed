// Camera rays and the density field of the surface renderer (layout in shared/render/surface_layout.h).
// Include after declaring `params` (SurfaceParams), and, for the field, the rgba32f storage texel
// buffers `sorted` (positions, or kernel centres, in grid order) and `shape` (the kernels' G, see
// below; any buffer for the isotropic field), `cell_rank` and `cell_start`, and shared/render/anisotropy.h.

#include "common/camera.glsl"

vec3 grid_min() { return params.grid_origin_cell.xyz; }
vec3 grid_max() { return params.grid_origin_cell.xyz + params.grid_origin_cell.w * vec3(params.grid_dims.xyz); }

#ifdef SURFACE_FIELD
#include "common/grid_query.glsl"

// Loops over the particles j that can lie within r of p: the cells of the 3x3x3 block around
// p's cell whose nearest point is closer than r (the corner and edge cells usually are not).
// The cell size is r, so the block holds every such particle.
#define FOR_EACH_PARTICLE_NEAR(p, j)                                                          \
    {                                                                                         \
    ivec3 near_cell_ = grid_cell(p, params.grid_origin_cell, params.grid_dims);               \
    vec3 near_local_ = (p - params.grid_origin_cell.xyz) / params.grid_origin_cell.w - vec3(near_cell_); \
    for (int near_k_ = 0; near_k_ < 27; ++near_k_) {                                          \
        ivec3 near_o_ = ivec3(near_k_ % 3, (near_k_ / 3) % 3, near_k_ / 9) - ivec3(1);          \
        vec3 near_gap_ = max(mix(vec3(0.0), near_local_, lessThan(near_o_, ivec3(0))),          \
                             mix(vec3(0.0), 1.0 - near_local_, greaterThan(near_o_, ivec3(0)))); \
        if (dot(near_gap_, near_gap_) >= 1.0) continue;                                        \
        uvec2 near_range_ = grid_neighbor_range(near_cell_, near_k_, params.grid_dims);         \
        for (uint j = near_range_.x + field_lane; j < near_range_.y; j += kFieldLanes)

#define END_FOR_EACH_PARTICLE_NEAR } }

// Lanes that share one ray's field evaluations (specialization constant 2; issue 36): lane
// field_lane of kFieldLanes visits every kFieldLanes-th particle of each cell, and the partial
// sums are added across the lanes with a butterfly of subgroup shuffles, so every lane holds the
// same bits (x + y == y + x) and all take the same branches. One lane per ray (1, the default)
// is the plain loop. On a GPU a ray's evaluation is a chain of ~150 dependent loads; shared
// among lanes, the chain is shorter and more warps hide its latency (the H200 ran 5 warps a
// multiprocessor on the calm frame with one lane a ray).
layout(constant_id = 2) const uint kFieldLanes = 1u;
uint field_lane = 0u;

float lanes_sum(float x) {
    for (uint m = 1u; m < kFieldLanes; m *= 2u) x += subgroupShuffleXor(x, m);
    return x;
}
vec3 lanes_sum(vec3 x) {
    for (uint m = 1u; m < kFieldLanes; m *= 2u) x += subgroupShuffleXor(x, m);
    return x;
}

// The anisotropic surface (SURFACE_ANISOTROPIC_FIELD): `sorted` holds the kernels' smoothed
// centres in their own grid's order and `shape` (declared by the including shader) their G, three
// rows, row 0's w = |det G| (render/classify_shape.comp). Every G has semi-axes <= r, so the
// kernels that reach p are those whose centre is within r of it, as in the isotropic field.
// Which field is fixed per pipeline (specialization constant 1, the renderer's ray_march_[2]): on
// the software device both sides of a branch inside the evaluation loop cost, uniform or not.
layout(constant_id = 1) const bool kAnisotropicField = false;
bool anisotropic_field() { return kAnisotropicField; }

// `sorted` and `shape` are rgba32f storage texel buffers (gathers at scattered indices: see
// common/grid_query.glsl).
vec4 field_centre(uint j) { return imageLoad(sorted, int(j)); }
vec4 field_shape_row(uint j, uint row) { return imageLoad(shape, int(3u * j + row)); }

mat3 kernel_shape(uint j) {
    // mat3 takes columns: the transpose of the rows is G.
    return transpose(mat3(field_shape_row(j, 0u).xyz, field_shape_row(j, 1u).xyz, field_shape_row(j, 2u).xyz));
}

/// phi(p) = V sum_j W(p - x_j, r): the normalised density (1 inside resting fluid); with the
/// anisotropic surface V sum_j W(p - x_bar_j, G_j) (Yu & Turk eq. 5, Wu eq. 8).
float field_density(vec3 p) {
    float sum = 0.0;
    float r2 = params.radius * params.radius;
    bool anisotropic = anisotropic_field();  // uniform across the dispatch: the branch is free
    FOR_EACH_PARTICLE_NEAR(p, j) {
        vec3 d = p - field_centre(j).xyz;
        float d2 = dot(d, d);
        if (!anisotropic) {
            sum += cubic_kernel(d2, params.inv_radius, params.kernel_coeff);
        } else if (d2 < r2) {  // only then read the shape
            sum += anisotropic_kernel(d, kernel_shape(j), field_shape_row(j, 0u).w);
        }
    }
    END_FOR_EACH_PARTICLE_NEAR
    return params.volume * lanes_sum(sum);
}

/// grad phi(p) (points into the fluid).
vec3 field_gradient(vec3 p) {
    vec3 sum = vec3(0.0);
    float r2 = params.radius * params.radius;
    bool anisotropic = anisotropic_field();
    FOR_EACH_PARTICLE_NEAR(p, j) {
        vec3 d = p - field_centre(j).xyz;
        float d2 = dot(d, d);
        if (!anisotropic) {
            sum += cubic_gradient(d, d2, params.inv_radius, params.kernel_coeff);
        } else if (d2 < r2) {
            sum += anisotropic_kernel_gradient(d, kernel_shape(j), field_shape_row(j, 0u).w);
        }
    }
    END_FOR_EACH_PARTICLE_NEAR
    return params.volume * lanes_sum(sum);
}
#endif
