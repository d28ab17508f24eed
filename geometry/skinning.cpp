// Skeleton parsing, automatic skin weights, forward kinematics and linear-blend skinning (see skinning.h).
#include "geometry/skinning.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "core/json_fields.h"

namespace aquaform::geometry {

using namespace json_fields;

namespace {

constexpr std::string_view kSkeletonKeys[] = {"bones"};
constexpr std::string_view kBoneKeys[] = {"name", "parent", "head", "tail", "radius"};
constexpr size_t kMaxBones = 256;
constexpr const char* kBoneExample = "{\"name\": \"hips\", \"parent\": null, \"head\": [0, 0.9, 0]}";
constexpr const char* kPointWhat = "an array of three numbers [x, y, z] in the mesh's file coordinates";

/// Names the cycle `start` sits on, e.g. "a -> b -> a", or returns "" when its parents reach a root.
std::string parent_cycle(const std::vector<Bone>& bones, size_t start) {
    std::vector<size_t> chain{start};
    for (int p = bones[start].parent; p >= 0; p = bones[static_cast<size_t>(p)].parent) {
        auto seen = std::find(chain.begin(), chain.end(), static_cast<size_t>(p));
        if (seen != chain.end()) {
            std::string text;
            for (auto it = seen; it != chain.end(); ++it) text += bones[*it].name + " -> ";
            return text + bones[*seen].name;
        }
        chain.push_back(static_cast<size_t>(p));
    }
    return "";
}

/// Stable reorder so that every parent comes before its children (siblings keep the file's order).
void sort_parents_first(std::vector<Bone>& bones) {
    std::vector<int> new_index(bones.size(), -1);
    std::vector<size_t> order;
    while (order.size() < bones.size()) {
        for (size_t i = 0; i < bones.size(); ++i) {
            const int p = bones[i].parent;
            if (new_index[i] < 0 && (p < 0 || new_index[static_cast<size_t>(p)] >= 0)) {
                new_index[i] = static_cast<int>(order.size());
                order.push_back(i);
            }
        }
    }
    std::vector<Bone> sorted;
    for (size_t i : order) {
        sorted.push_back(bones[i]);
        if (sorted.back().parent >= 0) sorted.back().parent = new_index[static_cast<size_t>(sorted.back().parent)];
    }
    bones = std::move(sorted);
}

double round4(float x) { return std::round(double(x) * 1e4) / 1e4 + 0.0; }  // + 0.0: no "-0.0" in files

nlohmann::ordered_json point_json(const glm::vec3& p) { return {round4(p.x), round4(p.y), round4(p.z)}; }

/// Distance from p to the segment a..b.
double segment_distance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double s = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + s * ab));
}

}  // namespace

int Skeleton::find(const std::string& name) const {
    for (size_t i = 0; i < bones.size(); ++i)
        if (bones[i].name == name) return static_cast<int>(i);
    return -1;
}

glm::vec3 Skeleton::tail_of(size_t bone) const {
    const Bone& b = bones[bone];
    if (b.tail) return *b.tail;
    for (const Bone& c : bones)
        if (c.parent == static_cast<int>(bone)) return c.head;
    if (b.parent < 0) return b.head;  // a lone root: a point
    return b.head + 0.25f * (b.head - bones[static_cast<size_t>(b.parent)].head);
}

Skeleton parse_skeleton(const json& v, const std::string& path) {
    if (!v.is_object())
        fail(path + " must be an object {\"bones\": [" + kBoneExample + ", ...]}, got " + written(v) + " (" +
             kind_of(v) + ")");
    check_keys(v, "in " + path, kSkeletonKeys);
    require(v, "bones", "in " + path, std::string("\"bones\": [") + kBoneExample + "]");
    const json& list = v["bones"];
    const std::string list_path = path + ".bones";
    if (!list.is_array() || list.empty() || list.size() > kMaxBones)
        fail(list_path + " must be an array of 1 to " + std::to_string(kMaxBones) + " bones such as [" + kBoneExample +
             "], got " + written(list) + " (" + kind_of(list) + ")");

    Skeleton skeleton;
    std::vector<std::string> parent_names(list.size());
    size_t with_radius = 0;
    for (size_t i = 0; i < list.size(); ++i) {
        const json& b = list[i];
        const std::string bp = list_path + "[" + std::to_string(i) + "]";
        if (!b.is_object()) fail(bp + " must be an object such as " + kBoneExample + ", got " + written(b));
        check_keys(b, "in " + bp, kBoneKeys);
        require(b, "name", "in " + bp, "\"name\": \"thigh_l\"");
        require(b, "head", "in " + bp, "\"head\": [0.1, 0.9, 0]");
        Bone bone;
        const json& name = b["name"];
        if (!name.is_string() || name.get<std::string>().empty())
            fail(bp + ".name must be a non-empty string such as \"thigh_l\", got " + written(name));
        bone.name = name.get<std::string>();
        if (int other = skeleton.find(bone.name); other >= 0)
            fail(bp + ".name \"" + bone.name + "\" is already the name of " + list_path + "[" + std::to_string(other) +
                 "]; give every bone its own name");
        if (b.contains("parent") && !b["parent"].is_null()) {
            if (!b["parent"].is_string())
                fail(bp + ".parent must be the name of another bone or null (a root), got " + written(b["parent"]));
            parent_names[i] = b["parent"].get<std::string>();
        }
        bone.head = read_vec3(b["head"], bp + ".head", kPointWhat);
        if (b.contains("tail")) bone.tail = read_vec3(b["tail"], bp + ".tail", kPointWhat);
        if (b.contains("radius")) {
            bone.radius = read_number(b["radius"], bp + ".radius",
                                      {0.0, HUGE_VAL, true, false, "a positive length (the limb's thickness)"});
            ++with_radius;
        }
        skeleton.bones.push_back(std::move(bone));
    }
    if (with_radius != 0 && with_radius != list.size()) {
        const auto missing =
            std::find_if(skeleton.bones.begin(), skeleton.bones.end(), [](const Bone& b) { return !b.radius; });
        fail(list_path + "[" + std::to_string(missing - skeleton.bones.begin()) + "] (\"" + missing->name +
             "\") has no \"radius\" but other bones have one; give every bone a radius or none");
    }

    for (size_t i = 0; i < list.size(); ++i) {
        if (parent_names[i].empty()) continue;
        const int p = skeleton.find(parent_names[i]);
        if (p < 0) {
            std::string names;
            for (const Bone& b : skeleton.bones) names += (names.empty() ? "" : ", ") + b.name;
            fail(list_path + "[" + std::to_string(i) + "].parent is \"" + parent_names[i] +
                 "\", which is not the name of a bone; use one of " + names + ", or null for a root");
        }
        skeleton.bones[i].parent = p;
    }
    for (size_t i = 0; i < list.size(); ++i)
        if (std::string cycle = parent_cycle(skeleton.bones, i); !cycle.empty())
            fail(list_path + "[" + std::to_string(i) + "].parent closes a cycle of parents: " + cycle +
                 "; every chain of parents must end at a root (\"parent\": null)");
    sort_parents_first(skeleton.bones);
    return skeleton;
}

nlohmann::ordered_json skeleton_json(const Skeleton& skeleton) {
    nlohmann::ordered_json bones = nlohmann::ordered_json::array();
    for (const Bone& b : skeleton.bones) {
        nlohmann::ordered_json j;
        j["name"] = b.name;
        j["parent"] = b.parent < 0 ? nlohmann::ordered_json(nullptr)
                                   : nlohmann::ordered_json(skeleton.bones[static_cast<size_t>(b.parent)].name);
        j["head"] = point_json(b.head);
        if (b.tail) j["tail"] = point_json(*b.tail);
        if (b.radius) j["radius"] = round4(*b.radius);
        bones.push_back(std::move(j));
    }
    return {{"bones", bones}};
}

SkinWeights compute_skin_weights(const std::vector<glm::vec3>& rest_vertices, const Skeleton& skeleton) {
    struct Segment {
        glm::dvec3 a, b;
        double inv_radius;
    };
    std::vector<Segment> segments;
    for (size_t i = 0; i < skeleton.bones.size(); ++i) {
        const Bone& bone = skeleton.bones[i];
        segments.push_back({bone.head, skeleton.tail_of(i), bone.radius ? 1.0 / double(*bone.radius) : 1.0});
    }
    // A vertex on a segment (d = 0) must not divide by zero; far below any real distance.
    constexpr double kFloor = 1e-9;
    constexpr size_t kSlots = 4;
    const size_t used = std::min(kSlots, segments.size());

    SkinWeights out;
    out.bones.resize(rest_vertices.size(), glm::uvec4(0));
    out.weights.resize(rest_vertices.size(), glm::vec4(0.0f));
    for (size_t v = 0; v < rest_vertices.size(); ++v) {
        std::array<std::pair<double, uint32_t>, kSlots> nearest;
        nearest.fill({std::numeric_limits<double>::infinity(), 0u});
        for (size_t b = 0; b < segments.size(); ++b) {
            const double d = std::max(
                kFloor, segment_distance(rest_vertices[v], segments[b].a, segments[b].b) * segments[b].inv_radius);
            if (d >= nearest.back().first) continue;
            nearest.back() = {d, static_cast<uint32_t>(b)};
            std::sort(nearest.begin(), nearest.end());
        }
        const double cut = std::pow(kBlendRatio * nearest[0].first, -4.0);
        std::array<double, kSlots> w{};
        double sum = 0.0;
        for (size_t k = 0; k < used; ++k) sum += w[k] = std::max(0.0, std::pow(nearest[k].first, -4.0) - cut);
        for (size_t k = 0; k < used; ++k) {
            out.bones[v][k] = nearest[k].second;
            out.weights[v][k] = static_cast<float>(w[k] / sum);
        }
    }
    return out;
}

std::vector<glm::mat4> bone_matrices(const Skeleton& skeleton, const SkeletonPose& pose) {
    if (pose.rotations.size() != skeleton.bones.size())
        throw Failure("bone_matrices: the pose has " + std::to_string(pose.rotations.size()) + " rotations for " +
                      std::to_string(skeleton.bones.size()) + " bones");
    std::vector<glm::mat4> out(skeleton.bones.size());
    for (size_t i = 0; i < skeleton.bones.size(); ++i) {
        const Bone& b = skeleton.bones[i];
        const glm::mat4 local = glm::translate(glm::mat4(1.0f), b.head) * glm::mat4_cast(pose.rotations[i]) *
                                glm::translate(glm::mat4(1.0f), -b.head);
        const glm::mat4 above =
            b.parent < 0 ? glm::translate(glm::mat4(1.0f), pose.root_offset) : out[static_cast<size_t>(b.parent)];
        out[i] = above * local;
    }
    return out;
}

Mesh skin(const Mesh& rest, const SkinWeights& weights, const std::vector<glm::mat4>& matrices) {
    if (weights.bones.size() != rest.vertices.size())
        throw Failure("skin: weights for " + std::to_string(weights.bones.size()) + " vertices, mesh has " +
                      std::to_string(rest.vertices.size()));
    Mesh out;
    out.faces = rest.faces;
    out.vertices.resize(rest.vertices.size());
    for (size_t i = 0; i < rest.vertices.size(); ++i) {
        const glm::vec3 v = rest.vertices[i];
        const glm::vec4 v4(v, 1.0f);
        glm::vec3 moved(0.0f);
        for (int k = 0; k < 4; ++k) {
            const float w = weights.weights[i][k];
            if (w != 0.0f) moved += w * (glm::vec3(matrices[weights.bones[i][k]] * v4) - v);
        }
        out.vertices[i] = v + moved;
    }
    return out;
}

}  // namespace aquaform::geometry
