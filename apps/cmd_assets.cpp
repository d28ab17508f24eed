// `aquaform assets [--out DIR]`: write the meshes the project ships (assets/meshes/) from the
// generators in geometry/primitives.h, so that the committed files can always be regenerated and
// checked against their source (tests/test_assets.cpp compares them byte for byte).
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "control/character_walk.h"
#include "core/file_write.h"
#include "core/output_dir.h"
#include "geometry/mesh.h"
#include "geometry/primitives.h"

namespace aquaform::cli {

namespace {

namespace fs = std::filesystem;

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
        return refuse("assets", "unexpected argument \"" + args->positional[0] + "\"; use aquaform assets [--out DIR]");
    const fs::path out_dir = args->value("--out", "assets/meshes");
    // No folder lock here: the generator writes the same bytes every time (two at once write the
    // same files), and its folder is the repository's assets/meshes, which holds these alone.
    if (auto ready = prepare_output_dir(out_dir); !ready) return refuse("assets", ready.error());

    struct Named {
        std::string file;
        geometry::Mesh mesh;
    };
    std::vector<Named> meshes = {{"sphere.obj", geometry::make_sphere(0.5f, 3)},
                                 {"torus.obj", geometry::make_torus(0.35f, 0.15f)},
                                 {"glass.obj", geometry::make_glass(0.09f, 0.02f, 0.18f, 0.02f)}};
    for (char c : geometry::kBlockLetters)
        meshes.push_back({std::string("letter_") + c + ".obj", geometry::make_block_letter(c)});
    const geometry::Character character = geometry::make_character();
    meshes.push_back({"character.obj", character.mesh});

    for (const Named& m : meshes) {
        const fs::path path = out_dir / m.file;
        if (Result<bool> written = geometry::write_obj(path, m.mesh); !written)
            return refuse("assets", written.error(), kExitFailure);
        report(path, std::to_string(m.mesh.vertices.size()) + " vertices, " + std::to_string(m.mesh.faces.size()) +
                         " triangles");
    }
    const fs::path skeleton_path = out_dir / "character_skeleton.json";
    const std::string skeleton = control::character_walk_text(character.skeleton);
    if (auto written = write_file_with(skeleton_path, [&](std::ostream& out) { out << skeleton; }); !written)
        return refuse("assets", written.error(), kExitFailure);
    report(skeleton_path, std::to_string(character.skeleton.bones.size()) + " bones, walk cycle of 1 s");
    return kExitOk;
}

}  // namespace aquaform::cli
