#include "sim/pbf_params.h"

#include <algorithm>
#include <cmath>

#include "grid/neighbor_grid.h"
#include "shaders/shared/core/sph_kernels.h"
#include "shaders/shared/sim/dfsph_physics.h"
#include "shaders/shared/sim/pbf_physics.h"
#include "shaders/shared/solids/tank_layout.h"
#include "sim/frame_stats.h"

static_assert(TANK_MAX_BOXES == PBF_MAX_SOLIDS, "the renderers draw every static box the solver takes");

namespace aquaform {

namespace {
constexpr double SPH_PI_D = 3.14159265358979323846;
}  // namespace

PbfConstants pbf_constants(const Scene& scene) {
    PbfConstants c;
    const float s = scene.particle_spacing;
    c.h = scene.solver.kernel_radius_factor * s;
    const float h2 = c.h * c.h;
    const float poly6_coeff = shader::poly6_coefficient(c.h);
    const float spiky_coeff = shader::spiky_gradient_coefficient(c.h);
    const int reach = static_cast<int>(std::ceil(scene.solver.kernel_radius_factor));
    double w_sum = 0.0;
    double w_half = 0.0;       // the particle's own layer and those on one side of it
    double grad2_sum = 0.0;    // sum |grad W|^2, to be scaled by the particle volume squared
    double consistency = 0.0;  // sum (x_j - x_i) . grad W_ij, to be scaled by the volume
    for (int z = -reach; z <= reach; ++z)
        for (int y = -reach; y <= reach; ++y)
            for (int x = -reach; x <= reach; ++x) {
                glm::vec3 r = glm::vec3(float(x), float(y), float(z)) * s;
                float r2 = glm::dot(r, r);
                w_sum += shader::poly6(r2, h2, poly6_coeff);
                if (z >= 0) w_half += shader::poly6(r2, h2, poly6_coeff);
                glm::vec3 g = shader::spiky_gradient(r, r2, c.h, spiky_coeff);
                grad2_sum += glm::dot(g, g);
                consistency -= glm::dot(r, g);  // r = x_i - x_j
            }
    c.mass = static_cast<float>(scene.rest_density / w_sum);
    const double volume = 1.0 / w_sum;
    c.stiffness_ref = static_cast<float>(volume * volume * grad2_sum);
    c.gradient_consistency = static_cast<float>(volume * consistency / 3.0);
    // The wall must supply the missing (1 - w_half / w_sum) of rho0 at distance s / 2, where
    // its unscaled continuum integral is (pi c / 4) (F(h) - F(s / 2)).
    const float d0 = 0.5f * s;
    const double integral = SPH_PI_D * poly6_coeff / 4.0 *
                            (shader::pbf_wall_antiderivative(c.h, h2) - shader::pbf_wall_antiderivative(d0, h2));
    c.wall_phi = static_cast<float>((1.0 - w_half / w_sum) / integral);
    return c;
}

shader::SimParams make_sim_params(const Scene& scene, const GridGeometry& grid, uint32_t particle_count) {
    const PbfConstants c = pbf_constants(scene);
    const SolverSettings& sv = scene.solver;
    shader::SimParams p{};
    // Particle centres stay a hair inside the walls so that "outside the domain" means leaked.
    const float margin = 1.0e-3f * scene.particle_spacing;
    p.domain_min = glm::vec4(scene.domain.min, margin);
    p.domain_max = glm::vec4(scene.domain.max, 0.0f);
    p.gravity = glm::vec4(scene.gravity, 0.0f);
    p.grid_origin_cell = glm::vec4(grid.origin, grid.cell_size);
    p.grid_dims = glm::uvec4(grid.dims, grid.cell_count());
    p.h = c.h;
    p.h2 = c.h * c.h;
    p.mass = c.mass;
    p.rest_density = scene.rest_density;
    p.volume = c.mass / scene.rest_density;
    p.poly6_coeff = shader::poly6_coefficient(c.h);
    p.spiky_coeff = shader::spiky_gradient_coefficient(c.h);
    p.epsilon = sv.relaxation * c.stiffness_ref;
    p.scorr_n = sv.scorr_n;
    p.neighbor_capacity = neighbor_list_capacity(sv.kernel_radius_factor);
    const float dq = sv.scorr_dq * c.h;
    p.scorr_inv_wdq = 1.0f / shader::poly6(dq * dq, p.h2, p.poly6_coeff);
    p.viscosity = sv.viscosity;
    p.vorticity = sv.vorticity;
    set_substeps(p, sv.frame_dt, sv.substeps);
    p.scorr_k = scorr_k_of_step(scene, p.dt);
    p.max_speed = sv.max_speed;  // 0: no cap
    p.particle_count = particle_count;
    p.solid_count = 0;  // the solids' table is sim/boundary.h's (Boundary::write_params)
    p.front_floor = scene.domain.min.y + c.h;
    p.front_tag = 0;
    p.wall_scale = c.wall_phi * shader::SPH_PI * p.poly6_coeff / 4.0f;
    p.wall_f_h = shader::pbf_wall_antiderivative(c.h, p.h2);
    p.constraint_min = sv.density_constraint == DensityConstraint::two_sided ? -1.0e30f : 0.0f;
    p.pressure_scale = c.gradient_consistency * scene.rest_density;
    // Fewer and the particle is at a free surface, where a divergence-free solve would hold the
    // water together (shaders/sim/dfsph_rate.comp).
    p.divergence_min_neighbors = float(DFSPH_NEIGHBOR_FRACTION * full_neighbor_count(sv.kernel_radius_factor));
    return p;
}

void set_substeps(shader::SimParams& params, float frame_dt, uint32_t substeps) {
    params.dt = frame_dt / float(std::max(substeps, 1u));
    params.inv_dt = 1.0f / params.dt;
}

float scorr_k_of_step(const Scene& scene, float dt) {
    const double k = scene.solver.scorr_k / pbf_constants(scene).stiffness_ref;
    const double iterations_share = double(kScorrIterations) / double(std::max(scene.solver.iterations, 1u));
    const double below = std::min(double(dt) / kScorrStep, 1.0);
    return float(k * iterations_share * below * below);
}

uint32_t substeps_for_speed(const SolverSettings& solver, float h, double max_speed, double accel, double growth) {
    const double lo = std::max(solver.substeps, 1u), hi = std::max(solver.max_substeps, solver.substeps);
    if (!std::isfinite(max_speed) || !std::isfinite(accel) || !std::isfinite(growth)) return uint32_t(hi);
    // n steps of frame_dt / n: (v + max(a frame_dt, growth)) frame_dt / n <= cfl h.
    const double speed = max_speed + std::max(accel * solver.frame_dt, growth);
    const double needed = std::ceil(speed * solver.frame_dt / (double(solver.cfl) * h) - 1e-9);
    return uint32_t(std::clamp(needed, lo, hi));
}

uint32_t substeps_for_compression(const SolverSettings& solver, uint32_t steps, uint32_t last_steps,
                                  double max_density_error) {
    const double hi = std::max(solver.max_substeps, solver.substeps);
    if (!std::isfinite(max_density_error)) return uint32_t(hi);
    if (max_density_error <= kStepDensityErrorBound) return steps;
    const double more = std::ceil(double(last_steps) * std::sqrt(max_density_error / kStepDensityErrorBound) - 1e-9);
    return std::max(steps, uint32_t(std::min(more, hi)));
}

}  // namespace aquaform
