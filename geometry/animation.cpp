// Mesh placement and animation: parsing with messages that name the key path, and evaluation at a
// time (see animation.h for the conventions).
#include "geometry/animation.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "core/json_fields.h"

namespace aquaform::geometry {

using namespace json_fields;
namespace fs = std::filesystem;

namespace {

constexpr std::string_view kPlacementKeys[] = {"position", "rotation_degrees", "scale", "fit_into"};
constexpr std::string_view kRigidKeys[] = {"keyframes", "loop"};
constexpr std::string_view kRigidKeyKeys[] = {"t", "position", "rotation_degrees", "scale"};
constexpr std::string_view kSequenceKeys[] = {"sequence", "first", "count", "fps", "loop"};
constexpr std::string_view kSkeletalKeys[] = {"skeleton", "keyframes", "loop"};
constexpr std::string_view kPoseKeyKeys[] = {"t", "root_offset", "rotations_degrees"};
constexpr size_t kMaxKeys = 100000;
constexpr uint32_t kMaxFrames = 100000;

constexpr const char* kPointWhat = "an array of three numbers [x, y, z] in metres";
constexpr const char* kAnglesWhat = "an array of three angles in degrees [x, y, z], applied X, then Y, then Z";
const Range kScaleRange{0.0, 1e6, true, false, "a positive number (1 keeps the size)"};
constexpr const char* kKindsHelp =
    "say how the mesh moves with \"keyframes\" (rigid motion, e.g. {\"keyframes\": [{\"t\": 0}, {\"t\": 2, "
    "\"position\": [0, 0.3, 0]}]}), \"sequence\" (OBJ frames, e.g. {\"sequence\": \"walk_%03d.obj\", \"count\": "
    "24, \"fps\": 24}) or \"skeleton\" with \"keyframes\" (skinning)";

std::string where(const std::string& path) { return path.empty() ? "at top level" : "in " + path; }
std::string item(const std::string& path, size_t i) { return path + "[" + std::to_string(i) + "]"; }

bool read_loop(const json& v, const std::string& path) {
    if (!v.contains("loop")) return false;
    if (!v["loop"].is_boolean())
        fail(child(path, "loop") + " must be true or false, got " + written(v["loop"]) + " (" + kind_of(v["loop"]) +
             ")");
    return v["loop"].get<bool>();
}

/// The "keyframes" array, checked for size; each element is read by the caller.
const json& read_key_list(const json& v, const std::string& path, const char* example) {
    require(v, "keyframes", where(path), std::string("\"keyframes\": [") + example + "]");
    const json& keys = v["keyframes"];
    if (!keys.is_array() || keys.empty() || keys.size() > kMaxKeys)
        fail(child(path, "keyframes") + " must be an array of 1 to " + std::to_string(kMaxKeys) + " keys such as [" +
             example + "], got " + written(keys) + " (" + kind_of(keys) + ")");
    return keys;
}

/// Reads key i's "t" and checks it comes after the previous key.
double read_time(const json& key, const std::string& key_path, const std::vector<double>& earlier) {
    require(key, "t", "in " + key_path, "\"t\": 0.5 (seconds)");
    read_number(key["t"], key_path + ".t", {-1e9, 1e9, false, false, "a time in seconds"});
    const double t = key["t"].get<double>();
    if (!earlier.empty() && !(t > earlier.back()))
        fail(key_path + ".t is " + written(key["t"]) + " but the key before it is at t = " + fmt(earlier.back()) +
             "; key times must increase strictly (list the keys in time order, no two at the same time)");
    return t;
}

void check_key_object(const json& key, const std::string& key_path, std::span<const std::string_view> keys,
                      const char* example) {
    if (!key.is_object())
        fail(key_path + " must be an object such as " + std::string(example) + ", got " + written(key));
    check_keys(key, "in " + key_path, keys);
}

RigidAnimation parse_rigid(const json& v, const std::string& path) {
    constexpr const char* kExample =
        "{\"t\": 0, \"position\": [0, 0, 0], \"rotation_degrees\": [0, 0, 0], \"scale\": 1}";
    check_keys(v, where(path), kRigidKeys);
    RigidAnimation anim;
    anim.loop = read_loop(v, path);
    const json& keys = read_key_list(v, path, kExample);
    for (size_t i = 0; i < keys.size(); ++i) {
        const json& k = keys[i];
        const std::string kp = item(child(path, "keyframes"), i);
        check_key_object(k, kp, kRigidKeyKeys, kExample);
        anim.times.push_back(read_time(k, kp, anim.times));
        RigidKey key;
        if (k.contains("position")) key.position = read_vec3(k["position"], kp + ".position", kPointWhat);
        if (k.contains("rotation_degrees"))
            key.rotation =
                rotation_xyz_degrees(read_vec3(k["rotation_degrees"], kp + ".rotation_degrees", kAnglesWhat));
        if (k.contains("scale")) key.scale = read_number(k["scale"], kp + ".scale", kScaleRange);
        anim.keys.push_back(key);
    }
    return anim;
}

/// "walk_%03d.obj" split around its one %d conversion (optional 0 flag and width); "%%" is a literal %.
struct FramePattern {
    std::string before, after;
    int width = 0;
    bool zero_pad = false;

    std::string name(uint64_t number) const {
        std::string digits = std::to_string(number);
        if (digits.size() < size_t(width)) digits.insert(0, size_t(width) - digits.size(), zero_pad ? '0' : ' ');
        return before + digits + after;
    }
};

FramePattern parse_pattern(const json& v, const std::string& key_path) {
    const std::string fix =
        "; write the file name with one frame-number placeholder, e.g. \"walk_%03d.obj\" for "
        "walk_000.obj, walk_001.obj, ...";
    if (!v.is_string() || v.get<std::string>().empty())
        fail(key_path + " must be a file name pattern, got " + written(v) + " (" + kind_of(v) + ")" + fix);
    const std::string text = v.get<std::string>();
    FramePattern p;
    bool found = false;
    for (size_t i = 0; i < text.size(); ++i) {
        std::string& out = found ? p.after : p.before;
        if (text[i] != '%') {
            out += text[i];
            continue;
        }
        if (i + 1 < text.size() && text[i + 1] == '%') {
            out += '%';
            ++i;
            continue;
        }
        size_t j = i + 1;
        const bool zero = j < text.size() && text[j] == '0';
        if (zero) ++j;
        const size_t digits_start = j;
        while (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j])) && j - digits_start < 2) ++j;
        if (j >= text.size() || text[j] != 'd' || found)
            fail(key_path + " is " + written(v) + (found ? ", which has more than one %" : ", whose % is not %d") +
                 fix);
        found = true;
        p.zero_pad = zero;
        p.width = j > digits_start ? std::stoi(text.substr(digits_start, j - digits_start)) : 0;
        i = j;
    }
    if (!found) fail(key_path + " is " + written(v) + ", which has no frame number (%d)" + fix);
    return p;
}

SequenceAnimation parse_sequence(const json& v, const std::string& path, const fs::path& base_dir) {
    check_keys(v, where(path), kSequenceKeys);
    const std::string example = "\"sequence\": \"walk_%03d.obj\", \"count\": 24, \"fps\": 24";
    require(v, "count", where(path), example);
    require(v, "fps", where(path), example);
    const std::string seq_path = child(path, "sequence");
    const FramePattern pattern = parse_pattern(v["sequence"], seq_path);
    const uint32_t first = v.contains("first") ? read_integer(v["first"], child(path, "first"), 0, 1000000000) : 0;
    const uint32_t count = read_integer(v["count"], child(path, "count"), 1, kMaxFrames);
    SequenceAnimation anim;
    anim.fps = read_number(v["fps"], child(path, "fps"),
                           {0.0, 10000.0, true, false, "a positive number of frames per second, e.g. 24"});
    anim.loop = read_loop(v, path);
    auto frames = std::make_shared<std::vector<Mesh>>();
    for (uint32_t f = 0; f < count; ++f) {
        const uint64_t number = uint64_t(first) + f;
        const fs::path file = base_dir / pattern.name(number);
        std::error_code ec;
        if (!fs::is_regular_file(file, ec))
            fail(seq_path + " is " + written(v["sequence"]) + " but frame " + std::to_string(number) + " (\"" +
                 file.string() + "\") does not exist; the sequence needs frames " + std::to_string(first) + " to " +
                 std::to_string(uint64_t(first) + count - 1) + ": add the file or correct \"first\" and \"count\"");
        Result<LoadedMesh> loaded = load_obj(file);
        if (!loaded) fail(seq_path + " frame " + std::to_string(number) + ": " + loaded.error());
        frames->push_back(std::move(loaded).value().mesh);
        anim.files.push_back(file);
    }
    anim.frames = std::move(frames);
    return anim;
}

SkeletalAnimation parse_skeletal(const json& v, const std::string& path) {
    constexpr const char* kExample =
        "{\"t\": 0, \"root_offset\": [0, 0, 0], \"rotations_degrees\": {\"thigh_l\": [-25, 0, 0]}}";
    check_keys(v, where(path), kSkeletalKeys);
    SkeletalAnimation anim;
    anim.skeleton = parse_skeleton(v["skeleton"], child(path, "skeleton"));
    anim.loop = read_loop(v, path);
    std::vector<std::string_view> bone_names;
    for (const Bone& b : anim.skeleton.bones) bone_names.push_back(b.name);
    const json& keys = read_key_list(v, path, kExample);
    for (size_t i = 0; i < keys.size(); ++i) {
        const json& k = keys[i];
        const std::string kp = item(child(path, "keyframes"), i);
        check_key_object(k, kp, kPoseKeyKeys, kExample);
        anim.times.push_back(read_time(k, kp, anim.times));
        SkeletonPose pose;
        pose.rotations.assign(anim.skeleton.bones.size(), glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
        if (k.contains("root_offset")) pose.root_offset = read_vec3(k["root_offset"], kp + ".root_offset", kPointWhat);
        if (k.contains("rotations_degrees")) {
            const json& rotations = k["rotations_degrees"];
            const std::string rp = kp + ".rotations_degrees";
            if (!rotations.is_object())
                fail(rp + " must be an object of bone name to angles, e.g. {\"thigh_l\": [-25, 0, 0]}, got " +
                     written(rotations) + " (" + kind_of(rotations) + ")");
            check_keys(rotations, "in " + rp + " (keys are bone names of " + child(path, "skeleton") + ")", bone_names);
            for (const auto& [name, angles] : rotations.items())
                pose.rotations[size_t(anim.skeleton.find(name))] =
                    rotation_xyz_degrees(read_vec3(angles, rp + "." + name, kAnglesWhat));
        }
        anim.keys.push_back(std::move(pose));
    }
    return anim;
}

MeshAnimation parse_animation_object(const json& v, const std::string& path, const fs::path& base_dir) {
    if (!v.is_object())
        fail(path + " must be an object; " + kKindsHelp + "; got " + written(v) + " (" + kind_of(v) + ")");
    if (v.contains("sequence")) return MeshAnimation(parse_sequence(v, path, base_dir));
    if (v.contains("skeleton")) return MeshAnimation(parse_skeletal(v, path));
    if (v.contains("keyframes")) return MeshAnimation(parse_rigid(v, path));
    fail((path.empty() ? std::string("the animation") : path) + " is " + written(v) + "; " + kKindsHelp);
}

Mesh transformed(const Mesh& mesh, const glm::mat4& m) {
    Mesh out;
    out.faces = mesh.faces;
    out.vertices.reserve(mesh.vertices.size());
    for (const glm::vec3& v : mesh.vertices) out.vertices.push_back(glm::vec3(m * glm::vec4(v, 1.0f)));
    return out;
}

}  // namespace

glm::quat rotation_xyz_degrees(const glm::vec3& degrees) {
    const glm::vec3 r = glm::radians(degrees);
    return glm::angleAxis(r.z, glm::vec3(0, 0, 1)) * glm::angleAxis(r.y, glm::vec3(0, 1, 0)) *
           glm::angleAxis(r.x, glm::vec3(1, 0, 0));
}

MeshPlacement parse_placement(const json& v, const std::string& path) {
    if (!v.is_object())
        fail(path +
             " must be an object such as {\"position\": [0.5, 0.2, 0.5], \"rotation_degrees\": [0, 90, 0], "
             "\"scale\": 0.5}, got " +
             written(v) + " (" + kind_of(v) + ")");
    check_keys(v, where(path), kPlacementKeys);
    MeshPlacement p;
    if (v.contains("position")) p.position = read_vec3(v["position"], child(path, "position"), kPointWhat);
    if (v.contains("rotation_degrees"))
        p.rotation_degrees = read_vec3(v["rotation_degrees"], child(path, "rotation_degrees"), kAnglesWhat);
    if (v.contains("scale")) p.scale = read_number(v["scale"], child(path, "scale"), kScaleRange);
    if (v.contains("fit_into")) {
        for (const char* ignored : {"position", "scale"})
            if (v.contains(ignored))
                fail(child(path, ignored) +
                     " would be ignored: fit_into chooses the size and position itself; "
                     "remove \"" +
                     ignored + "\" or \"fit_into\"");
        p.fit_into = read_box(v["fit_into"], child(path, "fit_into"),
                              "\"fit_into\": {\"min\": [0.2, 0, 0.2], \"max\": [0.8, 0.6, 0.8]}");
    }
    return p;
}

glm::mat4 placement_matrix(const MeshPlacement& placement, const Mesh& rest) {
    const glm::mat4 rotation = glm::mat4_cast(rotation_xyz_degrees(placement.rotation_degrees));
    if (!placement.fit_into)
        return glm::translate(glm::mat4(1.0f), placement.position) * rotation *
               glm::scale(glm::mat4(1.0f), glm::vec3(placement.scale));
    // apply() owns the fitting rule; read its scale and offset back from the bounds it produces.
    Mesh rotated = rest, placed = rest;
    MeshPlacement rotate_only;
    rotate_only.rotation_degrees = placement.rotation_degrees;
    apply(rotate_only, rotated);
    apply(placement, placed);
    const Box a = rotated.bounds(), b = placed.bounds();
    const glm::vec3 extent = a.max - a.min;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const float s = extent[axis] > 0.0f ? (b.max[axis] - b.min[axis]) / extent[axis] : 1.0f;
    const glm::vec3 offset = (b.min + b.max) * 0.5f - s * (a.min + a.max) * 0.5f;
    return glm::translate(glm::mat4(1.0f), offset) * glm::scale(glm::mat4(1.0f), glm::vec3(s)) * rotation;
}

KeySpan locate_key(const std::vector<double>& times, double t, bool loop) {
    const size_t n = times.size();
    if (n <= 1 || !std::isfinite(t)) return {};
    const double first = times.front(), last = times.back();
    if (loop) t -= (last - first) * std::floor((t - first) / (last - first));
    if (t <= first) return {0, 0, 0.0f};
    if (t >= last) return {n - 1, n - 1, 0.0f};
    const size_t i = size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
    return {i, i + 1, static_cast<float>((t - times[i]) / (times[i + 1] - times[i]))};
}

glm::mat4 RigidAnimation::transform_at(double t, const glm::vec3& pivot) const {
    if (keys.empty()) return glm::mat4(1.0f);
    const KeySpan s = locate_key(times, t, loop);
    const RigidKey& a = keys[s.i0];
    const RigidKey& b = keys[s.i1];
    const glm::vec3 position = glm::mix(a.position, b.position, s.alpha);
    const float scale = glm::mix(a.scale, b.scale, s.alpha);
    const glm::quat rotation = glm::slerp(a.rotation, b.rotation, s.alpha);
    return glm::translate(glm::mat4(1.0f), pivot + position) * glm::mat4_cast(rotation) *
           glm::scale(glm::mat4(1.0f), glm::vec3(scale)) * glm::translate(glm::mat4(1.0f), -pivot);
}

size_t SequenceAnimation::frame_at(double t) const {
    const double count = double(frames ? frames->size() : 0);
    if (count == 0.0 || !std::isfinite(t)) return 0;
    double f = std::floor(t * double(fps) + 1e-6);
    f = loop ? f - count * std::floor(f / count) : std::clamp(f, 0.0, count - 1.0);
    return static_cast<size_t>(f);
}

SkeletonPose SkeletalAnimation::pose_at(double t) const {
    if (keys.empty()) return {glm::vec3(0.0f), std::vector<glm::quat>(skeleton.bones.size(), glm::quat(1, 0, 0, 0))};
    const KeySpan s = locate_key(times, t, loop);
    const SkeletonPose& a = keys[s.i0];
    const SkeletonPose& b = keys[s.i1];
    SkeletonPose pose;
    pose.root_offset = glm::mix(a.root_offset, b.root_offset, s.alpha);
    pose.rotations.resize(a.rotations.size());
    for (size_t i = 0; i < a.rotations.size(); ++i)
        pose.rotations[i] = glm::slerp(a.rotations[i], b.rotations[i], s.alpha);
    return pose;
}

double MeshAnimation::duration() const {
    if (const auto* r = std::get_if<RigidAnimation>(&kind_)) return r->times.back();
    if (const auto* q = std::get_if<SequenceAnimation>(&kind_)) return double(q->frames->size()) / double(q->fps);
    if (const auto* k = std::get_if<SkeletalAnimation>(&kind_)) return k->times.back();
    return 0.0;
}

std::vector<double> MeshAnimation::key_times() const {
    if (const auto* r = std::get_if<RigidAnimation>(&kind_)) return r->times;
    if (const auto* k = std::get_if<SkeletalAnimation>(&kind_)) return k->times;
    std::vector<double> times;
    if (const auto* q = std::get_if<SequenceAnimation>(&kind_))
        for (size_t f = 0; f < q->frames->size(); ++f) times.push_back(double(f) / double(q->fps));
    return times;
}

bool MeshAnimation::loops() const {
    return std::visit(
        [](const auto& k) {
            if constexpr (requires { k.loop; })
                return k.loop;
            else
                return false;
        },
        kind_);
}

void MeshAnimation::bind(const Mesh& rest, const MeshPlacement& placement) {
    const auto* sequence = std::get_if<SequenceAnimation>(&kind_);
    rest_ = sequence ? sequence->frames->front() : rest;
    placement_ = placement_matrix(placement, rest_);
    placed_rest_ = rest_;
    apply(placement, placed_rest_);
    const Box b = placed_rest_.bounds();
    pivot_ = (b.min + b.max) * 0.5f;
    if (const auto* k = std::get_if<SkeletalAnimation>(&kind_))
        weights_ = compute_skin_weights(rest_.vertices, k->skeleton);
    bound_ = true;
}

void MeshAnimation::require_bound(const char* what) const {
    if (!bound_) throw internal_failure(std::string("MeshAnimation::") + what + " called before bind()");
}

glm::mat4 MeshAnimation::transform_at(double t) const {
    require_bound("transform_at");
    const auto* r = std::get_if<RigidAnimation>(&kind_);
    return r ? r->transform_at(t, pivot_) : glm::mat4(1.0f);
}

Mesh MeshAnimation::mesh_at(double t) const {
    require_bound("mesh_at");
    if (const auto* q = std::get_if<SequenceAnimation>(&kind_))
        return transformed((*q->frames)[q->frame_at(t)], placement_);
    if (const auto* k = std::get_if<SkeletalAnimation>(&kind_)) {
        std::vector<glm::mat4> matrices = bone_matrices(k->skeleton, k->pose_at(t));
        for (glm::mat4& m : matrices) m = placement_ * m;  // skin straight into scene coordinates
        return skin(rest_, weights_, matrices);
    }
    if (std::holds_alternative<RigidAnimation>(kind_)) return transformed(placed_rest_, transform_at(t));
    return placed_rest_;
}

MeshAnimation parse_animation(const json& v, const std::string& path, const fs::path& base_dir) {
    if (!v.is_string()) return parse_animation_object(v, path, base_dir);
    const fs::path file = base_dir / v.get<std::string>();
    const std::string fix = "name a JSON file holding the animation (relative to \"" + base_dir.string() +
                            "\") or write the animation object inline";
    if (v.get<std::string>().empty()) fail(path + " is \"\" (empty); " + fix);
    try {
        const std::string text = read_json_file(file, "animation file", "it is not a readable file; " + fix);
        return parse_animation_object(parse_strict(text, file.string()), "", file.parent_path());
    } catch (const Invalid& e) {
        fail(path + " (" + v.get<std::string>() + "): " + (e.has_origin ? "" : file.string() + ": ") + e.message);
    }
}

}  // namespace aquaform::geometry
