#include "sim/obstacles.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/file_name.h"
#include "core/json_fields.h"
#include "geometry/animation.h"
#include "geometry/inside.h"

namespace aquaform {

class StartSolid {
public:
    explicit StartSolid(const geometry::Mesh& mesh)
        : triangles_(mesh.triangle_soup()), bounds_(mesh.bounds()), test_(triangles_) {}
    bool contains(const glm::vec3& p) const {
        for (int a = 0; a < 3; ++a)
            if (p[a] < bounds_.min[a] || p[a] > bounds_.max[a]) return false;
        return test_.contains(p);
    }
    const Box& bounds() const { return bounds_; }

private:
    std::vector<glm::vec3> triangles_;  // before test_, which keeps a reference to them
    Box bounds_;
    geometry::InsideTest test_;
};

namespace {

using namespace json_fields;

constexpr std::string_view kObstacleKeys[] = {"file", "placement", "animation"};
constexpr const char* kExample =
    "{\"rock\": {\"file\": \"../meshes/sphere.obj\", \"placement\": {\"position\": [0.5, 0.1, 0.2]}}}";

/// Times at which a motion is checked: every key (so that no key, however close to the next,
/// aliases away: between keys the motion is interpolated, and its speed is that of the span), and
/// for interpolated motions kMotionSamples steps from start to end for the curved paths between
/// them. A sequence holds each frame until the next: its speed is a frame's move times the frame
/// rate, seen from key to key. A still obstacle: t = 0 alone.
constexpr int kMotionSamples = 480;
std::vector<double> check_times(const geometry::MeshAnimation& a) {
    if (!a.moves()) return {0.0};
    std::vector<double> t = a.key_times();
    const double end = std::max(a.duration(), 1e-6);
    if (!std::holds_alternative<geometry::SequenceAnimation>(a.kind()))
        for (int k = 0; k <= kMotionSamples; ++k) t.push_back(end * k / kMotionSamples);
    std::sort(t.begin(), t.end());
    t.erase(std::unique(t.begin(), t.end()), t.end());
    return t;
}

/// The largest distance any vertex moves between two poses of one mesh (a sequence's frames
/// may differ in vertices: then the corners of their bounds stand in).
double largest_move(const geometry::Mesh& a, const geometry::Mesh& b) {
    double d = 0.0;
    if (a.vertices.size() == b.vertices.size()) {
        for (size_t i = 0; i < a.vertices.size(); ++i)
            d = std::max(d, double(glm::length(a.vertices[i] - b.vertices[i])));
        return d;
    }
    const Box ba = a.bounds(), bb = b.bounds();
    return std::max(double(glm::length(ba.min - bb.min)), double(glm::length(ba.max - bb.max)));
}

ObstacleSpec read_obstacle(const json& v, const std::string& name, const std::string& path, const SceneBasics& scene,
                           const std::filesystem::path& base_dir) {
    if (!v.is_object())
        fail(path + " must be an object such as {\"file\": \"../meshes/sphere.obj\"}, got " + written(v));
    check_keys(v, "in " + path, kObstacleKeys);
    ObstacleSpec o;
    o.name = name;
    geometry::MeshAnimation motion;
    if (v.contains("animation")) motion = geometry::parse_animation(v["animation"], path + ".animation", base_dir);
    if (const auto* rigid = std::get_if<geometry::RigidAnimation>(&motion.kind()))
        for (size_t k = 0; k < rigid->keys.size(); ++k)
            if (rigid->keys[k].scale != 1.0f)
                fail(path + ".animation.keyframes[" + std::to_string(k) + "].scale is " + fmt(rigid->keys[k].scale) +
                     "; an obstacle keeps its size as it moves (its boundary is made once, at that size): give the "
                     "size in " +
                     path + ".placement.scale and leave scale out of the keyframes");
    const bool sequence = std::holds_alternative<geometry::SequenceAnimation>(motion.kind());
    if (!sequence) require(v, "file", "in " + path, "\"file\": \"../meshes/sphere.obj\"");
    geometry::MeshPlacement placement;
    if (v.contains("placement")) placement = geometry::parse_placement(v["placement"], path + ".placement");
    geometry::Mesh rest;
    geometry::MeshReport report;
    if (v.contains("file")) {
        if (!v["file"].is_string()) fail(path + ".file must be a path string, got " + written(v["file"]));
        o.file = base_dir / v["file"].get<std::string>();
        auto loaded = geometry::load_obj(o.file);  // refuses meshes without volume or with large holes
        if (!loaded) fail(path + ".file: " + loaded.error());
        rest = std::move(loaded.value().mesh);
        report = loaded.value().report;
    }
    motion.bind(rest, placement);
    o.moves = motion.moves();
    o.deforms = motion.deforms();
    if (!sequence && !report.watertight()) o.mesh_notes = geometry::describe(report);

    // The obstacle must stay in the tank (within a particle spacing: a box may stand on the floor),
    // and its fastest point must move slowly enough for the time-step rule.
    const float slack = scene.particle_spacing;
    geometry::Mesh last;
    double last_t = 0.0;
    for (double t : check_times(motion)) {
        geometry::Mesh now = motion.mesh_at(t);
        const Box b = now.bounds();
        for (int a = 0; a < 3; ++a)
            if (b.min[a] < scene.domain.min[a] - slack || b.max[a] > scene.domain.max[a] + slack)
                fail(path + (o.moves ? " at t = " + fmt(t) + " s" : std::string()) + " stands at " + fmt(b) +
                     ", which reaches outside the tank " + fmt(scene.domain) + " on " + "xyz"[a] +
                     "; particles cannot reach it there and the solver does not cut it: move or scale it inside (" +
                     path + ".placement: position, scale or fit_into" + (o.moves ? ", or its animation" : "") + ")");
        if (t > last_t) o.max_speed = std::max(o.max_speed, largest_move(last, now) / (t - last_t));
        last = std::move(now);
        last_t = t;
    }
    // Its speed against the time-step rule is checked with the whole scene's (speed_beyond_step_rule).
    o.start = std::make_shared<StartSolid>(motion.mesh_at(0.0));
    o.shape = std::make_shared<geometry::MeshAnimation>(std::move(motion));
    return o;
}

/// An obstacle's name becomes part of its files' names (exports/obstacle_export.h): the file name rule.
void check_name(const std::string& name) {
    if (!is_file_name(name))
        fail("obstacles: the name " + written(json(name)) +
             " cannot name the obstacle's files (obstacle_<name>.obj); a name "
             "is " +
             std::string(kFileNameRule) + ", e.g. \"rock_1\": rename it");
}

std::string lower(std::string text) {
    for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

/// Whether a still solid named `still` writes the file a moving one named `moving` writes at some
/// frame (obstacle_<moving>_NNNN.obj), compared without case as a case-insensitive disk would.
bool takes_frame_file(const std::string& still, const std::string& moving) {
    const std::string s = lower(still), prefix = lower(moving) + "_";
    return s.size() >= prefix.size() + 4 && s.compare(0, prefix.size(), prefix) == 0 &&
           std::all_of(s.begin() + std::ptrdiff_t(prefix.size()), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// Two solids never share a file: the static boxes' obstacle_static_box_<i>.obj, a still obstacle's
/// obstacle_<name>.obj and a moving one's obstacle_<name>_NNNN.obj.
void check_files_apart(const std::vector<ObstacleSpec>& obstacles, size_t static_boxes) {
    struct Solid {
        std::string name, path;
        bool moves;
    };
    std::vector<Solid> solids;
    for (size_t b = 0; b < static_boxes; ++b)
        solids.push_back({"static_box_" + std::to_string(b), "static_boxes[" + std::to_string(b) + "]", false});
    for (const ObstacleSpec& o : obstacles) solids.push_back({o.name, "obstacles." + o.name, o.moves});
    for (size_t i = 0; i < solids.size(); ++i)
        for (size_t j = 0; j < solids.size(); ++j) {
            const Solid &a = solids[i], &b = solids[j];
            const bool same = i < j && a.moves == b.moves && lower(a.name) == lower(b.name);
            const bool frame = !a.moves && b.moves && takes_frame_file(a.name, b.name);
            if (same || frame)
                fail(a.path + " and " + b.path + " would write the same file (" +
                     (frame ? "obstacle_" + a.name + ".obj is one of " + b.path + "'s frames, obstacle_" + b.name +
                                  "_NNNN.obj"
                            : "obstacle_" + a.name + (a.moves ? "_NNNN" : "") + ".obj, names compared without case") +
                     "); rename one of them");
        }
}

}  // namespace

double max_obstacle_speed(const SceneBasics& scene) {
    const double h = double(scene.solver.kernel_radius_factor) * scene.particle_spacing;
    return double(scene.solver.cfl) * h * double(std::max(scene.solver.max_substeps, scene.solver.substeps)) /
           double(scene.solver.frame_dt);
}

std::vector<ObstacleSpec> read_obstacles(const json& v, const SceneBasics& scene, const std::filesystem::path& base_dir,
                                         size_t slots) {
    if (!v.is_object())
        fail("obstacles must be an object of named obstacles, e.g. " + std::string(kExample) + ", got " + written(v));
    if (v.size() > slots)
        fail("obstacles has " + std::to_string(v.size()) + " entries but the solver takes " + std::to_string(slots) +
             " more solids besides the static_boxes (" + std::to_string(scene.static_boxes.size()) +
             "); join meshes into one OBJ (an obstacle may have several parts)");
    std::vector<ObstacleSpec> out;
    for (const auto& [name, entry] : v.items()) {
        check_name(name);
        out.push_back(read_obstacle(entry, name, "obstacles." + name, scene, base_dir));
    }
    check_files_apart(out, scene.static_boxes.size());
    return out;
}

bool inside_start_solid(const std::vector<ObstacleSpec>& obstacles, const glm::vec3& p) {
    for (const ObstacleSpec& o : obstacles)
        if (o.start && o.start->contains(p)) return true;
    return false;
}

std::vector<Box> start_solid_bounds(const std::vector<ObstacleSpec>& obstacles) {
    std::vector<Box> out;
    for (const ObstacleSpec& o : obstacles)
        if (o.start) out.push_back(o.start->bounds());
    return out;
}

}  // namespace aquaform
