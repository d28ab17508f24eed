#include "control/strength.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace aquaform::control {

float boundary_gradient(float support) { return 315.0f / 256.0f / support; }

Strength automatic_strength(const StrengthInputs& in, const StrengthOverrides& overrides) {
    const Scene& scene = *in.scene;
    const float h = scene.solver.kernel_radius_factor * scene.particle_spacing;
    const float g = glm::length(scene.gravity);
    const float rho0 = scene.rest_density;
    Strength s;
    s.support = overrides.support.value_or(std::max(h, 2.0f * in.control_spacing));
    s.hold_pressure = rho0 * g * in.shape_height / kHoldSpread;
    s.pressure = overrides.pressure.value_or(s.hold_pressure);
    if (overrides.pressure) s.source = "given";
    const float quiet_step = kStepFraction * scene.particle_spacing;  // a_max dt^2 at most this
    const float a_max = s.pressure / rho0 * boundary_gradient(s.support);
    const float needed = std::ceil(scene.solver.frame_dt * std::sqrt(a_max / quiet_step) - 1e-4f);
    s.substeps = scene.solver.substeps;
    if (!overrides.fixed_substeps) s.substeps = std::max<uint32_t>(s.substeps, uint32_t(std::min(needed, 64.0f)));
    const float dt = scene.solver.frame_dt / float(s.substeps);
    s.stable_pressure = rho0 * quiet_step / (boundary_gradient(s.support) * dt * dt);
    if (s.pressure > s.stable_pressure * 1.0001f) {
        char buf[400];
        if (!overrides.pressure) {
            std::snprintf(buf, sizeof buf,
                          "holding a shape %.3g m tall needs %.4g Pa of control pressure, more than the %.4g Pa the "
                          "solver takes quietly at %u substeps; the pressure is capped there and the shape will sag. "
                          "Allow more substeps (remove control.fixed_substeps) or use a smaller shape",
                          in.shape_height, s.hold_pressure, s.stable_pressure, s.substeps);
            s.pressure = s.stable_pressure;
        } else {
            std::snprintf(buf, sizeof buf,
                          "control pressure %.4g Pa is above the %.4g Pa the solver takes quietly at %u substeps: "
                          "expect a churning or exploding fluid. Lower control.pressure or allow more substeps",
                          s.pressure, s.stable_pressure, s.substeps);
        }
        s.warning = buf;
    }
    return s;
}

std::string Strength::describe() const {
    char buf[300];
    std::snprintf(buf, sizeof buf,
                  "control pressure %.4g Pa (%s; holding needs %.4g, quiet up to %.4g), support radius %.3g m, "
                  "%u substeps per frame",
                  pressure, source, hold_pressure, stable_pressure, support, substeps);
    return buf;
}

}  // namespace aquaform::control
