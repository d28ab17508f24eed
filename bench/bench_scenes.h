// The scenes the benchmarks run: dam breaks of a chosen size (`aquaform bench sim` and
// `aquaform bench render`).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "sim/scene.h"

namespace aquaform::study {

/// A dam break with about `particles` particles: a column a x 2a x a in a 4a x 2.5a x a tank
/// (particle spacing 1 cm, so a grows as the cube root of the count).
inline Scene bench_scene(uint32_t particles, uint32_t iterations) {
    Scene s;
    s.name = "bench_dam_break_" + std::to_string(particles);
    s.particle_spacing = 0.01f;
    const float a = s.particle_spacing * std::cbrt(particles / 2.0f);
    s.domain = {glm::vec3(0.0f), glm::vec3(4.0f * a, 2.5f * a, a)};
    s.fluid_blocks = {{glm::vec3(0.0f), glm::vec3(a, 2.0f * a, a)}};
    s.column_width = a;
    s.solver.iterations = iterations;
    s.solver.substeps = 2;
    s.solver.viscosity = 0.01f;
    s.solver.vorticity = 1.0e-4f;
    return s;
}

/// bench_scene with water that comes and goes: a nozzle over the middle of the tank pouring down
/// at 1 m/s, a fifth of the column's width across, and a drain along the far wall's foot.
inline Scene flow_bench_scene(uint32_t particles, uint32_t iterations) {
    Scene s = bench_scene(particles, iterations);
    const float a = s.domain.max.z;
    EmitterSpec nozzle;
    nozzle.name = "nozzle";
    nozzle.position = glm::vec3(2.0f * a, 2.2f * a, 0.5f * a);
    nozzle.radius = 0.1f * a;
    nozzle.speed = {{0.0, 1.0f}};
    s.emitters = {nozzle};
    SinkSpec drain;
    drain.name = "drain";
    drain.box = {glm::vec3(3.7f * a, -a, -a), glm::vec3(5.0f * a, 0.15f * a, 2.0f * a)};
    s.sinks = {drain};
    return s;
}

/// Martin & Moyce's dimensionless time T = t sqrt(2 g / a) at which the surge front reaches
/// Z = x / a = 2.56: halfway from the column's face (x = a) to the far wall (x = 4a) of a
/// bench_scene tank. The fluid is then a thin tongue running along the floor behind a tall
/// collapsing column: aggregate and thin sheets side by side, before any splash off the wall.
constexpr double kHalfTankFrontT = 2.20;

/// The frame of `scene` (a bench_scene) at which the front has travelled about half the tank:
/// T = kHalfTankFrontT, i.e. t = 2.2 / sqrt(2 g / a); 15 frames (0.25 s) for 32,768 particles,
/// 27 frames (0.44 s) for a million.
inline uint32_t bench_half_tank_frame(const Scene& scene) {
    const double a = scene.column_width.value_or((scene.domain.max.x - scene.domain.min.x) / 4.0f);
    const double g = std::abs(double(scene.gravity.y)) > 0.0 ? std::abs(double(scene.gravity.y)) : 9.81;
    const double t = kHalfTankFrontT / std::sqrt(2.0 * g / a);
    return uint32_t(std::lround(t / double(scene.solver.frame_dt)));
}

}  // namespace aquaform::study
