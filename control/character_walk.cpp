#include "control/character_walk.h"

#include <nlohmann/json.hpp>

namespace aquaform::control {

namespace {

using ordered_json = nlohmann::ordered_json;

/// One walk-cycle key: degrees about x (negative swings a limb forward, +z) and the hips' bob.
ordered_json walk_key(double t, int thigh_l, int thigh_r, int shin_l, int shin_r, int arm_l, int arm_r, double bob) {
    ordered_json rotations;
    rotations["thigh_l"] = {thigh_l, 0, 0};
    rotations["thigh_r"] = {thigh_r, 0, 0};
    rotations["shin_l"] = {shin_l, 0, 0};  // knees only bend backward (positive)
    rotations["shin_r"] = {shin_r, 0, 0};
    rotations["upper_arm_l"] = {arm_l, 0, 0};
    rotations["upper_arm_r"] = {arm_r, 0, 0};
    rotations["forearm_l"] = {-15, 0, 0};  // elbows slightly bent forward throughout
    rotations["forearm_r"] = {-15, 0, 0};
    ordered_json key;
    key["t"] = t;
    key["root_offset"] = {0, bob, 0};
    key["rotations_degrees"] = rotations;
    return key;
}

/// The character's skeleton and a 1 s walk in place: thighs swing +-25 degrees, the swinging leg's
/// knee bends most as it passes, arms swing against the legs, the hips dip at each heel strike.
ordered_json character_animation(const geometry::Skeleton& skeleton) {
    ordered_json j;
    j["skeleton"] = geometry::skeleton_json(skeleton);
    j["keyframes"] = {
        walk_key(0.0, -25, 25, 5, 20, 20, -20, -0.02),  // left heel strikes in front
        walk_key(0.25, 0, 0, 5, 45, 0, 0, 0.0),         // right leg passes
        walk_key(0.5, 25, -25, 20, 5, -20, 20, -0.02),  // right heel strikes in front
        walk_key(0.75, 0, 0, 45, 5, 0, 0, 0.0),         // left leg passes
        walk_key(1.0, -25, 25, 5, 20, 20, -20, -0.02),  // = t 0, so the loop is seamless
    };
    j["loop"] = true;
    return j;
}

/// Each element of `array` on its own line, compact: short to read and diff, easy to copy into a scene.
std::string one_per_line(const ordered_json& array, const std::string& indent) {
    std::string s = "[\n";
    for (size_t i = 0; i < array.size(); ++i)
        s += indent + "  " + array[i].dump() + (i + 1 < array.size() ? ",\n" : "\n");
    return s + indent + "]";
}

std::string animation_text(const ordered_json& j) {
    return "{\n  \"skeleton\": {\"bones\": " + one_per_line(j["skeleton"]["bones"], "  ") +
           "},\n  \"keyframes\": " + one_per_line(j["keyframes"], "  ") + ",\n  \"loop\": " + j["loop"].dump() +
           "\n}\n";
}

}  // namespace

std::string character_walk_text(const geometry::Skeleton& skeleton) {
    return animation_text(character_animation(skeleton));
}

}  // namespace aquaform::control
