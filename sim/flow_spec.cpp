#include "sim/flow_spec.h"

#include <algorithm>
#include <cmath>

#include "core/json_fields.h"
#include "geometry/animation.h"
#include "geometry/mesh.h"
#include "sim/obstacles.h"
#include "sim/scene_basics.h"

namespace aquaform {

namespace {

using namespace json_fields;

constexpr std::string_view kEmitterKeys[] = {"position", "direction", "radius", "size", "wall",
                                             "height",   "speed",     "start",  "stop"};
constexpr std::string_view kSinkKeys[] = {"box", "plane", "mesh"};
constexpr std::string_view kPlaneKeys[] = {"point", "normal"};
constexpr std::string_view kSinkMeshKeys[] = {"file", "placement"};
constexpr const char* kSinkShapes =
    "{\"box\": {\"min\": [..], \"max\": [..]}}, {\"plane\": {\"point\": [..], \"normal\": [..]}} or "
    "{\"mesh\": {\"file\": \"../meshes/sphere.obj\", \"placement\": {..}}}";
constexpr const char* kTableFix = "fit the solver's table: merge neighbouring ones";
constexpr const char* kEmitterExample =
    "{\"tap\": {\"position\": [0.3, 0.5, 0.3], \"direction\": [0, -1, 0], \"radius\": 0.01, \"speed\": 1.0}}";

glm::vec3 read_unit(const json& v, const std::string& path) {
    const glm::vec3 d = read_vec3(v, path, "a direction [x, y, z]");
    const float length = glm::length(d);
    if (!(length > 1e-6f)) fail(path + " is " + written(v) + ", which has no direction; give e.g. [0, -1, 0]");
    return d / length;
}

/// A side wall of the tank ("min_x", "max_x", "min_z", "max_z"): its axis and side.
std::pair<int, bool> read_wall(const json& v, const std::string& path) {
    static constexpr const char* kWalls[] = {"min_x", "max_x", "min_z", "max_z"};
    for (int i = 0; i < 4; ++i)
        if (v.is_string() && v.get<std::string>() == kWalls[i]) return {i < 2 ? 0 : 2, i % 2 == 1};
    fail(path + " is " + written(v) +
         "; an inflow comes in through a side wall of the tank: \"min_x\", \"max_x\", \"min_z\" or \"max_z\"");
}

std::vector<SpeedKey> read_speed(const json& v, const std::string& path) {
    const Range speed{0.0, HUGE_VAL, true, false, "a speed above 0 m/s"};
    if (v.is_number()) return {{0.0, read_number(v, path, speed)}};
    if (!v.is_array() || v.empty())
        fail(path + " must be a speed in m/s (e.g. 1.0) or keys [[time, speed], ...] (e.g. [[0, 1.0], [2, 0]]), got " +
             written(v));
    std::vector<SpeedKey> keys;
    for (size_t i = 0; i < v.size(); ++i) {
        const std::string at = path + "[" + std::to_string(i) + "]";
        if (!v[i].is_array() || v[i].size() != 2) fail(at + " must be [time, speed], got " + written(v[i]));
        SpeedKey key{read_number(v[i][0], at + "[0]", {0.0, HUGE_VAL, false, false, "a time in seconds, from 0"}),
                     read_number(v[i][1], at + "[1]", {0.0, HUGE_VAL, false, false, "a speed from 0 m/s"})};
        if (!keys.empty() && !(key.time > keys.back().time))
            fail(at + " is at " + fmt(key.time) + " s, not after the key before it (" + fmt(keys.back().time) +
                 " s); give the keys in increasing time");
        keys.push_back(key);
    }
    if (std::none_of(keys.begin(), keys.end(), [](const SpeedKey& k) { return k.speed > 0.0f; }))
        fail(path + " is " + written(v) +
             ": every key's speed is 0, so the nozzle emits nothing; give a speed above 0");
    return keys;
}

/// Where the nozzle's particles stand when a layer leaves it (its lattice in the nozzle's plane).
std::vector<glm::vec3> nozzle_points(const EmitterSpec& e, float spacing) {
    const auto [width_axis, height_axis] = e.across_axes();
    std::vector<glm::vec3> points;
    for (const glm::vec2& o : nozzle_lattice(e, spacing).offsets)
        points.push_back(e.position + o.x * width_axis + o.y * height_axis);
    return points;
}

void check_nozzle_place(const EmitterSpec& e, const std::string& path, const SceneBasics& scene) {
    const float s = scene.particle_spacing;
    const Box& d = scene.domain;
    for (const glm::vec3& p : nozzle_points(e, s)) {
        for (int a = 0; a < 3; ++a)
            if (!(p[a] >= d.min[a] + 0.25f * s && p[a] <= d.max[a] - 0.25f * s))
                fail(path + " reaches " + fmt(p) + ", outside the tank " + fmt(d) + " on " + "xyz"[a] +
                     ": its water would start in the wall; move the nozzle (position, radius or size) inside the tank");
        for (size_t b = 0; b < scene.static_boxes.size(); ++b)
            if (scene.static_boxes[b].contains(p))
                fail(path + " reaches " + fmt(p) + ", inside static_boxes[" + std::to_string(b) + "] " +
                     fmt(scene.static_boxes[b]) + "; water cannot start inside a solid: move the nozzle out of it");
        if (inside_start_solid(scene.obstacles, p))
            fail(path + " reaches " + fmt(p) +
                 ", inside an obstacle; water cannot start inside a solid: move the nozzle out of it (the nozzle's "
                 "face should lie on the solid's surface or in the open)");
    }
}

EmitterSpec read_emitter(const std::string& name, const json& v, const std::string& path, const SceneBasics& scene) {
    if (!v.is_object())
        fail(path + " must be an object such as " + std::string(kEmitterExample) + ", got " + written(v));
    check_keys(v, "in " + path, kEmitterKeys);
    EmitterSpec e;
    e.name = name;
    const float s = scene.particle_spacing;
    const Box& d = scene.domain;
    require(v, "speed", "in " + path, "\"speed\": 1.0");
    e.speed = read_speed(v["speed"], path + ".speed");
    const int shapes = int(v.contains("radius")) + int(v.contains("size")) + int(v.contains("wall"));
    if (shapes != 1)
        fail(path + (shapes == 0 ? " has no shape" : " has more than one shape") +
             "; give exactly one of \"radius\" (a disc), \"size\": [width, height] (a rectangle) or \"wall\" (an "
             "inflow over a side wall of the tank)");
    if (v.contains("wall")) {
        // An inflow: a rectangle across the whole wall from the floor up, half a spacing in.
        for (const char* key : {"position", "direction"})
            if (v.contains(key))
                fail(path + " has \"wall\" and \"" + key +
                     "\"; an inflow's place and direction are its wall's: remove \"" + key + "\"");
        const auto [axis, at_max] = read_wall(v["wall"], path + ".wall");
        const int across = 2 - axis;  // x walls span z, z walls span x
        const float height = v.contains("height")
                                 ? read_number(v["height"], path + ".height",
                                               {0.0, d.max.y - d.min.y, true, false,
                                                "a height above the floor in metres, at most the tank's"})
                                 : d.max.y - d.min.y;
        e.shape = EmitterSpec::Shape::rectangle;
        e.direction = glm::vec3(0.0f);
        e.direction[axis] = at_max ? -1.0f : 1.0f;
        e.position[axis] = at_max ? d.max[axis] - 0.5f * s : d.min[axis] + 0.5f * s;
        e.position[across] = 0.5f * (d.min[across] + d.max[across]);
        e.position.y = d.min.y + 0.5f * height;
        e.size = glm::vec2(d.max[across] - d.min[across], height);
    } else {
        if (v.contains("height"))
            fail(path +
                 ".height belongs to an inflow over a wall (\"wall\"); a nozzle's size is its \"radius\" or "
                 "\"size\": remove \"height\"");
        require(v, "position", "in " + path, "\"position\": [0.3, 0.5, 0.3]");
        require(v, "direction", "in " + path, "\"direction\": [0, -1, 0]");
        e.position = read_vec3(v["position"], path + ".position", "the nozzle's centre [x, y, z]");
        e.direction = read_unit(v["direction"], path + ".direction");
        const Range side{0.0, HUGE_VAL, true, false, "a size in metres above 0"};
        if (v.contains("radius")) {
            e.shape = EmitterSpec::Shape::disc;
            e.radius = read_number(v["radius"], path + ".radius", side);
        } else {
            e.shape = EmitterSpec::Shape::rectangle;
            const json& size = v["size"];
            if (!size.is_array() || size.size() != 2)
                fail(path + ".size must be [width, height] in metres, got " + written(size));
            e.size =
                glm::vec2(read_number(size[0], path + ".size[0]", side), read_number(size[1], path + ".size[1]", side));
        }
    }
    if (const std::string small = nozzle_too_small(e, s); !small.empty())
        fail(path + (e.shape == EmitterSpec::Shape::disc ? ".radius" : ".size") + ": " + small +
             "; make the nozzle larger or particle_spacing finer");
    if (v.contains("start"))
        e.start = read_number(v["start"], path + ".start", {0.0, HUGE_VAL, false, false, "a time in seconds, from 0"});
    if (v.contains("stop")) {
        e.stop = read_number(v["stop"], path + ".stop", {0.0, HUGE_VAL, false, false, "a time in seconds"});
        if (!(e.stop > e.start))
            fail(path + ".stop " + fmt(e.stop) + " s is not after its start " + fmt(e.start) +
                 " s, so the nozzle never opens; give a stop after the start");
    }
    check_nozzle_place(e, path, scene);
    return e;
}

}  // namespace

std::string emitter_names(const std::vector<EmitterSpec>& emitters) {
    std::vector<std::string> names;
    for (const EmitterSpec& e : emitters) names.push_back(e.name);
    return quoted_list(names);
}

Result<bool> check_nozzle(const EmitterSpec& e, const std::string& path, const SceneBasics& scene) {
    try {
        check_nozzle_place(e, path, scene);
    } catch (const Invalid& error) {
        return Error{error.message};
    }
    return true;
}

float EmitterSpec::area() const { return shape == Shape::disc ? float(M_PI) * radius * radius : size.x * size.y; }

namespace {
float keyed_speed(const std::vector<SpeedKey>& keys, double t) {
    if (keys.empty()) return 0.0f;
    if (t <= keys.front().time) return keys.front().speed;
    for (size_t i = 1; i < keys.size(); ++i)
        if (t < keys[i].time) {
            const double u = (t - keys[i - 1].time) / (keys[i].time - keys[i - 1].time);
            return float(keys[i - 1].speed + u * (keys[i].speed - keys[i - 1].speed));
        }
    return keys.back().speed;
}
}  // namespace

float EmitterSpec::speed_at(double t) const { return t >= start && t < stop ? keyed_speed(speed, t) : 0.0f; }

float EmitterSpec::max_speed(double t0, double t1) const {
    // Linear between keys: the largest is at an end or a key inside the interval.
    float top = std::max(speed_at(t0), speed_at(std::nextafter(std::min(t1, stop), 0.0)));
    if (t0 <= start && start <= t1) top = std::max(top, speed_at(start));
    for (const SpeedKey& k : speed)
        if (k.time >= t0 && k.time <= t1) top = std::max(top, speed_at(k.time));
    return top;
}

double EmitterSpec::distance_at(double t) const {
    const double end = std::min(t, stop);
    if (end <= start) return 0.0;
    // The trapezoid rule is exact for a speed linear between the points: the keys inside and the ends.
    std::vector<double> times{start};
    for (const SpeedKey& k : speed)
        if (k.time > start && k.time < end) times.push_back(k.time);
    times.push_back(end);
    double distance = 0.0;
    for (size_t i = 1; i < times.size(); ++i)
        distance += 0.5 * (times[i] - times[i - 1]) *
                    (double(keyed_speed(speed, times[i - 1])) + double(keyed_speed(speed, times[i])));
    return distance;
}

std::pair<glm::vec3, glm::vec3> EmitterSpec::across_axes() const {
    glm::vec3 up = glm::vec3(0.0f, 1.0f, 0.0f) - direction.y * direction;
    if (glm::length(up) < 1e-3f) up = glm::vec3(0.0f, 0.0f, 1.0f) - direction.z * direction;  // a vertical nozzle
    up = glm::normalize(up);
    return {glm::normalize(glm::cross(up, direction)), up};
}

bool EmitterSpec::holds(const glm::vec3& p, float spacing, float depth) const {
    const glm::vec3 d = p - position;
    const float along = glm::dot(d, direction);
    if (!(along >= -0.5f * spacing && along < depth + 0.5f * spacing)) return false;
    const auto [width_axis, height_axis] = across_axes();
    const glm::vec2 across(glm::dot(d, width_axis), glm::dot(d, height_axis));
    if (shape == Shape::disc) return glm::length(across) < radius + 0.5f * spacing;
    return std::abs(across.x) < 0.5f * (size.x + spacing) && std::abs(across.y) < 0.5f * (size.y + spacing);
}

std::string nozzle_too_small(const EmitterSpec& e, float s) {
    // A layer is one particle deep: a nozzle narrower than a particle would emit a thread of
    // particles far apart along it (its layers n s^3 / area apart), not a jet.
    if (e.shape == EmitterSpec::Shape::disc && !(e.area() >= s * s))
        return "a radius of " + fmt(e.radius) +
               " m gives the nozzle less area than one particle's cross-section at "
               "particle_spacing " +
               fmt(s) + " m (a radius of at least " + fmt(0.565f * s) + " m)";
    if (e.shape == EmitterSpec::Shape::rectangle && !(std::min(e.size.x, e.size.y) >= s))
        return fmt(e.size.x) + " by " + fmt(e.size.y) + " m is narrower than particle_spacing " + fmt(s) + " m";
    return {};
}

shader::FlowSink SinkSpec::packed(uint32_t first_node) const {
    switch (kind) {
        case Kind::box:
            return {glm::vec4(box.min, float(FLOW_SINK_BOX)), glm::vec4(box.max, 0.0f), glm::uvec4(0u)};
        case Kind::plane:
            return {glm::vec4(point, float(FLOW_SINK_PLANE)), glm::vec4(normal, 0.0f), glm::uvec4(0u)};
        case Kind::mesh:
            break;
    }
    return {glm::vec4(field->grid.origin, float(FLOW_SINK_MESH)), glm::vec4(field->grid.cell, 0.0f, 0.0f, 0.0f),
            glm::uvec4(field->grid.dims, first_node)};
}

bool SinkSpec::contains(const glm::vec3& p) const { return shader::flow_in_sink(packed(0), p, nodes().data()); }

const std::vector<float>& SinkSpec::nodes() const {
    static const std::vector<float> none;
    return field ? field->distance : none;
}

NozzleLattice nozzle_lattice(const EmitterSpec& e, float s) {
    NozzleLattice lattice;
    if (e.shape == EmitterSpec::Shape::rectangle) {
        const int nw = std::max(1, int(std::lround(e.size.x / s))), nh = std::max(1, int(std::lround(e.size.y / s)));
        for (int j = 0; j < nh; ++j)
            for (int i = 0; i < nw; ++i)
                lattice.offsets.emplace_back((float(i) + 0.5f) * e.size.x / float(nw) - 0.5f * e.size.x,
                                             (float(j) + 0.5f) * e.size.y / float(nh) - 0.5f * e.size.y);
    } else {
        const float target = e.area() / (s * s);
        const int reach = int(std::ceil(e.radius / s)) + 1;
        std::vector<glm::vec2> best;
        for (float centring : {0.0f, 0.5f}) {
            std::vector<glm::vec2> points;
            for (int j = -reach; j <= reach; ++j)
                for (int i = -reach; i <= reach; ++i) {
                    const glm::vec2 p((float(i) + centring) * s, (float(j) + centring) * s);
                    if (glm::length(p) < e.radius) points.push_back(p);
                }
            if (best.empty() || std::abs(float(points.size()) - target) < std::abs(float(best.size()) - target))
                best = points;
        }
        const float scale = best.empty() ? 1.0f : std::sqrt(e.area() / (float(best.size()) * s * s));
        for (glm::vec2& p : best) p *= scale;
        lattice.offsets = best;
    }
    lattice.layer_spacing = float(double(lattice.offsets.size()) * s * s * s / double(e.area()));
    return lattice;
}

std::vector<EmitterSpec> read_emitters(const json& v, const SceneBasics& scene) {
    std::vector<EmitterSpec> emitters;
    read_named(v, "emitters", kMaxEmitters, kEmitterExample, kTableFix,
               [&](const std::string& name, const json& e, const std::string& path) {
                   emitters.push_back(read_emitter(name, e, path, scene));
               });
    return emitters;
}

namespace {

/// A mesh sink: the OBJ placed in the world, and its signed distances on nodes half a particle
/// spacing apart reaching a spacing beyond it (so that the sign is sampled all round it).
void read_sink_mesh(SinkSpec& sink, const json& v, const std::string& path, const SceneBasics& scene,
                    const std::filesystem::path& base_dir) {
    if (!v.is_object())
        fail(path + " must be {\"file\": \"../meshes/sphere.obj\", \"placement\": {...}}, got " + written(v));
    check_keys(v, "in " + path, kSinkMeshKeys);
    require(v, "file", "in " + path, "\"file\": \"../meshes/sphere.obj\"");
    if (!v["file"].is_string()) fail(path + ".file must be a path string, got " + written(v["file"]));
    sink.kind = SinkSpec::Kind::mesh;
    sink.file = base_dir / v["file"].get<std::string>();
    auto loaded = geometry::load_obj(sink.file);  // refuses meshes without volume, with NaNs or large holes
    if (!loaded) fail(path + ".file: " + loaded.error());
    geometry::Mesh mesh = std::move(loaded.value().mesh);
    if (v.contains("placement")) geometry::apply(geometry::parse_placement(v["placement"], path + ".placement"), mesh);
    const float s = scene.particle_spacing;
    auto field = geometry::build_distance_field(mesh.triangle_soup(), 0.5f * s, s, "sink " + sink.name);
    if (!field)
        fail(path + ": " + field.error() + "; scale the mesh down (" + path +
             ".placement.scale) or use a box or plane sink");
    sink.field = std::make_shared<const geometry::DistanceField>(std::move(field.value()));
}

/// Where to look for a sink's reach in the tank: a lattice of kProbe points an axis over the tank
/// (its corners included) and, for a mesh, its nodes inside the tank.
constexpr int kProbe = 17;
std::vector<glm::vec3> tank_points(const Box& d) {
    std::vector<glm::vec3> points;
    for (int k = 0; k < kProbe; ++k)
        for (int j = 0; j < kProbe; ++j)
            for (int i = 0; i < kProbe; ++i)
                points.push_back(d.min + (d.max - d.min) * glm::vec3(i, j, k) / float(kProbe - 1));
    return points;
}

bool reaches_into(const SinkSpec& sink, const Box& d, const std::vector<glm::vec3>& tank) {
    if (std::any_of(tank.begin(), tank.end(), [&](const glm::vec3& p) { return sink.contains(p); })) return true;
    if (sink.kind == SinkSpec::Kind::box)
        return glm::all(glm::lessThanEqual(sink.box.min, d.max)) && glm::all(glm::lessThanEqual(d.min, sink.box.max));
    if (sink.kind == SinkSpec::Kind::mesh)
        for (size_t n = 0; n < sink.field->grid.node_count(); ++n) {
            const glm::vec3 p = sink.field->grid.position(sink.field->grid.node_of(n));
            if (d.contains(p) && sink.field->distance[n] < 0.0f) return true;
        }
    return false;
}

}  // namespace

std::vector<SinkSpec> read_sinks(const json& v, const SceneBasics& scene, const std::vector<EmitterSpec>& emitters,
                                 const std::filesystem::path& base_dir) {
    std::vector<SinkSpec> sinks;
    const Box& d = scene.domain;
    const std::vector<glm::vec3> tank = tank_points(d);
    read_named(
        v, "sinks", kMaxSinks, "{\"drain\": {\"box\": {\"min\": [0, 0, 0], \"max\": [0.1, 0.05, 0.1]}}}", kTableFix,
        [&](const std::string& name, const json& s, const std::string& path) {
            if (!s.is_object() || s.size() != 1) fail(path + " must be one of " + kSinkShapes + ", got " + written(s));
            check_keys(s, "in " + path, kSinkKeys);
            SinkSpec sink;
            sink.name = name;
            if (s.contains("box")) {
                sink.kind = SinkSpec::Kind::box;
                sink.box = read_box(s["box"], path + ".box", "{\"min\": [0, 0, 0], \"max\": [0.1, 0.05, 0.1]}");
            } else if (s.contains("mesh")) {
                read_sink_mesh(sink, s["mesh"], path + ".mesh", scene, base_dir);
            } else {
                const json& plane = s["plane"];
                if (!plane.is_object())
                    fail(path + ".plane must be {\"point\": [x, y, z], \"normal\": [1, 0, 0]}, got " + written(plane));
                check_keys(plane, "in " + path + ".plane", kPlaneKeys);
                require(plane, "point", "in " + path + ".plane", "\"point\": [1.0, 0, 0]");
                require(plane, "normal", "in " + path + ".plane", "\"normal\": [1, 0, 0]");
                sink.kind = SinkSpec::Kind::plane;
                sink.point = read_vec3(plane["point"], path + ".plane.point", "a point on the plane [x, y, z]");
                sink.normal = read_unit(plane["normal"], path + ".plane.normal");
            }
            // A sink is where water leaves a scene that goes on: one that takes all of the tank, or
            // takes water as a nozzle makes it, leaves nothing to simulate; one that takes none of
            // it would never remove anything (a typo'd coordinate, a normal the wrong way round).
            if (std::all_of(tank.begin(), tank.end(), [&](const glm::vec3& c) { return sink.contains(c); }))
                fail(path + " takes the whole tank " + fmt(d) +
                     ", so every particle would be removed at once; make it cover only where water should leave "
                     "(an outlet, a drain, a region far from the action)");
            if (!reaches_into(sink, d, tank))
                fail(path + " lies wholly outside the tank " + fmt(d) + ", so it would never remove anything; " +
                     (sink.kind == SinkSpec::Kind::plane ? "turn its normal round or move its point into the tank"
                                                         : "move it into the tank"));
            for (const EmitterSpec& e : emitters)
                for (const glm::vec3& p : nozzle_points(e, scene.particle_spacing))
                    if (sink.contains(p))
                        fail(path + " covers emitters." + e.name + " (its nozzle reaches " + fmt(p) +
                             "), so its water would be removed as it is made; move the sink away from the nozzle");
            sinks.push_back(sink);
        });
    return sinks;
}

}  // namespace aquaform
