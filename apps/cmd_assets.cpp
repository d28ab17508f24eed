// `aquaform assets [--out DIR]`: write the meshes the project ships (assets/meshes/) from the
// generators in control/primitives.h, so that the committed files can always be regenerated and
// checked against their source (tests/test_assets.cpp compares them byte for byte).
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/cli.h"
#include "control/mesh.h"
#include "control/primitives.h"
#include "core/file_write.h"
#include "core/output_dir.h"

namespace aquaform::cli {

namespace {

namespace fs = std::filesystem;
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
ordered_json character_animation(const control::Skeleton& skeleton) {
    ordered_json j;
    j["skeleton"] = control::skeleton_json(skeleton);
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
    for (size_t i = 0; i < array.size(); ++i) s += indent + "  " + array[i].dump() + (i + 1 < array.size() ? ",\n" : "\n");
    return s + indent + "]";
}

std::string animation_text(const ordered_json& j) {
    return "{\n  \"skeleton\": {\"bones\": " + one_per_line(j["skeleton"]["bones"], "  ") + "},\n  \"keyframes\": " +
           one_per_line(j["keyframes"], "  ") + ",\n  \"loop\": " + j["loop"].dump() + "\n}\n";
}

void report(const fs::path& path, const std::string& what) {
    std::error_code ec;
    const auto bytes = fs::file_size(path, ec);
    std::printf("wrote %s (%s, %.1f KB)\n", path.string().c_str(), what.c_str(), ec ? 0.0 : double(bytes) / 1024.0);
}

}  // namespace

int cmd_assets(const std::vector<std::string>& argv) {
    std::string error;
    auto args = parse_args(argv, {{"--out"}, {}}, "assets", &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    if (!args->positional.empty())
        return std::fprintf(stderr, "aquaform assets: unexpected argument \"%s\"; use aquaform assets [--out DIR]\n",
                            args->positional[0].c_str()),
               kExitUsage;
    const fs::path out_dir = args->value("--out", "assets/meshes");
    // No folder lock here: the generator writes the same bytes every time (two at once write the
    // same files), and its folder is the repository's assets/meshes, which holds these alone.
    if (auto ready = prepare_output_dir(out_dir); !ready)
        return std::fprintf(stderr, "aquaform assets: %s\n", ready.error().c_str()), kExitUsage;

    struct Named {
        std::string file;
        control::Mesh mesh;
    };
    std::vector<Named> meshes = {{"sphere.obj", control::make_sphere(0.5f, 3)},
                                 {"torus.obj", control::make_torus(0.35f, 0.15f)}};
    for (char c : control::kBlockLetters)
        meshes.push_back({std::string("letter_") + c + ".obj", control::make_block_letter(c)});
    const control::Character character = control::make_character();
    meshes.push_back({"character.obj", character.mesh});

    for (const Named& m : meshes) {
        const fs::path path = out_dir / m.file;
        if (Result<bool> written = control::write_obj(path, m.mesh); !written)
            return std::fprintf(stderr, "aquaform assets: %s\n", written.error().c_str()), kExitFailure;
        report(path, std::to_string(m.mesh.vertices.size()) + " vertices, " + std::to_string(m.mesh.faces.size()) +
                         " triangles");
    }
    const fs::path skeleton_path = out_dir / "character_skeleton.json";
    const std::string skeleton = animation_text(character_animation(character.skeleton));
    if (auto written = write_file_with(skeleton_path, [&](std::ostream& out) { out << skeleton; }); !written)
        return std::fprintf(stderr, "aquaform assets: %s\n", written.error().c_str()), kExitFailure;
    report(skeleton_path, std::to_string(character.skeleton.bones.size()) + " bones, walk cycle of 1 s");
    return kExitOk;
}

}  // namespace aquaform::cli
