// Per-frame figures of a simulation (one row of stats.csv).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>

#include "shaders/shared/pbf_layout.h"

namespace aquaform {

struct FrameStats {
    double time_s = 0.0;              ///< simulated time at the end of the frame
    double mean_density_error = 0.0;  ///< mean of max(rho/rho0 - 1, 0): compression, the constraint error
    double max_density_error = 0.0;
    double mean_density_deviation = 0.0;  ///< mean |rho/rho0 - 1|, free-surface deficiency included
    double kinetic_energy = 0.0;      ///< [J]
    double max_speed = 0.0;           ///< [m/s]
    uint32_t substeps = 0;            ///< solver steps this frame took (the time-step rule)
    double dt = 0.0;                  ///< their step [s]
    double cfl_number = 0.0;          ///< max_speed * dt / h at the frame's end (the rule keeps it <= cfl)
    bool speed_capped = false;        ///< the scene's safety cap (solver.max_speed) bound in this frame
    uint32_t particles = 0;
    uint32_t outside = 0;             ///< particles outside the domain box (leaked)
    uint32_t non_finite = 0;          ///< particles with NaN or infinite state
    std::optional<double> front;      ///< dam-break front [m from the wall], when the scene has one
    std::map<std::string, double> gpu_ms;  ///< GPU time per pass during this frame
};

/// Finishes the GPU's per-workgroup reduction. `front_wall_x` turns the front's x into a
/// distance from the wall; a front below -1e29 (no particle on the floor) stays empty.
FrameStats reduce_stats(std::span<const shader::StatsPartial> partials, uint32_t particles,
                        std::optional<float> front_wall_x);

}  // namespace aquaform
