// What a scene measures (its "probes" key): water-height gauges, pressure sensors on solids,
// and the force and torque on each solid. The GPU side is sim/probes.h; the readings go to
// probes.csv and probes.svg (runner/).
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json_fwd.hpp>

namespace aquaform {

struct SceneBasics;

/// A wire gauge: a vertical line at (x, z) from the floor up. It reads the height of the water
/// connected to what it stands on (the floor, or a solid's top), not spray flying over it.
struct HeightGauge {
    std::string name;
    float x = 0.0f, z = 0.0f;
};

/// A pressure sensor: a point on a solid's surface (a wall, a static box or an obstacle) and
/// its size (diameter, m; 0: a point). It reads the mean of the fluid's pressure over its face (a
/// disc of that diameter on the surface), the pressure at each point smoothed over the kernel's
/// support (h around it: the fluid's resolution); a sensor wider than 2 h is refused.
struct PressureSensor {
    std::string name;
    glm::vec3 position{0.0f};
    float size = 0.0f;
};

struct ProbeSpec {
    std::vector<HeightGauge> gauges;
    std::vector<PressureSensor> sensors;
    bool forces = true;  ///< the force and torque on every solid (static boxes and obstacles)
    bool empty() const { return gauges.empty() && sensors.empty() && !forces; }
};

/// Reads {"gauges": {"H1": {"x": 0.5, "z": 0.5}}, "sensors": {"P1": {"position": [x, y, z],
/// "size": 0.009}}, "forces": true}; every key optional. Gauges and sensors must lie in the tank,
/// a sensor within a particle spacing of a solid's surface. Throws json_fields::Invalid.
ProbeSpec read_probes(const nlohmann::json& v, const SceneBasics& scene);

}  // namespace aquaform
