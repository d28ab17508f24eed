// Camera rays and the density field of the surface renderer (layout in shared/surface_layout.h).
// Include after declaring `params` (SurfaceParams), and, for the field, the buffers `sorted`
// (vec4 positions in grid order), `cell_rank` and `cell_start`.

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
        for (uint j = near_range_.x; j < near_range_.y; ++j)

#define END_FOR_EACH_PARTICLE_NEAR } }

/// phi(p) = V sum_j W(p - x_j, r): the normalised density (1 inside resting fluid).
float field_density(vec3 p) {
    float sum = 0.0;
    FOR_EACH_PARTICLE_NEAR(p, j) {
        vec3 d = p - sorted[j].xyz;
        sum += cubic_kernel(dot(d, d), params.inv_radius, params.kernel_coeff);
    }
    END_FOR_EACH_PARTICLE_NEAR
    return params.volume * sum;
}

/// grad phi(p) (points into the fluid).
vec3 field_gradient(vec3 p) {
    vec3 sum = vec3(0.0);
    FOR_EACH_PARTICLE_NEAR(p, j) {
        vec3 d = p - sorted[j].xyz;
        sum += cubic_gradient(d, dot(d, d), params.inv_radius, params.kernel_coeff);
    }
    END_FOR_EACH_PARTICLE_NEAR
    return params.volume * sum;
}
#endif
