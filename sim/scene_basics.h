// The basics of a scene that the parts read after them need (its obstacles and probes check
// against the tank, the spacing and the solver): a leaf below sim/scene.h, so that those parts do
// not depend on the whole scene.
#pragma once

#include <cstdint>
#include <vector>

#include "core/box.h"
#include "sim/obstacle_spec.h"

namespace aquaform {

/// Which densities the PBF constraint corrects (shaders/sim/pbf_lambda.comp explains the choice).
enum class DensityConstraint { clamped, two_sided };

/// The pressure solve of a step (sim/pressure_solve.h): position-based fluids, the fast end
/// (Macklin & Mueller 2013, sim/pbf_pressure.h), or divergence-free SPH, the accurate end
/// (Bender & Koschier 2017, sim/dfsph_pressure.h).
enum class PressureMethod { pbf, dfsph };

/// The scene's name of a method ("pbf", "dfsph").
const char* method_name(PressureMethod method);

/// Solver settings (Macklin & Mueller 2013, "Position Based Fluids"; Bender & Koschier 2017,
/// "Divergence-Free SPH").
struct SolverSettings {
    PressureMethod method = PressureMethod::pbf;
    float frame_dt = 1.0f / 60.0f;  ///< simulated seconds per output frame
    /// Solver steps per frame: at least `substeps`, more where the fluid is fast (the time-step
    /// rule: the fastest particle moves at most cfl * h per step), up to `max_substeps`.
    uint32_t substeps = 2;
    uint32_t max_substeps = 32;
    uint32_t iterations = 4;  ///< constraint iterations per step (DFSPH: of its constant-density solve)
    /// DFSPH's divergence-free solve: iterations per step (0 switches it off).
    uint32_t divergence_iterations = 2;
    float kernel_radius_factor = 2.0f;  ///< h = factor * particle_spacing
    float relaxation = 0.01f;  ///< epsilon of eq. 11 relative to a full neighbourhood stiffness (sim/pbf_params.h)
    float viscosity = 0.01f;   ///< XSPH c (eq. 17)
    float vorticity = 0.0f;    ///< vorticity confinement epsilon (eq. 16)
    float scorr_k = 0.1f;      ///< tensile instability k (eq. 13)
    float scorr_n = 4.0f;      ///< tensile instability n
    float scorr_dq = 0.2f;     ///< tensile instability delta q, as a fraction of h
    float cfl = 0.4f;          ///< the time-step rule's Courant number: v_max * dt <= cfl * h
    /// A safety net, not a time-step rule: speeds are capped at this [m/s] (0 = off, the
    /// default); a frame where the cap binds is reported (FrameStats::speed_capped).
    float max_speed = 0.0f;
    /// clamped: C = max(rho / rho0 - 1, 0), only compression is corrected (the default);
    /// two_sided: C = rho / rho0 - 1, under-dense particles are pulled together too.
    DensityConstraint density_constraint = DensityConstraint::clamped;
};

struct SceneBasics {
    Box domain;                      ///< the tank: particles are kept inside it
    float particle_spacing = 0.02f;  ///< initial lattice spacing [m]
    SolverSettings solver;
    std::vector<Box> static_boxes;  ///< solid boxes inside the domain
    /// Solid obstacles from meshes (sim/obstacles.h); with the static boxes, at most
    /// PBF_MAX_SOLIDS solids. Fluid the blocks would start inside one is not started.
    std::vector<ObstacleSpec> obstacles;

    float kernel_radius() const { return solver.kernel_radius_factor * particle_spacing; }
};

}  // namespace aquaform
