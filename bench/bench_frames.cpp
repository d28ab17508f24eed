#include "bench/bench_frames.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "bench/bench_scenes.h"
#include "core/data_dir.h"

namespace aquaform::study {

namespace {

// Times of the events in the shipped scenes (the geometry is in metres, so a scaled scene's fluid
// moves alike), read off `aquaform run ... --preview` at the shipped sizes: the double dam break's
// collision throws its splash up at 0.55 s (splash fraction 12 %, 236 droplets); the violent
// dam break's wave is high on the far wall at 0.8 s (8 %, 89 droplets); the crown splash's
// splash fraction peaks at 0.25 s (5 %).
const BenchFrame kFrames[] = {
    {"calm", nullptr, -1.0,
     "dam break, front at mid-tank: one body of fluid, no splash (the frame bench render drew before)"},
    {"curtain", "droplet_curtain.json", 0.0,
     "constructed: 60 lone droplets 0.2 m in front of a slab; rays cross empty space between them and the bulk",
     FrameCheck::droplets},
    {"double_collision", "double_dam_break.json", 0.55, "Wu et al. Fig. 1: the two columns' fronts collide mid-tank"},
    {"violent_wall", "violent_dam_break.json", 0.80,
     "Wu et al. Fig. 9: the wave runs up the far wall and throws spray"},
    {"crown", "crown_splash.json", 0.25, "Wu et al. Fig. 10d: the crown of a ball thrown into a pool"},
    {"sheet", nullptr, 0.0,
     "constructed: a sheet one particle thick (24 x 24 at the particle spacing, jittered by 0.1), face on; "
     "--particles does not apply",
     FrameCheck::sheet, 1.0f},
    {"sheet_sparse", nullptr, 0.0,
     "constructed: the sheet at 1.5 spacings (16 x 16): too few neighbours for the anisotropic kernel to flatten; "
     "--particles does not apply",
     FrameCheck::sheet, 1.5f},
};

constexpr float kSheetSpacing = 0.02f;
constexpr float kSheetSide = 23.0f;  // lattice pitches of the dense sheet's side [spacings]

/// A sheet frame's scene: each of the sheet's particles a block of its own, holding one lattice
/// point at its centre (as the curtain's droplets are made), so the solver starts from the
/// jittered sheet; seen face on from 1 m.
Result<Scene> sheet_scene(const BenchFrame& frame) {
    const Sheet sheet = bench_sheet(frame);
    Scene s;
    s.name = std::string("one-particle-thick sheet (") + frame.name + ")";
    s.particle_spacing = kSheetSpacing;
    const glm::vec3 margin(0.1f);
    s.domain = {sheet.corner - margin, sheet.corner + glm::vec3(sheet.side, sheet.side, 0.0f) + margin};
    for (const glm::vec4& p : sheet.particles)
        s.fluid_blocks.push_back({glm::vec3(p) - 0.5f * kSheetSpacing, glm::vec3(p) + 0.5f * kSheetSpacing});
    s.frames = 1;
    s.event_frame = 0;
    ViewCamera camera;
    camera.target = sheet.centre();
    camera.eye = camera.target + glm::vec3(0.0f, 0.0f, 1.0f);
    camera.fov_y_degrees =
        2.0f * glm::degrees(std::atan(0.5f * sheet.side + 2.0f * kSheetSpacing));  // a margin of 2 spacings
    s.camera = camera;
    if (s.particle_count() != sheet.particles.size())
        return Error{std::string("frame ") + frame.name + ": the sheet's blocks hold " +
                     std::to_string(s.particle_count()) + " particles, not one each (" +
                     std::to_string(sheet.particles.size()) + ")"};
    return s;
}

/// scaled_scene for a scene of one bulk block and lone droplets.
Result<Scene> with_lone_droplets_scaled(const Scene& scene, uint64_t particles) {
    Scene bulk = scene;
    bulk.fluid_blocks.resize(1);
    bulk.block_fills.resize(std::min<size_t>(bulk.block_fills.size(), 1));
    const uint64_t droplets = scene.fluid_blocks.size() - 1;
    auto scaled = with_particle_count(bulk, particles > droplets + 64 ? particles - droplets : 64);
    if (!scaled) return scaled;
    Scene out = scaled.value();
    const float s = out.particle_spacing;
    for (size_t i = 1; i < scene.fluid_blocks.size(); ++i) {
        const glm::vec3 c = 0.5f * (scene.fluid_blocks[i].min + scene.fluid_blocks[i].max);
        out.fluid_blocks.push_back({c - 0.5f * s, c + 0.5f * s});
    }
    return out;
}

bool holds_lone_droplets(const Scene& scene) {
    if (scene.fluid_blocks.size() < 2) return false;
    for (size_t i = 1; i < scene.fluid_blocks.size(); ++i) {
        Scene one = scene;
        one.fluid_blocks = {scene.fluid_blocks[i]};
        one.block_fills = {scene.fill_of(i)};
        if (one.particle_count() != 1) return false;
    }
    return true;
}

}  // namespace

const std::vector<BenchFrame>& bench_frames() {
    static const std::vector<BenchFrame> frames(std::begin(kFrames), std::end(kFrames));
    return frames;
}

std::string default_frame_list(bool quick) {
    if (quick) return "calm,curtain";
    std::string list;
    for (const BenchFrame& f : kFrames) list += std::string(list.empty() ? "" : ",") + f.name;
    return list;
}

std::string known_frame_names() {
    std::string s;
    for (const BenchFrame& f : kFrames) s += std::string(s.empty() ? "" : ", ") + f.name;
    return s;
}

Result<std::vector<const BenchFrame*>> parse_bench_frames(const std::string& text) {
    std::vector<std::string> wanted;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        const bool known =
            std::any_of(std::begin(kFrames), std::end(kFrames), [&](const BenchFrame& f) { return item == f.name; });
        if (!known) return Error{"--frames: unknown frame \"" + item + "\"; choose from " + known_frame_names()};
        wanted.push_back(item);
    }
    if (wanted.empty()) return Error{"--frames is empty; choose from " + known_frame_names()};
    std::vector<const BenchFrame*> frames;
    for (const BenchFrame& f : kFrames)
        if (std::find(wanted.begin(), wanted.end(), f.name) != wanted.end()) frames.push_back(&f);
    return frames;
}

Result<std::vector<Scene>> bench_frame_scenes(const std::vector<const BenchFrame*>& frames, uint64_t particles,
                                              const std::filesystem::path& scene_dir) {
    std::vector<Scene> scenes;
    for (const BenchFrame* f : frames) {
        auto scene = bench_frame_scene(*f, particles, scene_dir);
        if (!scene) return Error{scene.error()};
        scenes.push_back(std::move(scene.value()));
    }
    return scenes;
}

Result<Scene> bench_frame_scene(const BenchFrame& frame, std::optional<uint64_t> particles,
                                const std::filesystem::path& scene_dir) {
    if (frame.check == FrameCheck::sheet) return sheet_scene(frame);
    if (!frame.scene_file) {
        Scene s = bench_scene(uint32_t(particles.value_or(32768)), 4);
        if (s.particle_count() == 0)
            return Error{"--particles " + std::to_string(*particles) + " makes an empty dam break; ask for more"};
        return s;
    }
    const std::filesystem::path path = scene_dir / frame.scene_file;
    auto scene = load_scene(path);
    if (!scene)
        return Error{scene.error() + " (frame '" + frame.name +
                     "' needs it; give the directory of the shipped scenes with --scene-dir)"};
    if (!particles) return scene;
    return scaled_scene(scene.value(), *particles);
}

Result<Scene> scaled_scene(const Scene& scene, uint64_t particles) {
    if (holds_lone_droplets(scene)) return with_lone_droplets_scaled(scene, particles);
    return with_particle_count(scene, particles);
}

std::filesystem::path default_scene_dir() {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::is_directory("assets/scenes", ec)) return "assets/scenes";  // the working directory's own first
    const std::optional<fs::path> assets = find_data_dir("assets");
    return assets ? *assets / "scenes" : fs::path("assets/scenes");
}

Sheet bench_sheet(const BenchFrame& frame) {
    const int n = 1 + int(std::lround(kSheetSide / frame.sheet_pitch));
    return one_particle_thick_sheet({0.1f, 0.1f, 0.2f}, kSheetSpacing, n, frame.sheet_pitch, 0.1f, 7);
}

std::vector<glm::vec3> lone_droplet_centres(const Scene& scene, const ParticleSnapshot& particles) {
    if (!holds_lone_droplets(scene)) return {};
    // In the blocks' order (v.w: the block a particle came from), whatever order the sort left.
    std::vector<glm::vec3> centres(scene.fluid_blocks.size() - 1);
    for (size_t i = 0; i < particles.x.size(); ++i)
        if (const size_t block = size_t(particles.v[i].w); block >= 1) centres[block - 1] = glm::vec3(particles.x[i]);
    return centres;
}

uint32_t bench_frame_index(const BenchFrame& frame, const Scene& scene) {
    if (frame.time_s < 0.0) return bench_half_tank_frame(scene);
    return uint32_t(std::lround(frame.time_s / double(scene.solver.frame_dt)));
}

}  // namespace aquaform::study
