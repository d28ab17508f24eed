// Scene description: what a scene file (JSON, SI units) asks the solver to simulate.
// Loading validates strictly; every error names the file, the key, the value and the fix.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/box.h"
#include "core/camera.h"
#include "core/result.h"
#include "sim/block_fill.h"
#include "sim/flow_spec.h"
#include "sim/probe_spec.h"
#include "sim/scene_basics.h"
#include "sim/whitewater_spec.h"

namespace aquaform {

/// Largest particle count a scene file (or --particles) may ask for; parse_scene rejects more, so
/// that a typo in particle_spacing fails with a message instead of exhausting memory. It is the
/// solver's limit: particle indices are 24-bit in its sort keys and control tags.
inline constexpr uint64_t kMaxSceneParticles = (uint64_t{1} << 24) - 1;  // 16,777,215
/// Most fluid blocks a scene may list (they are checked against each other pairwise).
inline constexpr size_t kMaxFluidBlocks = 1024;
/// Largest gravity a scene may ask for, in m/s^2 (about 100 g).
inline constexpr float kMaxGravity = 1000.0f;

/// The bounds of a scene's keys: the loader's checks and messages use these, docs/scenes.md
/// quotes them (tests/test_scene_bounds.cpp holds all three to the same numbers).
/// solver.frame_dt [s]: above 1e-5 s a frame is still a picture's worth of motion; the start is
/// relaxed to rest density (PbfSolver), so a small step is never worse than a large one.
inline constexpr double kMinFrameDt = 1.0e-5;
inline constexpr double kMaxFrameDt = 0.1;
inline constexpr uint32_t kMaxSubsteps = 64;      ///< solver.substeps, from 1
inline constexpr uint32_t kMaxMaxSubsteps = 256;  ///< solver.max_substeps, from 1
inline constexpr uint32_t kMaxIterations = 100;   ///< solver.iterations, from 1
inline constexpr double kMinKernelRadiusFactor = 1.0;
inline constexpr double kMaxKernelRadiusFactor = 4.0;
inline constexpr double kMaxViscosity = 1.0;     ///< solver.viscosity, from 0
inline constexpr double kMaxCfl = 1.0;           ///< solver.cfl, above 0
inline constexpr double kMaxSpeedCap = 1.0e4;    ///< solver.max_speed [m/s], from 0 (off)
inline constexpr uint32_t kMaxScorrN = 15;       ///< solver.scorr_n, from 1
inline constexpr uint32_t kMaxFrames = 1000000;  ///< frames and event_frame
/// A fluid block's start speed [m/s]. The blow-up bound (sim/blowup.h) counts the fastest start
/// speed in, so every accepted start runs.
inline constexpr float kMaxStartSpeed = 100.0f;

/// A scene: its basics (the tank, the spacing, the solver, the solids: sim/scene_basics.h) and
/// the rest of its file.
struct Scene : SceneBasics {
    std::filesystem::path path;  ///< file it was loaded from (empty when built in code)
    std::string name;
    float rest_density = 1000.0f;  ///< rho0 [kg/m^3]
    glm::vec3 gravity{0.0f, -9.81f, 0.0f};
    std::vector<Box> fluid_blocks;       ///< filled with particles at t = 0 (sim/block_fill.h)
    std::vector<BlockFill> block_fills;  ///< per fluid block; a block without one is a box at rest
    /// What the scene measures every step (its "probes" key): gauges, sensors, forces.
    std::optional<ProbeSpec> probes;
    /// Nozzles that add water during the run and volumes that take it away (its "emitters" and
    /// "sinks" keys; sim/fluid_flow.h).
    std::vector<EmitterSpec> emitters;
    std::vector<SinkSpec> sinks;
    /// The particles the solver makes room for (its "capacity" key); without it, the start's
    /// particles and all the emitters make over the scene's frames (particle_capacity()).
    std::optional<uint64_t> capacity;
    /// Spray, foam and bubbles made from the flow (its "whitewater" key; sim/whitewater.h).
    std::optional<WhitewaterSettings> whitewater;
    bool has_whitewater() const { return whitewater && whitewater->enabled; }
    uint32_t frames = 60;  ///< default number of frames for `aquaform run`
    /// Dam-break scenes: width a of the column against the wall at domain.min.x. When set,
    /// `aquaform run` writes front.csv (leading edge of the first fluid block on the floor).
    std::optional<float> column_width;
    /// The "control" section as JSON text (mesh control: meshes, timeline); parsed and validated
    /// by control::load_control_section, since sim/ does not know about meshes.
    std::optional<std::string> control_json;
    /// The scene's own view (the "camera" key); without it views frame the domain (scene_camera).
    std::optional<ViewCamera> camera;
    /// The frame that shows what the scene is about (the "event_frame" key, 0 to `frames`): a dam
    /// break's wave on the far wall, a splash's crown, a shape held. Its picture must show the
    /// whole fluid and the tank up to it (tests/test_scene_framing.cpp checks every shipped scene).
    std::optional<uint32_t> event_frame;

    BlockFill fill_of(size_t block) const { return block < block_fills.size() ? block_fills[block] : BlockFill{}; }

    /// The part of the scene a renderer needs: the domain and the particles' size.
    ParticleDomain particle_domain() const {
        return {domain, particle_spacing, solver.kernel_radius_factor, static_boxes};
    }
    /// Number of particles the fluid blocks produce, each block's volume over spacing^3
    /// (sim/block_fill.h; in 64 bits so that absurd spacings are caught before any allocation),
    /// less those that start empty (starts_empty).
    uint64_t particle_count() const;
    /// The slots the solver allocates: the "capacity" key, or the start's particles and every
    /// particle the emitters make over `frames` (saturated at 2^64 - 1).
    uint64_t particle_capacity() const;
    /// What `--particles` sizes (with_particle_count): the start's particles, or with emitters the
    /// capacity.
    uint64_t sized_particle_count() const;
    /// Whether a fluid block's lattice point is left empty at t = 0: inside an obstacle, or in a
    /// nozzle's hold (the water the nozzle itself places there: EmitterSpec::holds).
    bool starts_empty(const glm::vec3& p) const;
    /// Lattice points of the fluid blocks that stand inside an obstacle at t = 0, which are not
    /// started (the commands say how many).
    uint64_t particles_in_solids() const;
    /// The start positions of every fluid particle (sim/block_fill.h), with the index of the block
    /// each came from.
    void generate_particles(std::vector<glm::vec4>& positions, std::vector<uint32_t>& block_of) const;
};

/// Fewest particles `--particles` may ask for: below it a scene is a few particles, not a fluid.
inline constexpr uint64_t kMinSceneParticles = 64;

/// The scene with its particle spacing re-derived so that its fluid blocks hold about
/// `particles` (within a few per cent; a lattice cannot hit every count). Everything else keeps
/// its size in metres: the kernel radius follows the spacing (kernel_radius_factor). The error
/// names `flag` (e.g. "--particles") and the range kMinSceneParticles..kMaxSceneParticles.
Result<Scene> with_particle_count(const Scene& scene, uint64_t particles, const std::string& flag = "--particles");
/// Why a speed the scene starts with is more than the time-step rule can carry (a fluid block's
/// start velocity, an obstacle's motion), or empty: a step moves at most solver.cfl * h and a frame
/// has at most solver.max_substeps steps. `at` says at what spacing it was found ("" or "at
/// --particles N").
std::string speed_beyond_step_rule(const Scene& scene, const std::string& at = "");

/// The part of the tank a view frames: the whole domain, or for a fluid that falls under gravity
/// without mesh control, its floor up to the height the fluid can reach (a tall domain over a
/// low column would leave most of the picture empty): the level it rests at, plus kFramedWaveReach
/// times the height its blocks (tops and the head |v|^2 / 2g of their start speeds) stand above that
/// level, at least 1.1 times the highest block's height.
constexpr float kFramedWaveReach = 2.25f;  ///< that factor (measured in framed_region)
Box framed_region(const Scene& scene);
/// The camera of every view of the scene: its own, or one that frames framed_region().
ViewCamera scene_camera(const Scene& scene, float aspect);

/// What a user should hear of the scene's obstacles before a run, one line each: the fluid that
/// is not started because it would start inside one ("obstacles.rock: 1250 particles of the fluid
/// blocks would start inside it and are not started"), and what each mesh check tolerated.
std::vector<std::string> obstacle_notes(const Scene& scene);

/// Reads and validates a scene file.
Result<Scene> load_scene(const std::filesystem::path& path);
/// Validates a scene given as JSON text; `origin` names it in messages; files it names (obstacle
/// meshes) are relative to `base_dir`.
Result<Scene> parse_scene(const std::string& json_text, const std::string& origin,
                          const std::filesystem::path& base_dir = {});

}  // namespace aquaform
