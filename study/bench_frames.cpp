#include "study/bench_frames.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/data_dir.h"
#include "study/bench_scenes.h"

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
     "constructed: 60 lone droplets 0.2 m in front of a slab; rays cross empty space between them and the bulk"},
    {"double_collision", "double_dam_break.json", 0.55, "Wu et al. Fig. 1: the two columns' fronts collide mid-tank"},
    {"violent_wall", "violent_dam_break.json", 0.80, "Wu et al. Fig. 9: the wave runs up the far wall and throws spray"},
    {"crown", "crown_splash.json", 0.25, "Wu et al. Fig. 10d: the crown of a ball thrown into a pool"},
};

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

const std::vector<std::string>& quick_bench_frames() {
    static const std::vector<std::string> quick{"calm", "curtain"};
    return quick;
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
        const bool known = std::any_of(std::begin(kFrames), std::end(kFrames), [&](const BenchFrame& f) { return item == f.name; });
        if (!known) return Error{"--frames: unknown frame \"" + item + "\"; choose from " + known_frame_names()};
        wanted.push_back(item);
    }
    if (wanted.empty()) return Error{"--frames is empty; choose from " + known_frame_names()};
    std::vector<const BenchFrame*> frames;
    for (const BenchFrame& f : kFrames)
        if (std::find(wanted.begin(), wanted.end(), f.name) != wanted.end()) frames.push_back(&f);
    return frames;
}

Result<Scene> bench_frame_scene(const BenchFrame& frame, std::optional<uint64_t> particles,
                                const std::filesystem::path& scene_dir) {
    if (!frame.scene_file) {
        Scene s = bench_scene(uint32_t(particles.value_or(32768)), 4);
        if (s.particle_count() == 0)
            return Error{"--particles " + std::to_string(*particles) + " makes an empty dam break; ask for more"};
        return s;
    }
    const std::filesystem::path path = scene_dir / frame.scene_file;
    auto scene = load_scene(path);
    if (!scene)
        return Error{scene.error() + " (frame '" + frame.name + "' needs it; give the directory of the shipped scenes with --scene-dir)"};
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

uint32_t bench_frame_index(const BenchFrame& frame, const Scene& scene) {
    if (frame.time_s < 0.0) return bench_half_tank_frame(scene);
    return uint32_t(std::lround(frame.time_s / double(scene.solver.frame_dt)));
}

}  // namespace aquaform::study
