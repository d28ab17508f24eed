// The frames `aquaform bench render` draws: each chosen to exercise one part of the adaptive
// ray marcher of Wu et al. (a calm frame for the baseline, a constructed curtain of droplets for
// the mask and the skip, the splashy frames of the paper scenes, and constructed one-particle-thick
// sheets for the anisotropic surface), so that the benchmark measures the method where it is meant
// to matter and where it is not.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bench/surface_checks.h"
#include "core/result.h"
#include "sim/pbf_solver.h"
#include "sim/scene.h"

namespace aquaform::study {

/// What a frame's pictures are checked for besides the configurations' targets (study/
/// surface_checks.h): the droplets of a scene of lone droplets, or a sheet's coverage.
enum class FrameCheck { none, droplets, sheet };

struct BenchFrame {
    const char* name;
    /// A scene file under the scene directory, or nullptr for bench_scene()'s dam break (or the
    /// sheet of a sheet frame).
    const char* scene_file;
    /// Simulated time [s]; negative: the bench dam break's half-tank frame (bench_half_tank_frame).
    double time_s;
    const char* what;
    FrameCheck check = FrameCheck::none;
    float sheet_pitch = 0.0f;  ///< a sheet frame's lattice pitch [particle spacings]
};

/// Every frame, in the table's order.
const std::vector<BenchFrame>& bench_frames();
/// What --frames is when not given: every frame, or with --quick the calm and curtain frames.
std::string default_frame_list(bool quick);
/// "calm, curtain, ...": what --frames accepts.
std::string known_frame_names();
/// --frames a,b,c in the table's order.
Result<std::vector<const BenchFrame*>> parse_bench_frames(const std::string& text);

/// `scene` with about `particles` particles, its sizes in metres kept (with_particle_count); a
/// scene of one bulk block and lone droplets (blocks that hold one particle, like the curtain)
/// keeps each droplet a single particle at its centre: scaled like the bulk it would vanish at a
/// coarser spacing, or become a clump at a finer one.
Result<Scene> scaled_scene(const Scene& scene, uint64_t particles);

/// The frame's scene with about `particles` particles (a scene file is scaled to it; nullopt:
/// the file's own count; the calm dam break is made at `particles` or 32,768). `scene_dir`
/// holds the scene files (assets/scenes/ of the source tree by default).
Result<Scene> bench_frame_scene(const BenchFrame& frame, std::optional<uint64_t> particles,
                                const std::filesystem::path& scene_dir);
/// Every frame's scene (bench_frame_scene), all loaded before any work so that a bad one is
/// reported at once; the first error.
Result<std::vector<Scene>> bench_frame_scenes(const std::vector<const BenchFrame*>& frames, uint64_t particles,
                                              const std::filesystem::path& scene_dir);
/// Where the shipped scene files are: assets/scenes under the working directory, else beside
/// the binary's source tree (the binary in build/: ../assets/scenes); the first that exists.
std::filesystem::path default_scene_dir();

/// A sheet frame's sheet (the scene holds it as drawn at frame 0): about 0.46 m square at a
/// spacing of 0.02 m, jittered by 0.1 spacing, the same every run.
Sheet bench_sheet(const BenchFrame& frame);

/// The centres of the lone droplets, in the order of their blocks (the particles of a scene's
/// one-particle blocks, found by the block each came from, so they are followed wherever the
/// solver moved and sorted them); empty for a scene that holds none.
std::vector<glm::vec3> lone_droplet_centres(const Scene& scene, const ParticleSnapshot& particles);

/// The solver frame to draw: the frame's time in the scene's frames.
uint32_t bench_frame_index(const BenchFrame& frame, const Scene& scene);

}  // namespace aquaform::study
