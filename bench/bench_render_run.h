// `aquaform bench render`'s run (bench/bench_render.h holds its configurations and targets): each
// benchmark frame simulated, its reference and every configuration drawn, the tables printed, the
// targets judged, and (with --compare-surfaces) the anisotropic surface against the isotropic one.
// The command parses the flags, and writes bench_render.json and the sweeps' charts.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_render.h"
#include "core/result.h"
#include "pictures/svg_chart.h"
#include "render/picture_size.h"
#include "sim/scene.h"

namespace aquaform::study {

/// What `bench render` measures.
struct BenchRenderPlan {
    std::vector<const BenchFrame*> frames;
    std::vector<Scene> scenes;               ///< one per frame, loaded before any work
    std::optional<uint32_t> frame_override;  ///< --frame K instead of each frame's event
    std::vector<const BenchConfig*> configs;
    SurfaceSettings base;           ///< the render parameters every configuration shares
    bool compare_surfaces = false;  ///< each frame with both fields, each against its own reference
    PictureSize size;
    uint32_t repeats = 2;
    long requested_particles = 0;  ///< --particles (the GPU target applies to 1M)
    bool mask_sweep = false, blend_sweep = false;
    uint32_t march_lanes = 0;  ///< 0: the device's default
};

/// What it measured, for bench_render.json, the summary and the charts.
struct BenchRenderResult {
    nlohmann::json frames = nlohmann::json::array();
    std::vector<SweepPoint> mask_points, blend_points;
    /// Each measured frame ("calm iso") with its targets' lines.
    std::vector<std::pair<std::string, std::vector<std::string>>> summary;
    bool unstable = false;  ///< a simulation left physics; the frames before it are kept
};

/// Measures the plan's frames in order; Ctrl-C stops after the frame being measured.
BenchRenderResult run_bench_render(gpu::Context& ctx, const BenchRenderPlan& plan);

/// The suffixes of the sweeps' charts (beside the JSON: STEM + suffix) that sweep_charts writes
/// for these sweeps, known before any work so that the files are checked first.
std::vector<std::string> sweep_chart_suffixes(bool mask_sweep, bool blend_sweep);
/// The sweeps' charts, each with the suffix of its file beside bench_render.json.
std::vector<std::pair<std::string, Chart>> sweep_charts(const BenchRenderResult& result, const BenchRenderPlan& plan);
/// Writes `doc` (bench_render.json) to `out_path` and the sweeps' charts beside it, saying each
/// file's name; the first error.
Result<bool> write_bench_render_files(const std::filesystem::path& out_path, const nlohmann::json& doc,
                                      const BenchRenderResult& result, const BenchRenderPlan& plan);

}  // namespace aquaform::study
