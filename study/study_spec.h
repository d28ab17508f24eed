// The spec of `aquaform study`: a matrix of cases (a scene at a time and a camera), particle
// counts, resolutions and method configurations, plus an optional solver stability map. Every
// array-valued method parameter is expanded, so {"method": "sbuffer", "size": [1, 2]} is two
// configurations. Schema (unknown keys are refused, naming the closest known one):
//
// { "name": "default", "repeats": 2,
//   "cases": [{ "name": "karpati_table1",
//               "scene": "dam_break" | "path/relative/to/the/spec.json",
//               "particles": [2000, 4000],        // a scene file is scaled to each (default: its own)
//               "time": "half_tank" | 0.25,       // simulated seconds; half_tank: the front at mid-tank
//               "camera": "front" | "far" | "closeup" | {"eye": [..], "target": [..], "fov": 40},
//               "resolutions": ["512x512"],
//               "list_bytes_per_pixel": 256,      // metaball list memory (a budget to overflow)
//               "methods": [{"method": "sbuffer", "visual": "real", "size": [1, 2], "recursion": [1, 2, 4],
//                            "bisection": [3]},
//                           {"method": "adaptive", "resolution": ["full", "half", "quarter", "adaptive"]},
//                           {"method": "adaptive", "stepping": ["mask", "mask_skip"]},
//                           {"method": "narrow_range"}] }],
//   "solver_map": { "scene": "path.json", "dt": [0.002, 0.004], "iterations": [1, 2, 4],
//                   "control_pressure": [..], "time": 0.5 } }   (or an array of such maps)
//
// Methods: every method of render/registry.h (aquaform help lists them): reference, adaptive,
// uniform (the SPH surface renderer); brute, abuffer, sbuffer (metaballs); bilateral,
// curvature_flow, narrow_range (screen-space filters).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "render/impostor_view.h"
#include "render/renderer.h"
#include "study/study_solver_map.h"

namespace aquaform::study {

enum class StudyFamily { surface, metaball, screen_space };
/// The study family of a render method's family (MethodEntry::family); an error naming the
/// family and the known ones for any other (a method registered without a study family).
Result<StudyFamily> study_family(const std::string& family);

/// One expanded method configuration.
struct StudyMethod {
    std::string method;  ///< as in the spec
    StudyFamily family = StudyFamily::surface;
    std::string visual = "gradient";      ///< metaballs
    float size = 1.0f;                    ///< metaballs: range in particle spacings
    uint32_t recursion = 1;               ///< metaballs, real visual
    uint32_t bisection = 3;               ///< metaballs
    std::string resolution = "adaptive";  ///< adaptive method: full, half, quarter or adaptive
    /// Adaptive method, Wu et al. Fig. 5: "all" mechanisms (default), "mask" (the binary density
    /// grid alone), "mask_skip" (with the skip to D_agg) or "mask_wu_skip" (with Wu et al.'s skip
    /// after maxSkipCounts, which can jump over splashes); but "all" at full resolution.
    std::string stepping = "all";
    /// SPH surface methods: the field drawn, "anisotropic" (the default) or "isotropic" (label
    /// suffix " iso"); each is measured against the reference of its own field.
    std::string surface = "anisotropic";
    /// What the study renders with: the registry's settings of this configuration
    /// (Registry::from_json), with a fixed resolution as adaptive_resolution off and, for
    /// metaballs, the case's list memory.
    MethodSettings settings;

    /// "sbuffer real x2 r4 b3", "adaptive half", "uniform iso": unique within a case.
    std::string label() const;
    /// How much smaller than the case's resolution the method renders (half: 2, quarter: 4).
    uint32_t resolution_divisor() const;
};

struct StudyCamera {
    std::string preset = "front";  ///< front, far, closeup or custom
    ViewCamera custom;
};

struct StudyCase {
    std::string name;
    std::string scene = "dam_break";  ///< "dam_break" or a scene file path (resolved)
    /// Particle counts: the generated dam break's (default 4096), or a scene file scaled to each
    /// (scaled_scene in bench/bench_frames.h; empty: the file's own particles).
    std::vector<uint32_t> particles;
    std::optional<double> time_s;  ///< empty: half_tank
    StudyCamera camera;
    std::vector<std::pair<uint32_t, uint32_t>> resolutions;
    std::vector<StudyMethod> methods;
    std::string note;                   ///< what the case shows, for the report
    uint32_t list_bytes_per_pixel = 0;  ///< metaball list memory; 0: the renderer's default
};

struct StudySpec {
    std::string name;  ///< names the default output folder: letters, digits, '_', '-', '.' (core/file_name.h)
    uint32_t repeats = 2;
    std::vector<StudyCase> cases;
    std::vector<SolverMapSpec> solver_maps;  ///< "solver_map": one object or an array of them
    /// What the rows depend on: the spec as parsed, the scene files' texts and --particles. Its
    /// hash (spec_hash) marks every row written, so a rerun resumes only the rows of this spec.
    std::string identity;
};

/// 16 hex digits of a hash of spec.identity.
std::string spec_hash(const StudySpec& spec);

/// The identity of a (case, particle count) frame and of one measurement on it, as the CSV
/// files key their rows: "curtain/1500", "curtain/1500/96x64/adaptive mask" ("scene" for a
/// scene file's own count). Rows come in the order of study_cell_keys.
std::string study_frame_key(const StudyCase& c, std::optional<uint32_t> particles);
std::string study_cell_key(const std::string& frame_key, uint32_t width, uint32_t height, const std::string& label);
std::vector<std::string> study_cell_keys(const StudySpec& spec);
/// The particle counts a case's frames are made with (empty: a scene file's own).
std::vector<std::optional<uint32_t>> study_frame_counts(const StudyCase& c);

/// What the GPU work would find only later: every case's scene file loads and scales to each
/// count, every solver map's scene and settings hold (check_solver_map). The first problem,
/// naming the case or map and the fix.
Result<bool> check_study_scenes(const StudySpec& spec);

/// `study --particles N`: every case at about N particles: a generated dam break's list becomes
/// {N}, a scene file is scaled to it (with_particle_count). Refuses a scene that cannot be.
Result<bool> set_particle_count(StudySpec& spec, uint64_t particles);

/// Reads and checks a spec file; errors name the file, the key and the fix.
Result<StudySpec> load_study_spec(const std::filesystem::path& path);
Result<StudySpec> parse_study_spec(const std::string& text, const std::string& origin,
                                   const std::filesystem::path& base_dir);

}  // namespace aquaform::study
