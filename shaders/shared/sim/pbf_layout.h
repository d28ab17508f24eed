// Parameters and data layout of the position-based fluid solver (Macklin & Mueller 2013),
// included by the GPU passes (shaders/sim/*.comp), the C++ solver and its CPU reference. The
// math that reads the parameters is in pbf_physics.h.
//
// Shaders read SimParams as a uniform block (std140, the same layout as here: vec4s first, then
// scalars, then vec4 arrays). Why not a storage buffer: on the software device a storage-buffer
// load inside a loop or branch runs once per lane with a bounds check, even at a constant
// offset, and the neighbour loops read h, h^2 and the kernel constants for every neighbour; a
// uniform-block field is one scalar load.
//
// Per-particle arrays (structure of arrays, all in GPU memory):
//   x: position, w = particle id (as float: exact below 2^24)
//   v: velocity, w = tag (fluid block the particle came from, as float)
//   p: predicted position, w unused (DFSPH: the sort's spare for its carried state)
//   q: scratch written by the lambda pass: xyz = p, w = lambda (one load per neighbour later)
//   density: one float
#ifndef AQUAFORM_PBF_LAYOUT_H
#define AQUAFORM_PBF_LAYOUT_H
#include "../core/compat.h"
#include "../core/sph_kernels.h"
#include "../solids/solid_layout.h"  // SolidParams, PBF_NODE_*: the solids' table

/// Solids besides the tank's walls: the scene's static boxes and mesh obstacles together.
#define PBF_MAX_SOLIDS 16
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
    uint solid_count;     ///< solids[] in use (pbf_boundary.h)
    float front_floor;    ///< a particle below this height counts as "on the floor" for the front
    uint front_tag;       ///< tag whose leading edge front.csv follows
    float wall_scale;     ///< phi * pi * c_poly6 / 4, see pbf_wall_term
    float wall_f_h;       ///< F(h) of pbf_wall_term
    uint neighbor_capacity;  ///< neighbour-list entries per particle (shared/grid/grid_layout.h)
    float constraint_min; ///< C_i = max(rho_i / rho0 - 1, constraint_min): 0 one-sided, -1e30 two-sided
    float solid_margin;   ///< particle centres keep this far out of a solid's surface [m]
    float solid_stride;   ///< a move is checked for crossing a solid at this stride [m] (pbf_collide)
    float pressure_scale;  ///< kappa rho0: a particle's pressure is -pressure_scale sum(lambda) / dt^2 (probe_layout.h)
    /// DFSPH: a particle with fewer listed neighbours is at a free surface and its divergence is
    /// not corrected (shaders/sim/dfsph_rate.comp)
    float divergence_min_neighbors;
    SolidParams solids[PBF_MAX_SOLIDS];
};

/// Push constants of the passes that only need the particle count.
struct CountPush {
    uint count;
    uint pad0;
    uint pad1;
    uint pad2;
};

/// Push constants of the correct pass: which of the step's constraint iterations it is.
struct CorrectPush {
    uint count;
    uint iteration;  ///< 0 for the step's first
    uint pad0;
    uint pad1;
};

/// Push constants of the reorder (the sort's gather of the particle arrays).
struct ReorderPush {
    uint count;
    uint gather_carry;  ///< 1: p takes the pressure solve's carried state (DFSPH); 0: the prediction
    uint pad0;
    uint pad1;
};

/// Push constants of DFSPH's iterations (shaders/sim/dfsph_rate.comp, dfsph_velocity.comp).
struct DfsphPush {
    uint count;
    uint solve;        ///< DFSPH_DIVERGENCE or DFSPH_DENSITY: the component of the carried state it works on
    uint add_gravity;  ///< 1: the velocity pass adds dt g first (the density solve's warm start)
    uint pad0;
};
const uint DFSPH_DIVERGENCE = 0u;
const uint DFSPH_DENSITY = 1u;

/// Per-workgroup partial sums of the stats pass; the host finishes the reduction.
struct StatsPartial {
    float sum_density_error;    ///< sum of max(rho / rho0 - 1, 0)
    float max_density_error;
    float sum_kinetic_energy;   ///< [J]
    float max_speed;
    float outside;              ///< particles outside the domain box
    float in_solid;             ///< particles whose centre is inside a solid (static box or mesh obstacle)
    float non_finite;           ///< particles with a NaN or infinite position or velocity
    float front;                ///< largest x of a front_tag particle below front_floor (-1e30 if none)
    float sum_abs_density_dev;  ///< sum of |rho / rho0 - 1|, free-surface deficiency included
    float splash;               ///< particles with fewer neighbours than StatsPush::splash_neighbors
    float runup;                ///< largest y of a non-spray particle with x above StatsPush::runup_x (-1e30 if none)
    float list_overflow;        ///< particles with more neighbours than the list holds (they scan cells)
};

/// Push constants of the stats pass (sim/frame_stats.h explains the splash threshold).
struct StatsPush {
    uint count;
    float splash_neighbors;  ///< fewer neighbours within h than this make a splash particle
    float runup_x;           ///< particles beyond this x touch the far wall (1e30: no runup measured)
    uint pad0;
};

/// The droplet count on the GPU (sim/droplets.comp): connected groups of particles closer than
/// h over the frame's neighbour lists, in passes (the push's phase). Counters: the droplet count.
const uint DROPLET_INIT = 0u;      ///< parent = the smallest linked neighbour (or itself)
const uint DROPLET_HOOK = 1u;      ///< linked groups merged: the larger root hung under the smaller
const uint DROPLET_COMPRESS = 2u;  ///< parent = root
const uint DROPLET_SIZE = 3u;      ///< members counted at each root
const uint DROPLET_COUNT = 4u;     ///< roots of groups below the size limit counted

struct DropletPush {
    uint count;       ///< particles
    uint phase;       ///< DROPLET_INIT ...
    uint size_limit;  ///< groups with fewer members are droplets
    float link2;      ///< two particles closer than sqrt(link2) are linked
};

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::SimParams) == 5 * 16 + 28 * 4 + PBF_MAX_SOLIDS * 5 * 16);
static_assert(sizeof(aquaform::shader::CountPush) == 16);
static_assert(sizeof(aquaform::shader::CorrectPush) == 16);
static_assert(sizeof(aquaform::shader::ReorderPush) == 16);
static_assert(sizeof(aquaform::shader::DfsphPush) == 16);
static_assert(sizeof(aquaform::shader::StatsPartial) == 48);
static_assert(sizeof(aquaform::shader::StatsPush) == 16);
static_assert(sizeof(aquaform::shader::DropletPush) == 16);
#endif

#endif
