// Automatic strength of the driving force: the control pressure, support radius and solver step
// derived from the scene, so that a shape holds against gravity without a hand-tuned constant
// (the limitation Karpati et al. name in section 3.1). Users may override each.
//
// With a uniformly filled shape, phi = sum_c V_c W(x - x_c) is ~1 inside and 0 outside, and the
// force is a = (P / rho0) grad phi (shaders/shared/control/control_layout.h). In equilibrium the fluid
// pressure obeys grad p = rho (g + (P / rho0) grad phi), so its free surfaces are level sets of
// (P / rho0) phi - |g| y. Between the top and the bottom of a shape of height L:
//     (P / rho0) (phi_top - phi_bottom) = |g| L.
// Holding the shape means both surfaces sit inside the transition layer of phi, at 0.5 +- d/2:
//     P_hold = rho0 |g| L / d,   d = kHoldSpread.
// Quiet hold: the force peaks at the boundary, a_max = (P / rho0) |grad phi|, with |grad phi| =
// 315 / (256 H) for poly6 over a half-space (the kernel's integral over the boundary plane). Each
// step it moves a particle by a_max dt^2, which the solver's few iterations must undo; what they
// leave becomes velocity noise. Measured on a held sphere: the fluid comes to rest while
// a_max dt^2 <= 0.15 spacing and churns at the speed cap beyond ~0.5 spacing. So
//     a_max dt^2 <= kStepFraction * spacing,
// met by raising the solver's substeps (dt = frame_dt / substeps), or by capping P when the
// substeps are fixed. The density error stays below kDensityErrorBound at the automatic strength
// (tests/test_control_force.cpp checks both on a sphere).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "sim/scene.h"

namespace aquaform::control {

/// phi_top - phi_bottom of a held shape: surfaces at phi = 0.5 +- 0.25.
inline constexpr float kHoldSpread = 0.5f;
/// Largest displacement per step the control force may cause, in particle spacings.
inline constexpr float kStepFraction = 0.12f;
/// The bound on the maximum density error at the automatic strength.
inline constexpr float kDensityErrorBound = 0.10f;

struct StrengthInputs {
    const Scene* scene = nullptr;
    float control_spacing = 0.0f;  ///< spacing of the control points [m]
    float shape_height = 0.0f;     ///< the tallest shape's extent along gravity [m]
};

struct StrengthOverrides {
    std::optional<float> support;   ///< H [m]
    std::optional<float> pressure;  ///< P [Pa]
    bool fixed_substeps = false;    ///< keep the scene's substeps; cap P instead
};

struct Strength {
    float support = 0.0f;              ///< H [m]
    float pressure = 0.0f;             ///< P [Pa], what the force uses
    float hold_pressure = 0.0f;        ///< P_hold [Pa]
    float stable_pressure = 0.0f;      ///< largest quiet P at the chosen substeps [Pa]
    uint32_t substeps = 0;             ///< solver steps per frame the scene should run with
    const char* source = "automatic";  ///< of the pressure: "automatic" or "given"
    std::string warning;               ///< non-empty when the shape cannot be held quietly
    /// One line for the log: the numbers and where they came from.
    std::string describe() const;
};

/// H defaults to max(h, 2 * control spacing): at least the fluid kernel (section 3.1) and wide
/// enough that phi is smooth over the control lattice.
Strength automatic_strength(const StrengthInputs& in, const StrengthOverrides& overrides = {});

/// |grad phi| at the boundary of a uniformly filled half-space: 315 / (256 H) for poly6.
float boundary_gradient(float support);

}  // namespace aquaform::control
