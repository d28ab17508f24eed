#include "sim/blowup.h"

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "core/format_text.h"

namespace aquaform {

BlowupBounds blowup_bounds(const Scene& scene) {
    // Blow-up criterion, the one definition every command uses:
    //  - a particle is non-finite, or has left the domain (the walls clamp every step, so
    //    leaving means the update itself failed);
    //  - a speed above 10x the free fall over the domain's diagonal: no flow in this box gets
    //    near it (Earth's gravity at least, so that a weightless scene gets a bound too). The
    //    solver caps speeds at cfl * h / dt, so this fires only where that cap is higher: energy
    //    blow-ups (vorticity, s_corr, control force) at small dt;
    //  - a compression beyond rho = 1.5 rho0: the usual outcome at large dt, where the cap
    //    keeps the fluid finite but the iterations no longer hold it. PBF stays within ~10 % at
    //    usable settings (control/strength.h, kDensityErrorBound); half again the rest density
    //    is no longer an incompressible fluid;
    //  - a Courant number above 2: particles move more than two kernel radii per step, past the
    //    neighbours the solver sees (the step rule keeps it at solver.cfl, a few tenths; the
    //    solver map test's control force at 100x its pressure reaches 1.3).
    const double diagonal = glm::length(scene.domain.max - scene.domain.min);
    const double g = std::max(double(glm::length(scene.gravity)), 9.81);
    return {10.0 * std::sqrt(2.0 * g * diagonal), 0.5, 2.0};
}

std::string blowup_reason(const FrameStats& s, const BlowupBounds& bounds) {
    if (s.non_finite > 0) return format_text("%u particles have non-finite positions or velocities", s.non_finite);
    if (s.outside > 0) return format_text("%u particles left the domain", s.outside);
    if (!std::isfinite(s.max_speed) || s.max_speed > bounds.max_speed)
        return format_text("max speed %.3g m/s is above the plausible %.3g m/s", s.max_speed, bounds.max_speed);
    if (!std::isfinite(s.max_density_error) || s.max_density_error > bounds.max_density_error)
        return format_text("max density error %.3g is above %.3g", s.max_density_error, bounds.max_density_error);
    if (!std::isfinite(s.cfl_number) || s.cfl_number > bounds.max_courant)
        return format_text("Courant number %.3g is above %.3g (particles cross more than two kernel radii per step)", s.cfl_number,
                   bounds.max_courant);
    return "";
}

}  // namespace aquaform
