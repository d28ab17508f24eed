// A scene's whitewater (its "whitewater" key): the settings of the particles that
// sim/whitewater.h makes from the flow (spray, foam and bubbles; Ihmsen et al. 2012, whose
// potentials, thresholds and motion shaders/shared/sim/whitewater_layout.h writes out).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

namespace aquaform {

struct SceneBasics;

struct WhitewaterSettings {
    bool enabled = true;
    /// Most whitewater particles alive at once; 0: sized from the fluid and the device
    /// (whitewater_capacity). Particles that do not fit are counted (stats.csv), not made.
    uint32_t capacity = 0;
    glm::vec2 trapped_air{5.0f, 20.0f};    ///< Phi_ta's thresholds [m/s] (Ihmsen et al.: 5-20)
    glm::vec2 wave_crest{2.0f, 8.0f};      ///< Phi_wc's thresholds (Ihmsen et al.: 2-8)
    glm::vec2 kinetic_energy{1.0f, 8.0f};  ///< Phi_k's thresholds [J/kg]: from 1.4 to 4 m/s
    float k_trapped_air = 2000.0f;         ///< whitewater particles a second at Phi_ta = 1 (Ihmsen et al.: 4000)
    float k_wave_crest = 20000.0f;         ///< whitewater particles a second at Phi_wc = 1 (Ihmsen et al.: 50000)
    glm::vec2 lifetime{2.0f, 5.0f};        ///< each particle's life is drawn from this range [s]
    uint32_t spray_below = 6;              ///< fluid neighbours within h: fewer is spray
    uint32_t bubble_above = 20;            ///< more is a bubble; between is foam
    uint32_t emit_min_neighbors = 15;      ///< fluid particles with fewer neighbours emit nothing
    float air_drag = 0.5f;                 ///< spray's drag [1/s]
    float buoyancy = 2.0f;                 ///< bubbles rise at this many times -g
    float bubble_drag = 0.5f;              ///< bubbles take this share of the fluid's velocity a step
};

/// Reads {"enabled": true, "capacity": 0, "trapped_air": [5, 20], "wave_crest": [2, 8],
/// "kinetic_energy": [1, 8], "k_trapped_air": 2000, "k_wave_crest": 20000, "lifetime": [2, 5],
/// "spray_below": 6, "bubble_above": 20, "emit_min_neighbors": 15, "air_drag": 0.5,
/// "buoyancy": 2, "bubble_drag": 0.5}; every key optional. Throws json_fields::Invalid naming
/// the key, the value and the fix.
WhitewaterSettings read_whitewater(const nlohmann::json& v);

/// The pool's size for `fluid_particles` when the settings leave it to aquaform: four whitewater
/// particles a fluid particle, at least 65,536, within a sixteenth of `device_bytes` (the pool
/// takes 64 bytes a particle: two generations of position and velocity).
uint32_t whitewater_capacity(const WhitewaterSettings& settings, uint64_t fluid_particles, uint64_t device_bytes);

}  // namespace aquaform
