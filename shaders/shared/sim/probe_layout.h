// Probes of a scene (sim/probes.h): water-height gauges, pressure sensors and the force and
// torque on each solid (static box or mesh obstacle), measured on the GPU from the solver's own
// quantities.
//
// Pressure: PBF moves a particle by dx_i = V sum_j (lambda_i + lambda_j + s_corr_ij) grad W_ij per
// constraint iteration (eqs. 13, 14). An SPH pressure force does in one step dx_i = dt^2 a_i with
// a_i = -sum_j m (p_i / rho_i^2 + p_j / rho_j^2) grad W_ij ~ -(V / rho0) sum_j (p_i + p_j) grad W_ij
// at rho ~ rho0. The two agree term by term for p_i = -rho0 (lambda_i + s_i) / dt^2, where s_i is
// the particle's half of the pairs' s_corr (an artificial pressure, which carries much of a resting
// column's weight; shaders/sim/pbf_correct.comp takes its level around i), and the iterations of a
// step add up. On a lattice the symmetric sum recovers kappa = 0.947 (at h = 2 s) of a field's
// gradient (sim/pbf_params.h), so the solver supports a column with a lambda gradient 1 / kappa too
// steep: p_i = -kappa rho0 sum_iterations (lambda_i + s_i) / dt^2 reads rho0 g d at depth d.
#ifndef AQUAFORM_PROBE_LAYOUT_H
#define AQUAFORM_PROBE_LAYOUT_H
#include "../core/compat.h"

#include "pbf_layout.h"

#define PROBE_MAX_SENSORS 32
#define PROBE_MAX_GAUGES 16
#define PROBE_MAX_GAUGE_SAMPLES 512
#define PROBE_FORCE_WORKGROUP 256
/// A gauge sample inside a solid reads this (the gauge stands on the solid's top).
#define PROBE_IN_SOLID (-1.0f)

AF_BEGIN

struct ProbeParams {
    vec4 sensors[PROBE_MAX_SENSORS];  ///< xyz: the sensor's point on a solid's surface [m]; w: its face's radius [m]
    vec4 gauges[PROBE_MAX_GAUGES];    ///< x, z: the gauge's line; y: its lowest sample [m]; w: sample spacing [m]
    vec4 centres[PBF_MAX_SOLIDS];     ///< xyz: the point each solid's torque is taken about [m]
    uvec4 counts;                     ///< x: sensors; y: gauges; z: samples per gauge; w: solids
};

/// Push constants of the sampling pass: where this step's readings go.
struct ProbePush {
    uint slot;   ///< the step within the frame: readings at slot * (sensors + gauges * samples)
    uint count;  ///< particles
    uint pad0;
    uint pad1;
};

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::ProbeParams) == (PROBE_MAX_SENSORS + PROBE_MAX_GAUGES + PBF_MAX_SOLIDS + 1) * 16);
static_assert(sizeof(aquaform::shader::ProbePush) == 16);
#endif

#endif
