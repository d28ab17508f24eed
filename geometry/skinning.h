// Linear-blend skinning for control meshes: a small bone hierarchy defined in JSON, automatic skin
// weights from the distance of each rest vertex to each bone, forward kinematics and the blend.
// Everything here is in the mesh's own (file) coordinates; the placement applies afterwards.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "geometry/mesh.h"

namespace aquaform::geometry {

struct Bone {
    std::string name;
    int parent = -1;       ///< index into Skeleton::bones, always lower than this bone's index; -1: a root
    glm::vec3 head{0.0f};  ///< the joint the bone rotates about, in the mesh's file coordinates
    /// End of the bone's segment for the skin weights. Unset: the head of the bone's first child, or
    /// for a leaf a stub a quarter as long as its parent, continuing the parent's direction.
    std::optional<glm::vec3> tail;
    /// Thickness of the limb around the bone (same unit as the mesh). Weights use distance / radius,
    /// so a thick torso does not lose its side vertices to a thin arm nearby. Either every bone of a
    /// skeleton has one or none does (then plain distances count).
    std::optional<float> radius;
};

/// Bones ordered parents first (the parser reorders when the file lists a child before its parent).
struct Skeleton {
    std::vector<Bone> bones;

    /// Index of the bone called `name`, or -1.
    int find(const std::string& name) const;
    /// The segment the skin weights measure distance to (head, resolved tail).
    glm::vec3 tail_of(size_t bone) const;
};

/// Reads {"bones": [{"name": "hips", "parent": null, "head": [x, y, z], "tail": [..], "radius": r}, ...]};
/// throws json_fields::Invalid naming the key path for unknown keys, duplicate or unknown names and
/// parent cycles.
Skeleton parse_skeleton(const nlohmann::json& v, const std::string& path);
/// The same object back (parents as names, numbers rounded to 1e-4 so the file reads cleanly).
nlohmann::ordered_json skeleton_json(const Skeleton& skeleton);

/// Up to four influences per vertex, weights summing to 1 (unused slots: weight 0).
struct SkinWeights {
    std::vector<glm::uvec4> bones;
    std::vector<glm::vec4> weights;
};

/// Automatic weights. With d_b = distance from the rest vertex to bone b's segment (divided by the
/// bone's radius when the skeleton gives radii) and d_min the smallest of them, each of the four
/// nearest bones gets w_b = max(0, d_b^-4 - (kBlendRatio d_min)^-4), then the weights are normalised.
/// Inverse-distance^4 keeps each vertex on its own bone except near joints; the subtracted term
/// makes a bone's weight reach exactly 0 at kBlendRatio times the nearest distance, so vertices away
/// from joints follow one bone exactly and the weights stay continuous over the mesh.
inline constexpr double kBlendRatio = 2.0;
SkinWeights compute_skin_weights(const std::vector<glm::vec3>& rest_vertices, const Skeleton& skeleton);

/// One pose: a rotation per bone (relative to its parent, about its head, in rest-pose axes) and a
/// translation of the whole skeleton.
struct SkeletonPose {
    glm::vec3 root_offset{0.0f};
    std::vector<glm::quat> rotations;  ///< one per bone; identity = rest pose
};

/// Forward kinematics: G_b = G_parent(b) * T(head_b) * R_b * T(-head_b), roots prefixed by
/// T(root_offset). The identity pose gives identity matrices, so skinning reproduces the rest mesh.
std::vector<glm::mat4> bone_matrices(const Skeleton& skeleton, const SkeletonPose& pose);

/// Linear-blend skinning, v' = v + sum_i w_i (M_i v - v) (the same as sum_i w_i M_i v when the weights
/// sum to 1, but exact for identity matrices). Faces are copied from `rest`.
Mesh skin(const Mesh& rest, const SkinWeights& weights, const std::vector<glm::mat4>& bone_matrices);

}  // namespace aquaform::geometry
