// When a simulation has left physics: a speed, Courant number or compression that no step rule
// can hold, or particles that are not finite or left the box. One definition for every command
// (run, render, view, study and its solver maps, the benches), so the verdict means the same
// everywhere; README "When the fluid leaves physics" says what it means for a user.
#pragma once

#include <string>

#include "sim/frame_stats.h"
#include "sim/scene.h"

namespace aquaform {

struct BlowupBounds {
    double max_speed = 0.0;          ///< [m/s]
    double max_density_error = 0.0;  ///< rho/rho0 - 1
    double max_courant = 0.0;        ///< max_speed dt / h
};
BlowupBounds blowup_bounds(const Scene& scene);
/// Empty when the frame is plausible, else what failed ("3 particles have non-finite ...").
std::string blowup_reason(const FrameStats& stats, const BlowupBounds& bounds);
/// What to change in the scene when a run leaves physics.
constexpr const char* kBlowupFix =
    "raise solver.substeps or lower solver.frame_dt, or undo what adds energy (solver.vorticity, solver.scorr_k, "
    "\"density_constraint\": \"two_sided\", a control pressure) in the scene";

}  // namespace aquaform
