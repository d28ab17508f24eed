// Parameters and shared math of the position-based fluid solver (Macklin & Mueller 2013),
// included by the GPU passes (shaders/sim/*.comp), the C++ solver and its CPU reference.
//
// Per-particle arrays (structure of arrays, all in GPU memory):
//   x: position, w = particle id (as float: exact below 2^24)
//   v: velocity, w = tag (fluid block the particle came from, as float)
//   p: predicted position, w unused
//   q: scratch written by the lambda pass: xyz = p, w = lambda (one load per neighbour later)
//   density: one float
#ifndef AQUAFORM_PBF_LAYOUT_H
#define AQUAFORM_PBF_LAYOUT_H
#include "compat.h"
#include "sph_kernels.h"

#define PBF_MAX_STATIC_BOXES 16
#define PBF_STATS_WORKGROUP 256

AF_BEGIN

struct SimParams {
    vec4 domain_min;      ///< xyz [m]; w: wall margin [m]
    vec4 domain_max;      ///< xyz [m]
    vec4 gravity;         ///< xyz [m/s^2]
    vec4 grid_origin_cell;  ///< neighbour grid: xyz origin, w cell size (= h)
    uvec4 grid_dims;      ///< neighbour grid: xyz cells, w cell count
    float h;              ///< kernel radius [m]
    float h2;
    float mass;           ///< particle mass [kg], calibrated so a rest lattice has density rho0
    float rest_density;   ///< rho0 [kg/m^3]
    float volume;         ///< mass / rho0 [m^3]
    float poly6_coeff;
    float spiky_coeff;
    float epsilon;        ///< relaxation of eq. 11, = relaxation * stiffness_ref
    float scorr_k;        ///< eq. 13 k, divided by stiffness_ref (see sim/pbf_solver.cpp)
    float scorr_n;
    float scorr_inv_wdq;  ///< 1 / W(dq h)
    float viscosity;      ///< XSPH c
    float vorticity;      ///< vorticity confinement epsilon [m/s]
    float max_speed;      ///< safety cap [m/s]; 0 = none
    float dt;             ///< step [s]
    float inv_dt;
    uint particle_count;
    uint static_box_count;
    float front_floor;    ///< a particle below this height counts as "on the floor" for the front
    uint front_tag;       ///< tag whose leading edge front.csv follows
    float wall_scale;     ///< phi * pi * c_poly6 / 4, see pbf_wall_term
    float wall_f_h;       ///< F(h) of pbf_wall_term
    float constraint_min; ///< C_i = max(rho_i / rho0 - 1, constraint_min): 0 one-sided, -1e30 two-sided
    float pad1;
    vec4 box_min[PBF_MAX_STATIC_BOXES];
    vec4 box_max[PBF_MAX_STATIC_BOXES];
};

/// Push constants of the passes that only need the particle count.
struct CountPush {
    uint count;
    uint pad0;
    uint pad1;
    uint pad2;
};

/// Per-workgroup partial sums of the stats pass; the host finishes the reduction.
struct StatsPartial {
    float sum_density_error;    ///< sum of max(rho / rho0 - 1, 0)
    float max_density_error;
    float sum_kinetic_energy;   ///< [J]
    float max_speed;
    float outside;              ///< particles outside the domain box
    float non_finite;           ///< particles with a NaN or infinite position or velocity
    float front;                ///< largest x of a front_tag particle below front_floor (-1e30 if none)
    float sum_abs_density_dev;  ///< sum of |rho / rho0 - 1|, free-surface deficiency included
    float splash;               ///< particles with fewer neighbours than StatsPush::splash_neighbors
    float runup;                ///< largest y of a particle with x above StatsPush::runup_x (-1e30 if none)
};

/// Push constants of the stats pass (sim/frame_stats.h explains the splash threshold).
struct StatsPush {
    uint count;
    float splash_neighbors;  ///< fewer neighbours within h than this make a splash particle
    float runup_x;           ///< particles beyond this x touch the far wall (1e30: no runup measured)
    uint pad0;
};

/// Keeps a predicted position inside the domain and outside every static box (projection to
/// the nearest surface; PBF turns the correction into a velocity in the update).
AF_FN vec3 pbf_collide(vec3 p, SimParams params) {
    float m = params.domain_min.w;
    vec3 lo = vec3(params.domain_min) + vec3(m);
    vec3 hi = vec3(params.domain_max) - vec3(m);
    p = clamp(p, lo, hi);
    for (uint b = 0u; b < params.static_box_count; ++b) {
        vec3 bmin = vec3(params.box_min[b]) - vec3(m);
        vec3 bmax = vec3(params.box_max[b]) + vec3(m);
        if (p.x > bmin.x && p.x < bmax.x && p.y > bmin.y && p.y < bmax.y && p.z > bmin.z && p.z < bmax.z) {
            // Push out through the nearest face that opens into the domain: a box that reaches a
            // wall (across the whole depth, say) has no way out on that side.
            const float none = 1.0e30f;
            float dx0 = bmin.x > lo.x ? p.x - bmin.x : none, dx1 = bmax.x < hi.x ? bmax.x - p.x : none;
            float dy0 = bmin.y > lo.y ? p.y - bmin.y : none, dy1 = bmax.y < hi.y ? bmax.y - p.y : none;
            float dz0 = bmin.z > lo.z ? p.z - bmin.z : none, dz1 = bmax.z < hi.z ? bmax.z - p.z : none;
            float best = min(min(min(dx0, dx1), min(dy0, dy1)), min(dz0, dz1));
            if (best >= none) continue;  // the box fills the domain: nowhere to go
            if (best == dx0) p.x = bmin.x;
            else if (best == dx1) p.x = bmax.x;
            else if (best == dy0) p.y = bmin.y;
            else if (best == dy1) p.y = bmax.y;
            else if (best == dz0) p.z = bmin.z;
            else p.z = bmax.z;
        }
    }
    return p;
}

/// The predicted position p = x + dt v, kept inside the walls (Algorithm 1, line 4). The
/// reorder pass recomputes it with this same function instead of carrying p along.
AF_FN vec3 pbf_predicted_position(vec3 x, vec3 v, SimParams params) {
    return pbf_collide(x + params.dt * v, params);
}

/// Caps a velocity at params.max_speed: a safety net the scene may ask for (0 = off); the time
/// step follows the speeds instead (sim/pbf_params.h, substeps_for_speed).
AF_FN vec3 pbf_cap_speed(vec3 v, SimParams params) {
    float s2 = dot(v, v);
    if (params.max_speed > 0.0 && s2 > params.max_speed * params.max_speed) v *= params.max_speed / sqrt(s2);
    return v;
}

/// Antiderivative F(z) of (h^2 - z^2)^4, for the wall integral below.
AF_FN float pbf_wall_antiderivative(float z, float h2) {
    float z2 = z * z;
    float h4 = h2 * h2;
    return z * (h4 * h4 - z2 * (4.0f / 3.0f * h4 * h2 - z2 * (1.2f * h4 - z2 * (4.0f / 7.0f * h2 - z2 / 9.0f))));
}

/// The domain walls as fluid at rest beyond them, so that a particle near a wall has a full
/// neighbourhood (without it, wall particles are under-dense and the fluid presses into the
/// walls). For a half-space at distance d the poly6 density integrates in closed form:
///   rho_wall(d) / rho0 = phi (pi c / 4) (F(h) - F(d)),  d(rho_wall / rho0)/dd = -phi (pi c / 4) (h^2 - d^2)^4,
/// with phi calibrated on the host so that a lattice particle half a spacing from a wall has
/// exactly rho0. Returns xyz: grad_p of C_i from the walls; w: rho_wall / rho0.
AF_FN vec4 pbf_wall_term(vec3 p, SimParams params) {
    vec4 term = vec4(0.0f);
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            float d = side == 0 ? p[axis] - params.domain_min[axis] : params.domain_max[axis] - p[axis];
            d = max(d, 0.0f);
            if (d >= params.h) continue;
            float u = params.h2 - d * d;
            vec3 inward = vec3(0.0f);
            inward[axis] = side == 0 ? 1.0f : -1.0f;
            term += vec4(-params.wall_scale * u * u * u * u * inward,
                         params.wall_scale * (params.wall_f_h - pbf_wall_antiderivative(d, params.h2)));
        }
    }
    return term;
}

/// Tensile-instability correction s_corr = -k (W(r) / W(dq))^n (eq. 13).
AF_FN float pbf_scorr(float w, SimParams params) {
    return -params.scorr_k * pow(w * params.scorr_inv_wdq, params.scorr_n);
}

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::SimParams) == 5 * 16 + 24 * 4 + 2 * 16 * 16);
static_assert(sizeof(aquaform::shader::CountPush) == 16);
static_assert(sizeof(aquaform::shader::StatsPartial) == 40);
static_assert(sizeof(aquaform::shader::StatsPush) == 16);
#endif

#endif
