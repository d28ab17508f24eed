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
inline constexpr uint32_t kMaxSubsteps = 64;       ///< solver.substeps, from 1
inline constexpr uint32_t kMaxMaxSubsteps = 256;   ///< solver.max_substeps, from 1
inline constexpr uint32_t kMaxIterations = 100;    ///< solver.iterations, from 1
inline constexpr double kMinKernelRadiusFactor = 1.0;
inline constexpr double kMaxKernelRadiusFactor = 4.0;
inline constexpr double kMaxViscosity = 1.0;       ///< solver.viscosity, from 0
inline constexpr double kMaxCfl = 1.0;             ///< solver.cfl, above 0
inline constexpr double kMaxSpeedCap = 1.0e4;      ///< solver.max_speed [m/s], from 0 (off)
inline constexpr uint32_t kMaxScorrN = 15;         ///< solver.scorr_n, from 1
inline constexpr uint32_t kMaxFrames = 1000000;    ///< frames and event_frame
/// A fluid block's start speed [m/s]. The blow-up bound (sim/blowup.h) counts the fastest start
/// speed in, so every accepted start runs.
inline constexpr float kMaxStartSpeed = 100.0f;

/// Solver settings (Macklin & Mueller 2013, "Position Based Fluids").
/// Which densities the PBF constraint corrects (shaders/sim/pbf_lambda.comp explains the choice).
enum class DensityConstraint { clamped, two_sided };

struct SolverSettings {
    float frame_dt = 1.0f / 60.0f;      ///< simulated seconds per output frame
    /// Solver steps per frame: at least `substeps`, more where the fluid is fast (the time-step
    /// rule: the fastest particle moves at most cfl * h per step), up to `max_substeps`.
    uint32_t substeps = 2;
    uint32_t max_substeps = 32;
    uint32_t iterations = 4;            ///< constraint iterations per step
    float kernel_radius_factor = 2.0f;  ///< h = factor * particle_spacing
    float relaxation = 0.01f;           ///< epsilon of eq. 11 relative to a full neighbourhood stiffness (sim/pbf_params.h)
    float viscosity = 0.01f;            ///< XSPH c (eq. 17)
    float vorticity = 0.0f;             ///< vorticity confinement epsilon (eq. 16)
    float scorr_k = 0.1f;               ///< tensile instability k (eq. 13)
    float scorr_n = 4.0f;               ///< tensile instability n
    float scorr_dq = 0.2f;              ///< tensile instability delta q, as a fraction of h
    float cfl = 0.4f;                   ///< the time-step rule's Courant number: v_max * dt <= cfl * h
    /// A safety net, not a time-step rule: speeds are capped at this [m/s] (0 = off, the
    /// default); a frame where the cap binds is reported (FrameStats::speed_capped).
    float max_speed = 0.0f;
    /// clamped: C = max(rho / rho0 - 1, 0), only compression is corrected (the default);
    /// two_sided: C = rho / rho0 - 1, under-dense particles are pulled together too.
    DensityConstraint density_constraint = DensityConstraint::clamped;
};

/// How a fluid block is filled beyond its box (Scene::fluid_blocks keeps the box; a sphere's is
/// its bounding box, so every check on boxes holds for spheres too).
struct BlockFill {
    std::optional<float> sphere_radius;  ///< a ball of this radius about the box's centre, not the whole box
    glm::vec3 velocity{0.0f};            ///< the block's particles start with it [m/s]
};

struct Scene {
    std::filesystem::path path;         ///< file it was loaded from (empty when built in code)
    std::string name;
    Box domain;                          ///< the tank: particles are kept inside it
    float particle_spacing = 0.02f;      ///< initial lattice spacing [m]
    float rest_density = 1000.0f;        ///< rho0 [kg/m^3]
    glm::vec3 gravity{0.0f, -9.81f, 0.0f};
    std::vector<Box> fluid_blocks;       ///< filled with particles on a lattice at t = 0
    std::vector<BlockFill> block_fills;  ///< per fluid block; a block without one is a box at rest
    std::vector<Box> static_boxes;       ///< solid obstacles inside the domain
    SolverSettings solver;
    uint32_t frames = 60;                ///< default number of frames for `aquaform run`
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
    ParticleDomain particle_domain() const { return {domain, particle_spacing, solver.kernel_radius_factor, static_boxes}; }
    /// Number of particles the fluid blocks produce (computed without generating them, in
    /// 64 bits so that absurd spacings are caught before any allocation).
    uint64_t particle_count() const;
    /// The lattice positions of every fluid particle, with the index of the block each came from.
    void generate_particles(std::vector<glm::vec4>& positions, std::vector<uint32_t>& block_of) const;
};

/// Fewest particles `--particles` may ask for: below it a scene is a few particles, not a fluid.
inline constexpr uint64_t kMinSceneParticles = 64;

/// The scene with its particle spacing re-derived so that its fluid blocks hold about
/// `particles` (within a few per cent; a lattice cannot hit every count). Everything else keeps
/// its size in metres: the kernel radius follows the spacing (kernel_radius_factor). The error
/// names `flag` (e.g. "--particles") and the range kMinSceneParticles..kMaxSceneParticles.
Result<Scene> with_particle_count(const Scene& scene, uint64_t particles, const std::string& flag = "--particles");

/// The part of the tank a view frames: the whole domain, or for a fluid that falls under gravity
/// without mesh control, its floor up to the height the fluid can reach (a tall domain over a
/// low column would leave most of the picture empty): the level it rests at, plus kFramedWaveReach
/// times the height its blocks (tops and the head |v|^2 / 2g of their start speeds) stand above that
/// level, at least 1.1 times the highest block's height.
constexpr float kFramedWaveReach = 2.25f;  ///< that factor (measured in framed_region)
Box framed_region(const Scene& scene);
/// The camera of every view of the scene: its own, or one that frames framed_region().
ViewCamera scene_camera(const Scene& scene, float aspect);

/// Reads and validates a scene file.
Result<Scene> load_scene(const std::filesystem::path& path);
/// Validates a scene given as JSON text; `origin` names it in messages.
Result<Scene> parse_scene(const std::string& json_text, const std::string& origin);

}  // namespace aquaform
