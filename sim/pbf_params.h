// Turns a scene into the solver's GPU parameter block. Shared by the GPU solver and the CPU
// reference so that both run exactly the same numbers.
#pragma once

#include "grid/neighbor_grid.h"
#include "shaders/shared/sim/pbf_layout.h"
#include "sim/scene.h"

namespace aquaform {

/// Derived constants of a scene, with the choices the paper leaves open:
/// - mass: calibrated so that an interior particle of the initial lattice has exactly rho0
///   (m = rho0 / sum_j W(x_j) over the lattice), so a column at rest starts at rest;
/// - stiffness_ref: sum_k |grad_k C|^2 of that lattice particle. epsilon = relaxation *
///   stiffness_ref and the s_corr k is divided by it, so both are dimensionless and behave the
///   same at every particle spacing (the paper's values assume unit mass and spacing).
/// - wall_phi: scales the walls' continuum density (shaders/shared/sim/pbf_layout.h,
///   pbf_wall_term) so that a lattice particle half a spacing from a wall has exactly rho0.
struct PbfConstants {
    float h = 0.0f;
    float mass = 0.0f;
    float stiffness_ref = 0.0f;
    float wall_phi = 0.0f;
    /// kappa = (1/3) sum_j V (x_j - x_i) . grad W_ij over the rest lattice: how much of a linear
    /// field's gradient the symmetric sum sum_j V (f_i + f_j) grad W_ij recovers (0.947 at h = 2 s).
    /// The probes' pressure divides it out (shared/sim/probe_layout.h).
    float gradient_consistency = 1.0f;
};

PbfConstants pbf_constants(const Scene& scene);

/// The parameter block for one solver step (dt = frame_dt / scene.solver.substeps).
shader::SimParams make_sim_params(const Scene& scene, const GridGeometry& grid, uint32_t particle_count);
/// Sets the block's step to frame_dt / substeps.
void set_substeps(shader::SimParams& params, float frame_dt, uint32_t substeps);

/// s_corr (eq. 13) is an artificial pressure written as a position correction, and the paper
/// applies it in every constraint iteration of every step. So its pressure grew with the
/// iterations and as 1 / dt^2: 466 m/s at the surface at frame_dt 1e-5 in the dam break, and a
/// standing wave that lost more the more iterations or steps it was given (docs/solver.md).
/// Here it is one pressure whatever the solver's counts: the paper's k at the reference step
/// (kScorrStep, kScorrIterations: the shipped frame of 1/60 s in 2 steps of 4 iterations),
/// shared among the step's iterations, its push scaling as a force's (dt^2) below the
/// reference step. Above it, the paper's push a step is kept: a larger push at a large step is
/// a splash, not a pressure.
inline constexpr double kScorrStep = 1.0 / 120.0;  ///< [s]
inline constexpr uint32_t kScorrIterations = 4;
/// The parameter block's s_corr k (scaled by stiffness_ref) for one iteration of a step of `dt`.
float scorr_k_of_step(const Scene& scene, float dt);

/// The time-step rule (the CFL condition v_max * dt <= cfl * h, bounded by the scene's substeps
/// and max_substeps): the steps of the next frame from the largest speed at the end of the
/// last. The speed is the frame's one reduction, so choosing costs no extra readback; a frame
/// can speed up on the way, so the bound adds the larger of what `accel` [m/s^2] (gravity) can
/// add within it and `growth` [m/s], how much the largest speed grew over the last frame (a
/// wave hitting a wall throws spray faster than anything before it: one frame's growth is taken
/// to repeat). Whether a frame kept the bound is measured after it (FrameStats::cfl_number).
uint32_t substeps_for_speed(const SolverSettings& solver, float h, double max_speed, double accel, double growth = 0.0);

/// The largest density error (max of rho / rho0 - 1) a frame may end with before the next one
/// takes smaller steps.
inline constexpr double kStepDensityErrorBound = 0.10;

/// The time step also follows the compression: a fixed number of Jacobi iterations holds a
/// column only so many particles tall at a given step, and beyond it the bottom compresses until
/// it bursts. Measured on the Martin & Moyce column at a/60 (120 particles tall, cfl 0.4): the
/// density error reached 0.39 by the 4th frame, and the burst threw particles at 2.8 m/s (free
/// fall had reached 0.65 m/s) that slid along the floor ahead of the front (19 % front error at
/// 0.5 s). The compression a step leaves grows as dt^2, so when the last frame ended above
/// kStepDensityErrorBound the next takes sqrt(error / bound) times the steps (at most
/// max_substeps); at a/60 the burst is gone and the error at 0.5 s is 9.9 %. Returns at least
/// `steps`, what the speed rule chose.
uint32_t substeps_for_compression(const SolverSettings& solver, uint32_t steps, uint32_t last_steps,
                                  double max_density_error);

}  // namespace aquaform
