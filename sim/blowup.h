// When a simulation has left physics: a speed, Courant number or compression that no step rule
// can hold, or particles that are not finite or left the box. One definition for every command
// (run, render, view, study and its solver maps, the benches), so the verdict means the same
// everywhere; README "When the fluid leaves physics" says what it means for a user.
#pragma once

#include <cstdint>
#include <stdexcept>
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
/// What to change in the scene when a run leaves physics, whatever the bound.
constexpr const char* kBlowupFix =
    "raise solver.substeps or lower solver.frame_dt, or undo what adds energy (solver.vorticity, solver.scorr_k, "
    "\"density_constraint\": \"two_sided\", a control pressure) in the scene";
/// The fix for the bound this frame exceeded: smaller steps for a compression or a Courant
/// number the steps could not hold; for a speed the steps held (Courant number within the
/// scene's cfl), the energy's sources, since smaller steps would not help.
std::string blowup_fix(const FrameStats& stats, const Scene& scene);

/// The frame `stats` ends, counted as `run` numbers its frame files (frame 0 is t = 0).
uint32_t frame_index(const FrameStats& stats, const Scene& scene);

/// The verdict every command that steps the solver prints when a frame left physics, empty when
/// the frame is plausible: "the fluid left physics at frame 3 (t = 0.050 s): <bound>; <fix>".
/// `scene` is the scene as it runs (SimulationSession::scene()).
std::string blowup_verdict(const FrameStats& stats, const Scene& scene);
/// A run that left physics, thrown where a command's figures of it would mean nothing (the
/// benches): a runtime failure, not bad input (the command's top level prints it and exits 1).
class LeftPhysics : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};
/// Throws LeftPhysics with blowup_verdict when the frame left physics.
void require_physical(const FrameStats& stats, const Scene& scene);

}  // namespace aquaform
