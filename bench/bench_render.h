// `aquaform bench render`'s configurations and targets: the reference, uniform (Xiao et al.),
// adaptive (Wu et al.) and each adaptive mechanism alone on one dam-break frame, and the verdicts
// on the adaptive method's targets and on what the anisotropic surface keeps of the isotropic
// one's droplets and sheets (the command renders, prints and writes bench_render.json).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_frames.h"
#include "bench/render_measure.h"
#include "bench/surface_checks.h"
#include "bench/verdict.h"
#include "core/result.h"
#include "gpu/context.h"
#include "pictures/svg_chart.h"
#include "render/surface_metrics.h"
#include "render/surface_settings.h"

namespace aquaform::study {

/// One configuration: a method, and for the adaptive method which mechanisms are on.
struct BenchConfig {
    const char* label;
    SurfaceMethod method;
    bool mask, skip, adaptive_res, blend;
    const char* what;
    bool wu_skip = false;  ///< Wu et al.'s skip after maxSkipCounts instead of the exact one
};

/// Every configuration, in the table's order (the reference is rendered first and always: every
/// metric is against it).
const std::vector<BenchConfig>& bench_configs();
/// What --configs is when not given: every configuration, or the four --quick renders.
std::string default_config_list(bool quick);
const BenchConfig* find_config(const std::string& label);
/// "reference, uniform, adaptive, ...": what --configs accepts.
std::string known_labels();
/// --configs a,b,c in the table's order; the reference is always rendered.
Result<std::vector<const BenchConfig*>> parse_configs(const std::string& text);
/// `base` with the configuration's method and mechanisms, as that method's registry settings.
MethodSettings settings_for(const BenchConfig& c, SurfaceSettings base);
/// `base` drawn by the exhaustive reference.
MethodSettings reference_settings(SurfaceSettings base);

struct Measured {
    const BenchConfig* config;
    RenderMeasurement m;  ///< with the settings rendered
    SurfaceComparison cmp;
};

/// Mask + skip march steps per ray against uniform's (target <= 50 % at equal or lower depth
/// error: Wu et al. section 5 report about 50 %). Steps are the march's density evaluations;
/// the bisection that follows a hit is the same for both and is reported beside them.
Verdict steps_target(const std::vector<Measured>& results);
/// Adaptive resolution: march + upsample against the full-resolution march, PSNR against it.
Verdict resolution_target(const std::vector<Measured>& results);
/// A sweep of two of the adaptive method's parameters (`bench render --mask-sweep`,
/// `--blend-sweep`): the configuration it draws and the pairs it sets.
struct Sweep {
    const char* name;    ///< "mask", "blend"
    const char* config;  ///< the bench configuration drawn at each pair
    const char* a_name;  ///< the parameters' names in the table
    const char* b_name;
    std::vector<std::pair<float, float>> pairs;
    /// `base` with the pair set.
    SurfaceSettings (*apply)(SurfaceSettings base, float a, float b);
};
/// Wu et al.'s mask weights (a, b) of eq. 5 (their count convolution): b <= a <= 1, from the
/// exact bound (1, 1) down to where lone droplets lose their cells (b^3 below the marking
/// threshold, 0.72 counts at the default iso).
const Sweep& mask_sweep();
/// The normal blending's A (per particle radius, eq. 12) and B (per pixel of particle size,
/// eq. 13), from the screen-space normal alone (A = 0) to the object-space one (A large).
const Sweep& blend_sweep();

/// One sweep point on one frame, against the reference.
struct SweepPoint {
    std::string frame;
    float a = 1.0f, b = 1.0f;
    double steps_per_ray = 0.0;
    double uniform_steps_per_ray = 0.0;
    SurfaceComparison cmp;
};
/// The mask sweep's charts: march steps per ray (as a fraction of uniform's on the same frame)
/// against the mean depth error, and against the coverage mismatch; a series per frame.
Chart mask_sweep_depth_chart(const std::vector<SweepPoint>& points);
Chart mask_sweep_coverage_chart(const std::vector<SweepPoint>& points);
/// The blend sweep's chart: roughness against the normal error (vs the field's gradient).
Chart blend_sweep_chart(const std::vector<SweepPoint>& points);

/// One picture's checks (bench/surface_checks.h) on a frame that has them (BenchFrame::check).
struct PictureChecks {
    std::string label;  ///< "reference" or the configuration's
    std::optional<DropletCensus> droplets;
    std::optional<SheetCoverage> sheet;
};
/// What a frame's pictures are checked for: the lone droplets' centres (with the reach of the
/// census: the kernel's support r), or the sheet and the camera that sees it.
struct CheckSubjects {
    FrameCheck check = FrameCheck::none;
    std::vector<glm::vec3> droplets;
    float reach = 0.0f;
    Sheet sheet;
    ViewCamera camera;
};
/// Reads the droplets' centres back from `solver` on a droplet frame.
CheckSubjects check_subjects(const BenchFrame& frame, const Scene& scene, PbfSolver& solver, const ViewCamera& camera,
                             float reach);
PictureChecks check_picture(const std::string& label, const SurfaceFrame& frame, const CheckSubjects& subjects);
/// A picture's checks for its record, against the reference's of the same surface.
nlohmann::json picture_checks_json(const PictureChecks& p, const PictureChecks& reference);
/// The checks of every picture of one surface, the reference's first, as a table.
void print_picture_checks(const std::vector<PictureChecks>& pictures);

/// The curtain's droplets with the anisotropic surface against the isotropic one, picture by
/// picture (the reference with the reference, each configuration with itself): all present,
/// none lost or fattened (each projected area within 10 % of the isotropic one).
Verdict droplets_target(const std::vector<PictureChecks>& isotropic, const std::vector<PictureChecks>& anisotropic);
/// The one-particle-thick sheet: the anisotropic surface covers >= 99 % of its area in every
/// picture (the isotropic one may tear: reported beside it).
Verdict sheet_target(const std::vector<PictureChecks>& isotropic, const std::vector<PictureChecks>& anisotropic);

/// Real time on a GPU (issue 36): the adaptive reconstruction of 1M particles at 1920x1080 within
/// 4 ms, its depth sprites within 0.6 ms and its march within 2 ms.
/// `requested`: --particles (the lattice holds a little fewer: 986,078 for 1,000,000).
Verdict gpu_target(const std::vector<Measured>& results, const gpu::DeviceInfo& device, long requested,
                   uint32_t particles, uint32_t width, uint32_t height);

}  // namespace aquaform::study
