// Scene loading: strict validation of the JSON scene schema (see scene.h and
// assets/scenes/*.json). Helpers throw `Invalid` internally; parse_scene turns it into an Error
// prefixed with the origin, so nothing escapes load_scene/parse_scene.
#include "sim/scene.h"

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <span>
#include <string_view>

#include "core/json_fields.h"
#include "shaders/shared/sim/pbf_layout.h"
#include "sim/obstacles.h"

namespace aquaform {
namespace {

using namespace json_fields;

constexpr std::string_view kTopKeys[] = {
    "name",   "domain",       "particle_spacing", "rest_density", "gravity", "fluid_blocks", "static_boxes",
    "frames", "column_width", "solver",           "control",      "camera",  "event_frame",  "obstacles",
    "probes", "whitewater",   "emitters",         "sinks",        "capacity"};
constexpr std::string_view kSolverKeys[] = {"frame_dt",   "substeps",           "iterations", "kernel_radius_factor",
                                            "relaxation", "viscosity",          "vorticity",  "scorr_k",
                                            "scorr_n",    "scorr_dq",           "cfl",        "max_substeps",
                                            "max_speed",  "density_constraint", "method",     "divergence_iterations"};

constexpr const char* kAxis[] = {"x", "y", "z"};

void check_inside(const Box& b, const json& v, const std::string& path, const Box& domain) {
    for (int a = 0; a < 3; ++a) {
        const char* side = b.min[a] < domain.min[a] ? "min" : b.max[a] > domain.max[a] ? "max" : nullptr;
        if (side)
            fail(path + " " + side + " " + written(v[side]) + " lies outside the domain " + fmt(domain) + " on " +
                 kAxis[a] + "; move the block inside the domain or enlarge \"domain\"");
    }
}

/// True when the boxes share a volume; boxes that only touch do not overlap.
bool overlaps(const Box& a, const Box& b) {
    for (int i = 0; i < 3; ++i)
        if (a.max[i] <= b.min[i] || b.max[i] <= a.min[i]) return false;
    return true;
}

// ---- lattice ---------------------------------------------------------------------------------

/// A block side shorter than the spacing (to a relative 1e-4, for sides given as multiples of it)
/// holds no whole layer: refused at load.
bool thinner_than_spacing(float extent, float spacing) { return !(double(extent) / double(spacing) + 1e-4 >= 1.0); }

/// fn(point, block) for every particle of every fluid block (sim/block_fill.h), block by block.
template <typename Fn>
void for_each_block_point(const Scene& scene, Fn fn) {
    for (size_t bi = 0; bi < scene.fluid_blocks.size(); ++bi)
        for_each_block_particle(scene.fluid_blocks[bi], scene.fill_of(bi), scene.particle_spacing, scene.gravity,
                                [&](const glm::vec3& p) { fn(p, bi); });
}

// ---- the scene -------------------------------------------------------------------------------

constexpr const char* kBlockExample = "{\"min\": [0, 0, 0], \"max\": [0.3, 0.6, 0.2]}";

void read_solver(const json& s, SolverSettings& out) {
    if (!s.is_object())
        fail("solver must be an object such as {\"substeps\": 3, \"iterations\": 4}, got " + written(s) + " (" +
             kind_of(s) + ")");
    check_keys(s, "in solver", kSolverKeys);
    struct FloatKey {
        const char* key;
        float SolverSettings::*member;
        Range range;
    };
    const FloatKey floats[] = {
        {"frame_dt",
         &SolverSettings::frame_dt,
         {kMinFrameDt, kMaxFrameDt, false, false,
          "a number of seconds from " + fmt(kMinFrameDt) + " to " + fmt(kMaxFrameDt) + ", e.g. 0.0166667 (1/60 s)"}},
        {"kernel_radius_factor",
         &SolverSettings::kernel_radius_factor,
         {kMinKernelRadiusFactor, kMaxKernelRadiusFactor, false, false,
          "a number from " + fmt(kMinKernelRadiusFactor) + " to " + fmt(kMaxKernelRadiusFactor) +
              " (h = factor * particle_spacing; 2.0 is usual)"}},
        {"relaxation",
         &SolverSettings::relaxation,
         {0.0, HUGE_VAL, true, false,
          "a positive number, e.g. 0.01 (relative to the stiffness of a full neighbourhood)"}},
        {"viscosity",
         &SolverSettings::viscosity,
         {0.0, kMaxViscosity, false, false, "a number from 0 to " + fmt(kMaxViscosity) + ", e.g. 0.01"}},
        {"vorticity",
         &SolverSettings::vorticity,
         {0.0, HUGE_VAL, false, false, "a number >= 0, e.g. 0.0001 (0 turns it off)"}},
        {"scorr_k",
         &SolverSettings::scorr_k,
         {0.0, HUGE_VAL, false, false, "a number >= 0, e.g. 0.1 (0 turns it off)"}},
        {"scorr_dq",
         &SolverSettings::scorr_dq,
         {0.0, 1.0, true, true, "a number strictly between 0 and 1 (a fraction of h), e.g. 0.2"}},
        {"cfl",
         &SolverSettings::cfl,
         {0.0, kMaxCfl, true, false, "a number greater than 0 and at most " + fmt(kMaxCfl) + ", e.g. 0.4"}},
        {"max_speed",
         &SolverSettings::max_speed,
         {0.0, kMaxSpeedCap, false, false,
          "a speed in m/s from 0 (no cap, the default) to " + fmt(kMaxSpeedCap) + ", e.g. 50"}},
    };
    for (const auto& f : floats)
        if (s.contains(f.key)) out.*f.member = read_number(s[f.key], child("solver", f.key), f.range);
    if (s.contains("substeps")) out.substeps = read_integer(s["substeps"], "solver.substeps", 1, kMaxSubsteps);
    if (s.contains("max_substeps"))
        out.max_substeps = read_integer(s["max_substeps"], "solver.max_substeps", 1, kMaxMaxSubsteps);
    if (!s.contains("max_substeps")) out.max_substeps = std::max(out.max_substeps, out.substeps);
    if (out.max_substeps < out.substeps)
        fail("solver.max_substeps is " + std::to_string(out.max_substeps) + ", below solver.substeps (" +
             std::to_string(out.substeps) + ", the least steps per frame); raise max_substeps or lower substeps");
    if (s.contains("iterations"))
        out.iterations = read_integer(s["iterations"], "solver.iterations", 1, kMaxIterations);
    // An integer power: the GPU raises to it by squarings, without pow (sim/pbf_physics.h).
    if (s.contains("scorr_n")) out.scorr_n = float(read_integer(s["scorr_n"], "solver.scorr_n", 1, kMaxScorrN));
    if (s.contains("density_constraint")) {
        const json& c = s["density_constraint"];
        const bool known = c.is_string() && (c == "clamped" || c == "two_sided");
        if (!known)
            fail("solver.density_constraint is " + written(c) +
                 "; use \"clamped\" (only compression is corrected, "
                 "the default) or \"two_sided\" (under-dense particles are pulled together too)");
        out.density_constraint = c == "two_sided" ? DensityConstraint::two_sided : DensityConstraint::clamped;
    }
    if (s.contains("method")) {
        const json& m = s["method"];
        if (!m.is_string() || (m != "pbf" && m != "dfsph"))
            fail("solver.method is " + written(m) +
                 "; use \"pbf\" (position-based fluids: fast, damps waves; the default) or \"dfsph\" "
                 "(divergence-free SPH, experimental: keeps waves, but its surface sprays)");
        out.method = m == "dfsph" ? PressureMethod::dfsph : PressureMethod::pbf;
    }
    if (s.contains("divergence_iterations")) {
        if (out.method != PressureMethod::dfsph)
            fail(
                "solver.divergence_iterations is DFSPH's (its divergence-free solve) and this scene's solver.method "
                "is \"pbf\"; add \"method\": \"dfsph\" to the solver or remove the key");
        out.divergence_iterations =
            read_integer(s["divergence_iterations"], "solver.divergence_iterations", 0, kMaxIterations);
    }
}

std::vector<Box> read_boxes(const json& v, const std::string& key, const Box& domain) {
    if (!v.is_array())
        fail(key + " must be an array of boxes such as [" + kBlockExample + "], got " + written(v) + " (" + kind_of(v) +
             ")");
    std::vector<Box> boxes;
    for (size_t i = 0; i < v.size(); ++i) {
        std::string path = key + "[" + std::to_string(i) + "]";
        boxes.push_back(read_box(v[i], path, "\"max\": [0.3, 0.6, 0.2]"));
        check_inside(boxes.back(), v[i], path, domain);
    }
    return boxes;
}

constexpr std::string_view kBoxBlockKeys[] = {"shape", "min", "max", "velocity", "surface_wave"};
constexpr std::string_view kSurfaceWaveKeys[] = {"amplitude", "wavelength", "along"};

/// A box block's "surface_wave" {amplitude, wavelength, along} (sim/block_fill.h): the trough above
/// the block's bottom, the crest inside the domain.
SurfaceWave read_surface_wave(const json& v, const std::string& path, const Box& box, const Box& domain) {
    if (!v.is_object())
        fail(path + " must be an object such as {\"amplitude\": 0.03, \"wavelength\": 2.0, \"along\": \"x\"}, got " +
             written(v) + " (" + kind_of(v) + ")");
    check_keys(v, "in " + path, kSurfaceWaveKeys);
    require(v, "amplitude", "in " + path, "\"amplitude\": 0.03");
    require(v, "wavelength", "in " + path, "\"wavelength\": 2.0");
    SurfaceWave wave;
    const float height = box.max.y - box.min.y;
    wave.amplitude = read_number(v["amplitude"], path + ".amplitude",
                                 {0.0, double(height), false, true, "metres, from 0 to below the block's height"});
    wave.length =
        read_number(v["wavelength"], path + ".wavelength", {0.0, HUGE_VAL, true, false, "a positive length in metres"});
    if (v.contains("along")) {
        const json& a = v["along"];
        if (!(a.is_string() && (a == "x" || a == "z")))
            fail(path + ".along is " + written(a) + "; use \"x\" or \"z\" (the wave runs across the block's top)");
        wave.along = a == "x" ? 0 : 2;
    }
    if (box.max.y + wave.amplitude > domain.max.y)
        fail(path + ".amplitude " + written(v["amplitude"]) + " lifts the crest to " + fmt(box.max.y + wave.amplitude) +
             ", above the domain's top " + fmt(domain.max.y) + "; lower the block or the amplitude");
    return wave;
}
constexpr std::string_view kSphereBlockKeys[] = {"shape", "center", "radius", "velocity"};

/// A fluid block: a box {min, max} or {"shape": "sphere", center, radius}, either with an
/// optional start "velocity".
std::pair<Box, BlockFill> read_fluid_block(const json& v, const std::string& path, const Box& domain) {
    if (!v.is_object())
        fail(path + " must be an object such as " + std::string(kBlockExample) +
             " or {\"shape\": \"sphere\", "
             "\"center\": [x, y, z], \"radius\": r}, got " +
             written(v) + " (" + kind_of(v) + ")");
    const json* shape = v.contains("shape") ? &v["shape"] : nullptr;
    if (shape && !(shape->is_string() && (*shape == "box" || *shape == "sphere")))
        fail(path + ".shape is " + written(*shape) +
             "; use \"box\" (with min and max) or \"sphere\" (with center and radius)");
    Box box;
    BlockFill fill;
    if (shape && *shape == "sphere") {
        check_keys(v, "in " + path, kSphereBlockKeys);
        require(v, "center", "in " + path, "\"center\": [0.5, 0.6, 0.5]");
        require(v, "radius", "in " + path, "\"radius\": 0.1");
        const glm::vec3 c = read_vec3(v["center"], path + ".center", "an array of three numbers [x, y, z] in metres");
        const float r =
            read_number(v["radius"], path + ".radius", {0.0, HUGE_VAL, true, false, "a positive number of metres"});
        box = {c - glm::vec3(r), c + glm::vec3(r)};
        fill.sphere_radius = r;
        for (int a = 0; a < 3; ++a)
            if (box.min[a] < domain.min[a] || box.max[a] > domain.max[a])
                fail(path + " (center " + written(v["center"]) + ", radius " + written(v["radius"]) +
                     ") reaches outside the domain " + fmt(domain) + " on " + kAxis[a] +
                     "; move the sphere inside the domain or make it smaller");
    } else {
        check_keys(v, "in " + path, kBoxBlockKeys);
        json plain = v;  // read_box knows only min and max
        plain.erase("shape");
        plain.erase("velocity");
        plain.erase("surface_wave");
        box = read_box(plain, path, "\"max\": [0.3, 0.6, 0.2]");
        check_inside(box, v, path, domain);
        if (v.contains("surface_wave"))
            fill.wave = read_surface_wave(v["surface_wave"], path + ".surface_wave", box, domain);
    }
    if (v.contains("velocity")) {
        fill.velocity = read_vec3(v["velocity"], path + ".velocity", "an array of three numbers [x, y, z] in m/s");
        if (!(glm::length(fill.velocity) <= kMaxStartSpeed))
            fail(path + ".velocity " + written(v["velocity"]) + " is " + fmt(glm::length(fill.velocity)) +
                 " m/s, faster than " + fmt(kMaxStartSpeed) + " m/s; give a speed in m/s, e.g. [0, -2, 0]");
    }
    return {box, fill};
}

Scene read_scene(const json& j, const std::filesystem::path& base_dir) {
    if (!j.is_object())
        fail("the top level must be a JSON object {\"name\": ..., \"domain\": ..., ...}, got " + written(j) + " (" +
             kind_of(j) + "); see assets/scenes/dam_break.json for an example");
    check_keys(j, "at top level", kTopKeys);
    const std::string top = "at top level";
    require(j, "name", top, "\"name\": \"dam break\"");
    require(j, "domain", top, "\"domain\": {\"min\": [0, 0, 0], \"max\": [1.6, 0.8, 0.2]}");
    require(j, "particle_spacing", top, "\"particle_spacing\": 0.02");
    // A scene whose water all comes from its nozzles may start empty.
    if (!j.contains("fluid_blocks") && !j.contains("emitters"))
        fail(
            "missing required key \"fluid_blocks\" at top level (and no \"emitters\" bring the water); add it, "
            "e.g. \"fluid_blocks\": [" +
            std::string(kBlockExample) + "], or \"emitters\"");

    Scene scene;
    const json& name = j["name"];
    if (!name.is_string() || name.get<std::string>().empty())
        fail("name must be a non-empty string, e.g. \"dam break\", got " + written(name) + " (" + kind_of(name) + ")");
    scene.name = name.get<std::string>();

    scene.domain = read_box(j["domain"], "domain", "\"max\": [1.6, 0.8, 0.2]");
    scene.particle_spacing = read_number(j["particle_spacing"], "particle_spacing",
                                         {0.0, HUGE_VAL, true, false, "a positive number of metres, e.g. 0.02"});
    if (j.contains("rest_density"))
        scene.rest_density =
            read_number(j["rest_density"], "rest_density",
                        {0.0, HUGE_VAL, true, false, "a positive number in kg/m^3, e.g. 1000 for water"});
    if (j.contains("gravity")) {
        scene.gravity =
            read_vec3(j["gravity"], "gravity", "an array of three numbers [x, y, z] in m/s^2, e.g. [0, -9.81, 0]");
        // Beyond this the substep rule (substeps_for_speed) reaches its maximum and the speed cap
        // binds in every frame, so a run would show the cap, not the gravity.
        if (!(glm::length(scene.gravity) <= kMaxGravity))
            fail("gravity " + written(j["gravity"]) + " is " + fmt(glm::length(scene.gravity)) + " m/s^2; at most " +
                 fmt(kMaxGravity) + " m/s^2 (about 100 g) is simulated: give it in m/s^2, e.g. [0, -9.81, 0]");
    }
    if (j.contains("frames")) scene.frames = read_integer(j["frames"], "frames", 1, kMaxFrames);
    if (j.contains("solver")) read_solver(j["solver"], scene.solver);
    // The control section belongs to control/ (control/control_scene.h), which validates it.
    if (j.contains("control")) scene.control_json = j["control"].dump();

    if (j.contains("static_boxes")) {
        // The solver keeps its solids in a fixed table of its parameter block (SimParams.solids).
        check_count(j["static_boxes"], "static_boxes", PBF_MAX_SOLIDS,
                    "the solver keeps its solids in a fixed table; merge neighbouring boxes");
        scene.static_boxes = read_boxes(j["static_boxes"], "static_boxes", scene.domain);
    }
    const json& blocks = j.contains("fluid_blocks") ? j["fluid_blocks"] : json::array();
    if (!blocks.is_array())
        fail("fluid_blocks must be an array of blocks such as [" + std::string(kBlockExample) + "], got " +
             written(blocks) + " (" + kind_of(blocks) + ")");
    // Blocks are checked against each other pairwise below.
    check_count(blocks, "fluid_blocks", kMaxFluidBlocks, "merge neighbouring blocks into larger ones");
    for (size_t i = 0; i < blocks.size(); ++i) {
        auto [box, fill] = read_fluid_block(blocks[i], "fluid_blocks[" + std::to_string(i) + "]", scene.domain);
        scene.fluid_blocks.push_back(box);
        scene.block_fills.push_back(fill);
    }
    if (j.contains("camera")) scene.camera = read_view_camera(j["camera"], "camera");
    if (j.contains("event_frame")) {
        scene.event_frame = read_integer(j["event_frame"], "event_frame", 0, kMaxFrames);
        if (*scene.event_frame > scene.frames)
            fail("event_frame is " + written(j["event_frame"]) + ", past the scene's " + std::to_string(scene.frames) +
                 " frames; give a frame from 0 to " + std::to_string(scene.frames) + " or raise \"frames\"");
    }
    if (scene.fluid_blocks.empty() && !j.contains("emitters"))
        fail("fluid_blocks is [] (empty); add at least one block, e.g. [" + std::string(kBlockExample) +
             "], or an emitter that brings the water (\"emitters\")");

    for (size_t i = 0; i < scene.fluid_blocks.size(); ++i) {
        const Box& b = scene.fluid_blocks[i];
        std::string path = "fluid_blocks[" + std::to_string(i) + "]";
        for (int a = 0; a < 3; ++a)
            if (thinner_than_spacing(b.max[a] - b.min[a], scene.particle_spacing) ||
                block_particle_count(b, scene.fill_of(i), scene.particle_spacing) == 0)
                fail(path + " " + fmt(b) + " is thinner on " + kAxis[a] + " than particle_spacing " +
                     written(j["particle_spacing"]) +
                     ", so it holds no particles; widen the block or reduce "
                     "particle_spacing");
        for (size_t s = 0; s < scene.static_boxes.size(); ++s)
            if (overlaps(b, scene.static_boxes[s]))
                fail(path + " " + fmt(b) + " overlaps static_boxes[" + std::to_string(s) + "] " +
                     fmt(scene.static_boxes[s]) +
                     "; fluid cannot start inside a solid: shrink or move the block "
                     "(boxes may touch)");
        for (size_t k = 0; k < i; ++k)
            if (overlaps(b, scene.fluid_blocks[k]))
                fail(path + " " + fmt(b) + " overlaps fluid_blocks[" + std::to_string(k) + "] " +
                     fmt(scene.fluid_blocks[k]) +
                     ", which would place particles on top of each other; make the "
                     "blocks disjoint (they may touch)");
    }

    if (j.contains("obstacles"))
        scene.obstacles = read_obstacles(j["obstacles"], scene, base_dir, PBF_MAX_SOLIDS - scene.static_boxes.size());
    if (j.contains("probes")) scene.probes = read_probes(j["probes"], scene);
    if (j.contains("whitewater")) scene.whitewater = read_whitewater(j["whitewater"]);
    if (j.contains("emitters")) scene.emitters = read_emitters(j["emitters"], scene);
    if (j.contains("sinks")) scene.sinks = read_sinks(j["sinks"], scene, scene.emitters, base_dir);

    if (j.contains("column_width")) {
        const json& cw = j["column_width"];
        float a =
            read_number(cw, "column_width",
                        {0.0, HUGE_VAL, true, false, "a positive number of metres (the x-extent of fluid_blocks[0])"});
        const Box& b = scene.fluid_blocks[0];
        if (scene.fill_of(0).sphere_radius)
            fail("column_width is " + written(cw) +
                 " but fluid_blocks[0] is a sphere; a dam break's column is a box "
                 "against the wall at domain.min.x: make it fluid_blocks[0] or remove column_width");
        float extent = b.max.x - b.min.x;
        if (std::fabs(a - extent) > 1e-4f * std::max(a, extent))
            fail("column_width is " + written(cw) + " but fluid_blocks[0] is " + fmt(extent) + " m wide on x (" +
                 fmt(b) + "); set column_width to " + fmt(extent) + " or resize the block");
        if (std::fabs(b.min.x - scene.domain.min.x) > 0.5f * scene.particle_spacing)
            fail("column_width is " + written(cw) + " but fluid_blocks[0] starts at x = " + fmt(b.min.x) +
                 ", not against the wall at domain.min.x = " + fmt(scene.domain.min.x) +
                 "; move the block to the wall or remove column_width");
        scene.column_width = a;
    }

    if (const std::string fast = speed_beyond_step_rule(scene); !fast.empty()) fail(fast);
    uint64_t count = scene.particle_count();
    if (count > kMaxSceneParticles)
        fail("the fluid blocks hold " + (count < 1000000000000ull ? std::to_string(count) : fmt(double(count))) +
             " particles at particle_spacing " + written(j["particle_spacing"]) + ", more than the limit of " +
             std::to_string(kMaxSceneParticles) + "; increase particle_spacing or shrink fluid_blocks");
    if (j.contains("capacity")) {
        scene.capacity = read_integer(j["capacity"], "capacity", uint32_t(std::max<uint64_t>(count, 1)),
                                      uint32_t(kMaxSceneParticles));
    } else if (const uint64_t capacity = scene.particle_capacity(); capacity > kMaxSceneParticles) {
        fail("the emitters would make " + fmt(double(capacity - count)) + " particles over the scene's " +
             std::to_string(scene.frames) + " frames, more than the limit of " + std::to_string(kMaxSceneParticles) +
             " particles; set \"capacity\" (a nozzle stops while the fluid fills it, and the run says so), add a "
             "sink, or shorten the nozzles' run (\"stop\")");
    }
    return scene;
}

}  // namespace

const char* method_name(PressureMethod method) { return method == PressureMethod::dfsph ? "dfsph" : "pbf"; }

uint64_t Scene::particle_count() const {
    uint64_t total = 0;
    for (size_t i = 0; i < fluid_blocks.size(); ++i) {
        uint64_t n = block_particle_count(fluid_blocks[i], fill_of(i), particle_spacing);
        total = n > std::numeric_limits<uint64_t>::max() - total ? std::numeric_limits<uint64_t>::max() : total + n;
    }
    // Only a count the solver could hold is worth the inside test's time.
    if (total > kMaxSceneParticles || (obstacles.empty() && emitters.empty())) return total;
    uint64_t not_started = 0;
    for_each_block_point(*this, [&](const glm::vec3& p, size_t) { not_started += starts_empty(p) ? 1 : 0; });
    return total - not_started;
}

bool Scene::starts_empty(const glm::vec3& p) const {
    if (!obstacles.empty() && inside_start_solid(obstacles, p)) return true;
    return std::any_of(emitters.begin(), emitters.end(),
                       [&](const EmitterSpec& e) { return e.holds(p, particle_spacing, kernel_radius()); });
}

uint64_t Scene::sized_particle_count() const { return emitters.empty() ? particle_count() : particle_capacity(); }

uint64_t Scene::particle_capacity() const {
    if (capacity) return *capacity;
    uint64_t total = particle_count();
    const double end = double(frames) * solver.frame_dt;
    for (const EmitterSpec& e : emitters) {
        const NozzleLattice lattice = nozzle_lattice(e, particle_spacing);
        const double layers = std::floor(e.distance_at(end) / lattice.layer_spacing) + 1.0;
        const double made = layers * double(lattice.offsets.size());
        total = made >= double(std::numeric_limits<uint64_t>::max() - total) ? std::numeric_limits<uint64_t>::max()
                                                                             : total + uint64_t(made);
    }
    return total;
}

uint64_t Scene::particles_in_solids() const {
    uint64_t inside = 0;
    for_each_block_point(*this,
                         [&](const glm::vec3& p, size_t) { inside += inside_start_solid(obstacles, p) ? 1 : 0; });
    return inside;
}

void Scene::generate_particles(std::vector<glm::vec4>& positions, std::vector<uint32_t>& block_of) const {
    positions.clear();
    block_of.clear();
    uint64_t total = particle_count();
    positions.reserve(total);  // throws std::length_error for absurd counts instead of looping forever
    block_of.reserve(total);
    for_each_block_point(*this, [&](const glm::vec3& p, size_t block) {
        if (starts_empty(p)) return;
        positions.emplace_back(p, 0.0f);
        block_of.push_back(static_cast<uint32_t>(block));
    });
}

Result<Scene> with_particle_count(const Scene& scene, uint64_t particles, const std::string& flag) {
    if (particles < kMinSceneParticles || particles > kMaxSceneParticles)
        return Error{flag + " " + std::to_string(particles) + " is out of range; ask for " +
                     std::to_string(kMinSceneParticles) + " to " + std::to_string(kMaxSceneParticles) + " particles"};
    Scene out = scene;
    const uint64_t now = scene.sized_particle_count();
    if (now == 0) return Error{flag + ": " + scene.name + " holds no particle to scale; give its fluid blocks a size"};
    // A capacity the scene gives is in particles of its own spacing: it scales with the count.
    const auto at_spacing = [&](Scene& s, double spacing) {
        s.particle_spacing = float(spacing);
        if (scene.capacity)
            s.capacity =
                uint64_t(std::llround(double(*scene.capacity) * std::pow(scene.particle_spacing / spacing, 3.0)));
        return s.sized_particle_count();
    };
    // The count goes as spacing^-3; a few corrections absorb the lattice's rounding at the blocks' faces.
    double spacing = scene.particle_spacing * std::cbrt(double(now) / double(particles));
    float best = scene.particle_spacing;
    double best_error = INFINITY;
    for (int round = 0; round < 8; ++round) {
        const uint64_t n = at_spacing(out, spacing);
        const double error = std::abs(double(n) - double(particles)) / double(particles);
        if (error < best_error) best_error = error, best = out.particle_spacing;
        if (error < 0.005 || n == 0) break;
        spacing *= std::cbrt(double(n) / double(particles));
    }
    at_spacing(out, best);
    // Every block that holds fluid must keep some: a coarser lattice can miss a small block
    // (droplet_curtain's 60 droplets at 4000 particles) and the scene would lose it silently.
    auto loses_a_block = [&](double spacing, size_t* which) {
        for (size_t i = 0; i < scene.fluid_blocks.size(); ++i)
            if (block_particle_count(scene.fluid_blocks[i], scene.fill_of(i), scene.particle_spacing) > 0 &&
                block_particle_count(scene.fluid_blocks[i], scene.fill_of(i), float(spacing)) == 0) {
                if (which) *which = i;
                return true;
            }
        return false;
    };
    size_t lost = 0;
    if (loses_a_block(out.particle_spacing, &lost)) {
        // The coarsest spacing up to which every block keeps a particle, from the scene's own
        // upwards (a small sphere's lattice points come and go with the spacing, so it is walked,
        // not bisected); within 10 % of the count asked it is taken, else its count is the advice.
        double keep = scene.particle_spacing;
        while (keep < 64.0 * scene.particle_spacing && !loses_a_block(keep * 1.005, nullptr)) keep *= 1.005;
        Scene kept = scene;
        const uint64_t keeps = at_spacing(kept, keep);
        if (std::abs(double(keeps) - double(particles)) <= 0.1 * double(particles)) return kept;
        return Error{flag + " " + std::to_string(particles) + " cannot be met by " + scene.name + ": fluid_blocks[" +
                     std::to_string(lost) + "] (and any as small) would hold no particle at that size; at least " +
                     std::to_string(keeps) + " particles keep every block"};
    }
    if (out.sized_particle_count() == 0 || best_error > 0.5)
        return Error{flag + " " + std::to_string(particles) + " cannot be met by " + scene.name +
                     ": its thinnest fluid block holds no particle at that size; ask for more particles"};
    for (const EmitterSpec& e : out.emitters)
        if (const std::string small = nozzle_too_small(e, out.particle_spacing); !small.empty())
            return Error{flag + " " + std::to_string(particles) + " makes the particles of " + scene.name +
                         " too coarse for emitters." + e.name + ": " + small + "; ask for more particles"};
    // A finer spacing is a shorter step's reach: speeds the scene's own spacing carried may not be.
    if (const std::string fast = speed_beyond_step_rule(out, "at " + flag + " " + std::to_string(particles));
        !fast.empty())
        return Error{fast};
    return out;
}

std::string speed_beyond_step_rule(const Scene& scene, const std::string& at) {
    const double limit = max_obstacle_speed(scene), gravity = glm::length(scene.gravity);
    const double per_step = double(scene.solver.cfl) * scene.solver.kernel_radius_factor * scene.particle_spacing;
    const auto refuse = [&](const std::string& what, double speed, const std::string& slower) {
        const uint32_t steps = uint32_t(std::ceil(scene.solver.max_substeps * speed / limit));
        return what + " " + fmt(speed) + " m/s" + (at.empty() ? "" : " " + at) +
               ", faster than the time-step rule "
               "can carry: a step moves at most solver.cfl * h = " +
               fmt(per_step) +
               " m and a frame has at most "
               "solver.max_substeps = " +
               std::to_string(scene.solver.max_substeps) + " steps, so at most " + fmt(limit) + " m/s; " + slower +
               (steps <= kMaxMaxSubsteps ? " or raise solver.max_substeps to " + std::to_string(steps)
                                         : " (solver.max_substeps goes up to " + std::to_string(kMaxMaxSubsteps) + ")");
    };
    for (size_t i = 0; i < scene.fluid_blocks.size(); ++i) {
        // The first frame's steps follow the start speed and a frame of gravity (pbf_params.cpp).
        const double speed = glm::length(scene.fill_of(i).velocity) + gravity * scene.solver.frame_dt;
        if (glm::length(scene.fill_of(i).velocity) > 0.0f && speed > limit)
            return refuse("fluid_blocks[" + std::to_string(i) + "].velocity with a frame of gravity reaches", speed,
                          "give a slower start velocity");
    }
    for (const ObstacleSpec& o : scene.obstacles)
        if (o.max_speed > limit)
            return refuse("obstacles." + o.name + " moves at up to", o.max_speed, "slow its animation down");
    for (const EmitterSpec& e : scene.emitters)
        if (const float speed = e.max_speed(0.0, HUGE_VAL); speed > limit)
            return refuse("emitters." + e.name + " emits at up to", speed, "give the nozzle a slower speed");
    return {};
}

Box framed_region(const Scene& scene) {
    Box region = scene.domain;
    // Mesh control lifts fluid into its shapes anywhere in the domain; sideways gravity moves
    // it anywhere too: the whole tank is framed.
    const float g = std::max(-scene.gravity.y, 0.0f);
    if (scene.control_json || scene.fluid_blocks.empty() || g < 0.9f * glm::length(scene.gravity) || g <= 0.0f)
        return region;
    const float floor = scene.domain.min.y;
    // The height the fluid's energy reaches: each block's top plus the head of its start speed,
    // |v|^2 / 2g (a block thrown sideways or down splashes up as high as one thrown up).
    float top = floor;
    for (size_t i = 0; i < scene.fluid_blocks.size(); ++i) {
        const glm::vec3 v = scene.fill_of(i).velocity;
        top = std::max(top, scene.fluid_blocks[i].max.y + glm::dot(v, v) / (2.0f * g));
    }
    for (const Box& box : scene.static_boxes) top = std::max(top, box.max.y);
    // The level the fluid comes to rest at, spread over the floor: only the height above it
    // moves. A falling column's wave climbs the far wall: at the violent dam break's wave-on-
    // the-wall frame (0.8 s, 16k particles) 99 % of the fluid lies below 1.8 times that height
    // above the rest level, 99.9 % below 2.3 times, its highest droplet at 2.75 (2.9 at 20k;
    // Ritter's front speed 2 sqrt(gH) alone carries a head of 2H). The frame reaches 2.25 times:
    // the wave and nearly all its spray, while the few highest droplets may leave the picture;
    // framed for every droplet, the pool was a strip at the bottom of a 16:9 picture. A pool at
    // rest stays where it is, and keeps a tenth of its depth of headroom.
    const glm::vec3 size = scene.domain.size();
    const float volume = float(scene.particle_count()) * std::pow(scene.particle_spacing, 3.0f);
    const float rest = floor + std::min(volume / std::max(size.x * size.z, 1e-12f), top - floor);
    const float reach = std::max(rest + kFramedWaveReach * (top - rest), floor + 1.1f * (top - floor));
    region.max.y = std::min(scene.domain.max.y, reach);
    return region;
}

ViewCamera scene_camera(const Scene& scene, float aspect) {
    return scene.camera ? *scene.camera : camera_for_domain(framed_region(scene), aspect);
}

Result<Scene> parse_scene(const std::string& json_text, const std::string& origin,
                          const std::filesystem::path& base_dir) {
    try {
        return read_scene(parse_strict(json_text, origin), base_dir);
    } catch (const Invalid& e) {
        return Error{e.has_origin ? e.message : origin + ": " + e.message};
    } catch (const json::exception& e) {
        return Error{origin + ": cannot read the JSON: " + std::string(e.what())};
    } catch (const std::exception& e) {
        return Error{origin + ": " + std::string(e.what())};
    }
}

Result<Scene> load_scene(const std::filesystem::path& path) {
    std::string text;
    try {
        text = read_json_file(path, "scene file", "check the path (scenes live in assets/scenes/)");
    } catch (const Invalid& e) {
        return Error{e.message};
    }
    Result<Scene> scene = parse_scene(text, path.string(), path.parent_path());
    if (scene) scene.value().path = path;
    return scene;
}

std::vector<std::string> obstacle_notes(const Scene& scene) {
    std::vector<std::string> notes;
    if (scene.obstacles.empty()) return notes;
    const uint64_t inside = scene.particles_in_solids();
    for (const ObstacleSpec& o : scene.obstacles) {
        if (inside > 0) {
            // Counted per obstacle (a point inside two counts for both; the total is exact).
            uint64_t mine = 0;
            Scene one = scene;
            one.obstacles = {o};
            mine = one.particles_in_solids();
            if (mine > 0)
                notes.push_back(
                    "obstacles." + o.name + ": " + std::to_string(mine) +
                    " particles of the fluid blocks would start inside it and are not started (the scene's " +
                    std::to_string(scene.particle_count()) + " particles are those left)");
        }
        if (!o.mesh_notes.empty())
            notes.push_back("obstacles." + o.name + " (" + o.file.string() + "): " + o.mesh_notes);
    }
    return notes;
}

}  // namespace aquaform
