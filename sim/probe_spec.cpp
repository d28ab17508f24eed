#include "sim/probe_spec.h"

#include <algorithm>
#include <cmath>

#include "core/json_fields.h"
#include "geometry/animation.h"
#include "geometry/distance_field.h"
#include "shaders/shared/sim/probe_layout.h"
#include "sim/scene_basics.h"

namespace aquaform {

namespace {

using namespace json_fields;

constexpr std::string_view kProbeKeys[] = {"gauges", "sensors", "forces"};
constexpr std::string_view kGaugeKeys[] = {"x", "z"};
constexpr std::string_view kSensorKeys[] = {"position", "size"};
constexpr const char* kProbeFix = "are measured on the GPU: keep the ones you chart";

/// The distance from p to the nearest solid surface: the tank's walls and floor, the static boxes,
/// the obstacles as they stand at t = 0.
float distance_to_solids(const SceneBasics& scene, const glm::vec3& p) {
    const Box& d = scene.domain;
    float nearest = std::min({p.x - d.min.x, d.max.x - p.x, p.y - d.min.y, p.z - d.min.z, d.max.z - p.z});
    for (const Box& b : scene.static_boxes) nearest = std::min(nearest, std::abs(geometry::box_signed_distance(b, p)));
    for (const ObstacleSpec& o : scene.obstacles)
        nearest = std::min(nearest, geometry::distance_to_surface(o.shape->mesh_at(0.0).triangle_soup(), p));
    return nearest;
}

}  // namespace

ProbeSpec read_probes(const json& v, const SceneBasics& scene) {
    if (!v.is_object())
        fail("probes must be an object such as {\"gauges\": {\"H1\": {\"x\": 0.5, \"z\": 0.5}}}, got " + written(v));
    check_keys(v, "in probes", kProbeKeys);
    ProbeSpec spec;
    const Box& d = scene.domain;
    if (v.contains("gauges"))
        read_named(v["gauges"], "probes.gauges", PROBE_MAX_GAUGES, "{\"H1\": {\"x\": 0.5, \"z\": 0.5}}", kProbeFix,
                   [&](const std::string& name, const json& g, const std::string& path) {
                       if (!g.is_object())
                           fail(path + " must be {\"x\": ..., \"z\": ...} (a vertical line), got " + written(g));
                       check_keys(g, "in " + path, kGaugeKeys);
                       require(g, "x", "in " + path, "\"x\": 0.5");
                       require(g, "z", "in " + path, "\"z\": 0.5");
                       HeightGauge gauge{name};
                       gauge.x = read_number(g["x"], path + ".x",
                                             {d.min.x, d.max.x, false, false, "an x inside the tank " + fmt(d)});
                       gauge.z = read_number(g["z"], path + ".z",
                                             {d.min.z, d.max.z, false, false, "a z inside the tank " + fmt(d)});
                       spec.gauges.push_back(gauge);
                   });
    if (v.contains("sensors"))
        read_named(
            v["sensors"], "probes.sensors", PROBE_MAX_SENSORS, "{\"P1\": {\"position\": [0.8, 0.02, 0.5]}}", kProbeFix,
            [&](const std::string& name, const json& s, const std::string& path) {
                if (!s.is_object())
                    fail(path + " must be {\"position\": [x, y, z], \"size\": 0.009}, got " + written(s));
                check_keys(s, "in " + path, kSensorKeys);
                require(s, "position", "in " + path, "\"position\": [0.8, 0.02, 0.5]");
                PressureSensor sensor{name};
                sensor.position =
                    read_vec3(s["position"], path + ".position", "a point [x, y, z] on a solid's surface");
                // Inside the tank first: outside it, the distances to its walls are negative
                // and would pass for "on a wall".
                const float slack = scene.particle_spacing;
                for (int a = 0; a < 3; ++a)
                    if (!(sensor.position[a] >= d.min[a] - slack && sensor.position[a] <= d.max[a] + slack))
                        fail(path + ".position " + written(s["position"]) + " is outside the tank " + fmt(d) + " on " +
                             "xyz"[a] +
                             "; a pressure sensor sits on a solid's surface inside it (a "
                             "wall, the floor, a static box or an obstacle): move it there");
                if (s.contains("size"))
                    sensor.size = read_number(
                        s["size"], path + ".size",
                        {0.0, 0.5 * glm::length(d.max - d.min), false, false, "a diameter in metres, e.g. 0.009"});
                // The reading averages the particles' pressures over the kernel's support (h
                // around the point): that is the fluid's resolution, and a sensor wider than
                // it would be read over less than its face.
                const float h = scene.solver.kernel_radius_factor * scene.particle_spacing;
                if (sensor.size > 2.0f * h)
                    fail(path + ".size " + written(s["size"]) +
                         " is wider than the kernel's support 2 h = " + fmt(2.0f * h) +
                         " m that a reading averages over; split it into sensors at most 2 h "
                         "across, or make the particles coarser");
                const float off = distance_to_solids(scene, sensor.position);
                if (!(off <= scene.particle_spacing))
                    fail(path + ".position " + written(s["position"]) + " is " + fmt(off) +
                         " m from the nearest solid surface (the tank's walls and floor, static_boxes, obstacles); a "
                         "pressure sensor sits on one of them (within a particle spacing, " +
                         fmt(scene.particle_spacing) + " m): move it there, or give the solid it was on");
                spec.sensors.push_back(sensor);
            });
    if (v.contains("forces")) {
        if (!v["forces"].is_boolean()) fail("probes.forces must be true or false, got " + written(v["forces"]));
        spec.forces = v["forces"].get<bool>();
    }
    if (spec.forces && scene.static_boxes.empty() && scene.obstacles.empty())
        spec.forces = false;  // nothing to push on
    return spec;
}

}  // namespace aquaform
