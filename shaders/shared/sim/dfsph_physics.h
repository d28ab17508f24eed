// Divergence-free SPH's per-particle math (Bender & Koschier 2017, "Divergence-Free SPH for
// Incompressible and Weakly Compressible Fluids"), shared by the GPU passes (shaders/sim/dfsph_*.comp)
// and the CPU reference (sim/dfsph_reference.cpp). Densities are relative to rho0 (rho_i / rho0),
// masses are volumes V = m / rho0, and the solids are the density maps' m and grad m
// (pbf_boundary.h): rho_i / rho0 = V sum_j W_ij + m(x_i).
//
// A pressure solve moves velocities by dv_i = -dt (V sum_j (k_i + k_j) grad W_ij + k_i grad m(x_i)),
// k_i = p_i / rho0 (the solids mirror the particle's own k: their share is k_i grad m). The k_i
// that would cancel a particle's own error, its neighbours' k held at 0 and their reaction
// counted, is k_i = a_i error_i / dt^2 with the factor
//   a_i = 1 / (|V sum_j grad W_ij + grad m|^2 + sum_j |V grad W_ij|^2),
// the DFSPH factor (the paper's alpha_i / rho_i, in relative densities): PBF's lambda of a
// velocity instead of a position (pbf_lambda.comp). Where the paper leaves details open:
// - Kernels: poly6 for the density and the spiky gradient for the rest, as the PBF passes have
//   them, so both solvers share the calibration of the mass, the walls and the maps.
// - The factor's denominator has PBF's relaxation epsilon added: an isolated particle has a
//   factor of 1 / epsilon instead of a division by zero; in the bulk it changes a_i by 1 %.
// - Warm start: each solve starts from the k_i its last step ended with (carried through the
//   sort, sim/dfsph_pressure.h), in full, so a resting column's pressure is not built again
//   every step; an iteration adds to it (weighted: DFSPH_JACOBI_WEIGHT). Only compression is corrected, on the sum: k_i stays
//   >= 0, an iteration may lower it (the accumulated, clamped impulse of a unilateral
//   constraint), so a pressure carried over can fall as fast as it rose.
// - The divergence of a particle with fewer than divergence_min_neighbors (the solids counted)
//   is left alone, its k_i 0: at a free surface a divergence-free solve would hold the water
//   together (Bender & Koschier's code does the same).
#ifndef AQUAFORM_DFSPH_PHYSICS_H
#define AQUAFORM_DFSPH_PHYSICS_H
#include "pbf_physics.h"

/// DFSPH corrects the divergence of a particle with at least this fraction of a full
/// neighbourhood, the solids' share counted: Bender & Koschier's code asks for 20 neighbours at
/// h = 2 s, where a full neighbourhood has 32.5 (sim/frame_stats.h, full_neighbor_count).
#define DFSPH_NEIGHBOR_FRACTION (20.0f / 32.5f)
/// The Jacobi iterations' weight: a_i cancels a particle's error as if its neighbours' k stayed
/// 0, and they move too, so in the bulk a full step overshoots about twice. With the sums free
/// to fall, unweighted iterations blew up the standing wave in its second frame; at 0.5 they
/// converge (as IISPH's relaxed Jacobi does).
#define DFSPH_JACOBI_WEIGHT 0.5f

AF_BEGIN

/// a_i from grad_i = V sum_j grad W_ij + grad m and sum_grad2 = sum_j |V grad W_ij|^2.
AF_FN float dfsph_factor(vec3 grad_i, float sum_grad2 PBF_PARAMS) {
    return 1.0f / (dot(grad_i, grad_i) + sum_grad2 + params.epsilon);
}

/// The neighbours a particle counts: the listed ones, and the solids' share m = rho_solid / rho0
/// as that share of a full kernel's particles (the full count and the particle itself).
AF_FN float dfsph_neighbors(float listed, float solid_share PBF_PARAMS) {
    return listed + solid_share * (params.divergence_min_neighbors / DFSPH_NEIGHBOR_FRACTION + 1.0f);
}

/// The divergence-free solve's k_i after an iteration, from the k_i summed so far (`total`)
/// and rate = D(rho_i / rho0) / Dt.
AF_FN float dfsph_divergence_total(float total, float factor, float rate, float neighbors PBF_PARAMS) {
    if (neighbors < params.divergence_min_neighbors) return 0.0f;
    return max(total + DFSPH_JACOBI_WEIGHT * factor * rate * params.inv_dt, 0.0f);
}

/// The constant-density solve's k_i after an iteration, from the k_i summed so far and the
/// density predicted a step on, rho_i / rho0 + dt rate.
AF_FN float dfsph_density_total(float total, float factor, float density, float rate PBF_PARAMS) {
    float error = density + params.dt * rate - 1.0f;
    return max(total + DFSPH_JACOBI_WEIGHT * factor * error * params.inv_dt * params.inv_dt, 0.0f);
}

AF_END

#endif
