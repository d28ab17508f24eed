// Mesh placement and mesh animation for control meshes, read from a scene's "control" section:
// rigid keyframes (the placed mesh moves as a whole), an OBJ sequence (one file per frame) and
// linear-blend skinning with a small skeleton (geometry/skinning.h). The scene code parses an entry
// with parse_placement / parse_animation, binds the animation to its mesh once, then asks for the
// geometry (or, for rigid motion, only a matrix) at each frame's time.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "geometry/mesh.h"
#include "geometry/skinning.h"

namespace aquaform::geometry {

/// Euler angles in degrees applied X, then Y, then Z (R = Rz Ry Rx), the convention of apply().
glm::quat rotation_xyz_degrees(const glm::vec3& degrees);

/// Reads {"position": [x, y, z], "rotation_degrees": [x, y, z], "scale": s, "fit_into": {"min": [..],
/// "max": [..]}}, every key optional; fit_into excludes position and scale (apply() would ignore them).
/// Throws json_fields::Invalid naming the key path.
MeshPlacement parse_placement(const nlohmann::json& v, const std::string& path);

/// apply(placement, rest) as a matrix (v -> s R v + offset); fit_into is resolved against `rest`.
glm::mat4 placement_matrix(const MeshPlacement& placement, const Mesh& rest);

/// Where t falls among strictly increasing key times: between keys i0 and i1 = i0 + 1 at `alpha`.
/// Clamped to the first / last key outside their range; with `loop`, t first wraps into
/// [first, last) with period last - first (so the last key should repeat the first).
struct KeySpan {
    size_t i0 = 0;
    size_t i1 = 0;
    float alpha = 0.0f;
};
KeySpan locate_key(const std::vector<double>& times, double t, bool loop);

/// (a) Rigid motion of the placed mesh. At time t, with position p, rotation R (slerp) and scale s
/// interpolated between keys: x -> pivot + p + R s (x - pivot), the pivot being the centre of the
/// placed rest mesh's bounding box. So `position` is an offset from where the placement put the mesh,
/// and rotation and scale turn and grow it in place. Slerp takes the shorter way between keys, so keys
/// of a spin must be less than 180 degrees apart (e.g. every 90 degrees).
struct RigidKey {
    glm::vec3 position{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
    float scale = 1.0f;
};
struct RigidAnimation {
    std::vector<double> times;  ///< seconds, strictly increasing, one per key
    std::vector<RigidKey> keys;
    bool loop = false;

    glm::mat4 transform_at(double t, const glm::vec3& pivot) const;
};

/// (b) One OBJ file per frame, all loaded (and checked) when the animation is parsed.
struct SequenceAnimation {
    std::vector<std::filesystem::path> files;
    std::shared_ptr<const std::vector<Mesh>> frames;  ///< shared: copies of the animation stay cheap
    float fps = 24.0f;
    bool loop = false;

    /// Frame floor(t * fps) (plus 1e-6 so that t = k / fps is frame k despite rounding), clamped to
    /// the sequence or wrapped when `loop`.
    size_t frame_at(double t) const;
};

/// (c) Linear-blend skinning: poses interpolated between keys (root offset linearly, each bone's
/// rotation by slerp), in the mesh's file coordinates; the placement applies after skinning.
struct SkeletalAnimation {
    Skeleton skeleton;
    std::vector<double> times;
    std::vector<SkeletonPose> keys;
    bool loop = false;

    SkeletonPose pose_at(double t) const;
};

/// The animation of one control mesh; default-constructed it is none (the mesh stays where it is placed).
class MeshAnimation {
public:
    using Kind = std::variant<std::monostate, RigidAnimation, SequenceAnimation, SkeletalAnimation>;

    MeshAnimation() = default;
    explicit MeshAnimation(Kind kind) : kind_(std::move(kind)) {}

    /// Any animation.
    bool moves() const { return !std::holds_alternative<std::monostate>(kind_); }
    /// Sequence or skeleton: the shape changes, so control points must be placed again each frame.
    /// Otherwise they can be placed once and moved by transform_at().
    bool deforms() const {
        return std::holds_alternative<SequenceAnimation>(kind_) || std::holds_alternative<SkeletalAnimation>(kind_);
    }
    /// Time after which the motion repeats (loop) or holds still: the last key's time, or count / fps.
    double duration() const;
    /// Whether the motion repeats after duration() (else it holds its last pose).
    bool loops() const;
    /// The times of its keys (a sequence: each frame's start), where its speed may change at once.
    std::vector<double> key_times() const;
    const Kind& kind() const { return kind_; }

    /// Once per mesh, before transform_at / mesh_at: `rest` as loaded from its file (file coordinates)
    /// and its placement in the scene. Computes the skin weights, the rigid pivot and the placement
    /// matrix; fit_into is resolved once against the rest mesh (for a sequence: its first frame, and
    /// `rest` is not used), so a deforming mesh keeps one scale instead of being refitted each frame.
    void bind(const Mesh& rest, const MeshPlacement& placement);
    bool bound() const { return bound_; }

    /// The rigid motion at t in scene coordinates (identity for no animation, sequences and skeletons).
    glm::mat4 transform_at(double t) const;
    /// The whole mesh at t in scene coordinates. O(vertices); for skinning about 4 matrix-vector
    /// products per vertex.
    Mesh mesh_at(double t) const;

    const Mesh& placed_rest() const { return placed_rest_; }
    const SkinWeights& skin_weights() const { return weights_; }  ///< empty unless a skeleton

private:
    void require_bound(const char* what) const;

    Kind kind_;
    bool bound_ = false;
    Mesh rest_;         ///< file coordinates (skinning input)
    Mesh placed_rest_;  ///< scene coordinates
    glm::mat4 placement_{1.0f};
    glm::vec3 pivot_{0.0f};
    SkinWeights weights_;
};

/// Reads one of
///   {"keyframes": [{"t": 0, "position": [..], "rotation_degrees": [..], "scale": 1}, ...], "loop": false}
///   {"sequence": "walk_%03d.obj", "first": 0, "count": 24, "fps": 24, "loop": true}
///   {"skeleton": {"bones": [..]}, "keyframes": [{"t": 0, "root_offset": [..],
///                 "rotations_degrees": {"thigh_l": [x, y, z], ...}}, ...], "loop": true}
/// or a string: the name of a JSON file holding one of them (e.g. a character's skeleton and walk
/// cycle). Files are relative to `base_dir` (a referenced file's own folder for what it names).
/// Throws json_fields::Invalid naming the key path, the value and the fix.
MeshAnimation parse_animation(const nlohmann::json& v, const std::string& path, const std::filesystem::path& base_dir);

}  // namespace aquaform::geometry
