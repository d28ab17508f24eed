// The measurements of `aquaform study`: one row per (case, particles, resolution, method), each
// rendered on the same solver frame and measured against the reference of the field it draws:
// the SPH methods and the screen-space filters against the exhaustive SPH reference, the
// metaball methods against a fine S-buffer march of their own field (whose lists are exact on
// primary rays, so it is the brute-force surface at a fraction of the cost).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "study/study_spec.h"

namespace aquaform {
namespace gpu {
class Context;
}
}  // namespace aquaform

namespace aquaform::study {

struct StudyRow {
    std::string case_name, scene, method;
    std::string cell;  ///< study_cell_key (study_spec.h), or the frame's key for a frame that failed
    StudyMethod config;
    uint32_t width = 0, height = 0, particles = 0;
    double ms_total = 0.0;
    std::map<std::string, double> ms_per_pass;
    // Against the reference; empty when there is none (the reference itself, a failed run).
    std::optional<double> depth_err_mean, depth_err_p95, normal_err_deg_mean, coverage_mismatch, psnr_db;
    /// Smoothness (render/surface_metrics.h, surface_roughness): rms normal deviation [deg] over the
    /// regions the reference shows flat; the reference row has its own (the SPH field's bumps).
    std::optional<double> roughness_deg;
    double overflow_mib = 0.0;  ///< list memory the frame needed, when the lists overflowed
    std::string status = "ok";  ///< ok, overflow, or "failed: why"
    std::string image;          ///< the shaded frame, relative to the output directory
    std::string steps_image;    ///< SPH methods: march steps per pixel (Wu et al. Fig. 5)
    // What the frame cost, counted rather than timed: the same on every device.
    uint64_t rays = 0;
    std::optional<double> steps_per_ray, bisection_per_ray;  ///< SPH methods (render/renderer.h)
    double evals_per_ray = 0.0;                              ///< density or field evaluations per ray
    std::optional<double> leaps_per_ray;                     ///< SPH methods with the mask: empty cells leapt per ray
    std::optional<double> list_entries_per_pixel, list_bytes_per_pixel;  ///< A-/S-buffer metaballs
    std::optional<double> particle_visits_per_pixel;                     ///< metaballs
    double memory_bytes_per_pixel = 0.0;                                 ///< the renderer's GPU memory over the pixels
    /// Merged shards: the device of a row measured on another than study.md's header names (not in the CSV).
    std::string device;
};

/// The camera of a case: the front view of the domain, twice as far ("far"), or "closeup": the
/// eye on the boundary of the first fluid block, looking at its centre.
ViewCamera study_camera(const StudyCamera& spec, const Scene& scene, float aspect);

/// Resuming and stopping a study: a cell `done` accepts (study_cell_key) is skipped, and a frame
/// whose cells are all done is not simulated; `measured` gets each row as soon as it is measured
/// (false stops the study); Ctrl-C (core/interrupt.h) stops it after the current row.
struct StudyHooks {
    std::function<bool(const std::string& cell)> done;
    std::function<bool(const StudyRow& row)> measured;
};

/// Runs every case of the spec, printing progress to stderr; rows come in spec order. With an
/// `images_dir`, every method's shaded frame is written there as PNG. Returns the rows measured.
std::vector<StudyRow> run_study_cases(gpu::Context& ctx, const StudySpec& spec,
                                      const std::filesystem::path& images_dir = {}, const StudyHooks& hooks = {});
/// study.md: a table per case, the papers' table shapes (Karpati Table 1 as frames per second,
/// Wu Table 1 as time and error per resolution, Wu Table 2 as time per pass), and the targets.
/// `device`: the name of the device the times come from (study.md says which conclusions depend on it).
Result<bool> write_study_markdown(const std::filesystem::path& path, const StudySpec& spec,
                                  const std::vector<StudyRow>& rows, const std::vector<std::string>& target_lines,
                                  const std::string& device = "");
/// The targets, evaluated on whatever rows the spec produced (a line each; "not measured"
/// when the spec lacks the rows a target needs).
std::vector<std::string> study_targets(const std::vector<StudyRow>& rows);

}  // namespace aquaform::study
