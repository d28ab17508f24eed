#include "sim/blowup.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "core/format_text.h"

namespace aquaform {

namespace {

enum class Exceeded { none, non_finite, outside, speed, compression, courant };

Exceeded exceeded(const FrameStats& s, const BlowupBounds& bounds) {
    if (s.non_finite > 0) return Exceeded::non_finite;
    if (s.outside > 0) return Exceeded::outside;
    if (!std::isfinite(s.max_speed) || s.max_speed > bounds.max_speed) return Exceeded::speed;
    if (!std::isfinite(s.max_density_error) || s.max_density_error > bounds.max_density_error)
        return Exceeded::compression;
    if (!std::isfinite(s.cfl_number) || s.cfl_number > bounds.max_courant) return Exceeded::courant;
    return Exceeded::none;
}

}  // namespace

BlowupBounds blowup_bounds(const Scene& scene) {
    // Blow-up criterion, the one definition every command uses:
    //  - a particle is non-finite, or has left the domain (the walls clamp every step, so
    //    leaving means the update itself failed);
    //  - a speed above 10x what energy allows: the fastest start speed plus a free fall over
    //    the domain's diagonal, sqrt(v0^2 + 2 g d) (Earth's gravity at least, so that a
    //    weightless scene gets a bound too). No flow in this box gets near it, and every start
    //    speed the scene check accepts (kMaxStartSpeed) stays under it. The solver caps speeds
    //    at cfl * h / dt, so this fires only where that cap is higher: energy blow-ups
    //    (vorticity, s_corr, control force) at small dt;
    //  - a compression beyond rho = 1.5 rho0: the usual outcome at large dt, where the cap
    //    keeps the fluid finite but the iterations no longer hold it. PBF stays within ~10 % at
    //    usable settings (control/strength.h, kDensityErrorBound); half again the rest density
    //    is no longer an incompressible fluid;
    //  - a Courant number above 2: particles move more than two kernel radii per step, past the
    //    neighbours the solver sees (the step rule keeps it at solver.cfl, a few tenths; the
    //    solver map test's control force at 100x its pressure reaches 1.3).
    const double diagonal = glm::length(scene.domain.max - scene.domain.min);
    const double g = std::max(double(glm::length(scene.gravity)), 9.81);
    double start = 0.0;
    for (size_t i = 0; i < scene.fluid_blocks.size(); ++i)
        start = std::max(start, double(glm::length(scene.fill_of(i).velocity)));
    return {10.0 * std::sqrt(start * start + 2.0 * g * diagonal), 0.5, 2.0};
}

std::string blowup_reason(const FrameStats& s, const BlowupBounds& bounds) {
    switch (exceeded(s, bounds)) {
        case Exceeded::none:
            return "";
        case Exceeded::non_finite:
            return format_text("%u particles have non-finite positions or velocities", s.non_finite);
        case Exceeded::outside:
            return format_text("%u particles left the domain", s.outside);
        case Exceeded::speed:
            return format_text("max speed %.3g m/s is above the plausible %.3g m/s", s.max_speed, bounds.max_speed);
        case Exceeded::compression:
            return format_text("max density error %.3g is above %.3g", s.max_density_error, bounds.max_density_error);
        case Exceeded::courant:
            return format_text(
                "Courant number %.3g is above %.3g (particles cross more than two kernel radii per step)", s.cfl_number,
                bounds.max_courant);
    }
    return "";
}

std::string blowup_fix(const FrameStats& s, const Scene& scene) {
    const SolverSettings& solver = scene.solver;
    switch (exceeded(s, blowup_bounds(scene))) {
        case Exceeded::compression:
            return "the iterations no longer hold the fluid at this step: raise solver.substeps or solver.iterations, "
                   "or lower solver.frame_dt";
        case Exceeded::courant:
            return format_text(
                "the steps were too long for the speeds (the step rule stops at solver.max_substeps = %u): "
                "raise solver.max_substeps or lower solver.frame_dt",
                solver.max_substeps);
        case Exceeded::speed:
            // The step rule held the Courant number: smaller steps would move as fast.
            if (std::isfinite(s.cfl_number) && s.cfl_number <= 1.01 * solver.cfl)
                return "smaller steps do not help (the steps kept the Courant number within solver.cfl): undo what adds "
                       "energy (solver.vorticity, solver.scorr_k, \"density_constraint\": \"two_sided\", a control "
                       "pressure, a fast start velocity) in the scene";
            return kBlowupFix;
        default:
            return kBlowupFix;
    }
}

uint32_t frame_index(const FrameStats& stats, const Scene& scene) {
    return uint32_t(std::lround(stats.time_s / double(scene.solver.frame_dt)));
}

std::string blowup_verdict(const FrameStats& stats, const Scene& scene) {
    const std::string reason = blowup_reason(stats, blowup_bounds(scene));
    if (reason.empty()) return "";
    // Milliseconds and more as 0.017; a smaller time keeps its figures (1e-05, not 0.000).
    const bool tiny = stats.time_s > 0.0 && stats.time_s < 0.001;
    return format_text(tiny ? "the fluid left physics at frame %u (t = %.3g s): %s; %s"
                            : "the fluid left physics at frame %u (t = %.3f s): %s; %s",
                       frame_index(stats, scene), stats.time_s, reason.c_str(), blowup_fix(stats, scene).c_str());
}

void require_physical(const FrameStats& stats, const Scene& scene) {
    if (std::string verdict = blowup_verdict(stats, scene); !verdict.empty()) throw LeftPhysics(verdict);
}

}  // namespace aquaform
