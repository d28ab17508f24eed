// `aquaform bench frame`'s measurement: what a displayed frame costs at a chosen particle count
// (issue 36): the solver's frame at its time-step rule, the adaptive reconstruction and its
// composition at a chosen resolution, in one submission as `run` records them, timed over whole
// frames after a warm-up. The real-time factor is simulated seconds per wall second. (The frames
// that `bench render` draws are bench/bench_frames.h: a different thing.)
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_render.h"
#include "render/picture_size.h"

namespace aquaform::gpu {
class Context;
struct DeviceInfo;
}  // namespace aquaform::gpu

namespace aquaform::study {

/// What `bench frame` measures on: the benchmarks' dam break (study::bench_scene).
inline constexpr const char* kFrameBenchScene = "bench_dam_break";

/// The display issue 36's real-time targets are set for (bench frame's default picture).
inline constexpr PictureSize kTargetDisplay{1920, 1080};

struct FrameBenchOptions {
    uint32_t width = kTargetDisplay.width, height = kTargetDisplay.height;
    uint32_t warmup = 10;     ///< frames before timing (the column starts to fall, the rule's steps rise)
    uint32_t frames = 30;     ///< frames timed
    uint32_t iterations = 4;  ///< constraint iterations per step (the shipped scenes')
};

struct FrameBenchRecord {
    uint32_t requested = 0;  ///< the size asked for (bench_scene holds a little fewer)
    uint32_t particles = 0;
    uint32_t width = 0, height = 0;
    uint32_t iterations = 0;
    uint32_t warmup_frames = 0;
    std::vector<uint32_t> steps;   ///< the time-step rule's steps of each timed frame
    double steps_per_frame = 0.0;  ///< their mean
    double sim_seconds = 0.0;      ///< simulated time the timed frames advanced
    double wall_seconds = 0.0;     ///< wall time they took, submission to result
    double sim_s_per_frame = 0.0;
    double wall_ms_per_frame = 0.0;
    double frames_per_s = 0.0;
    /// GPU ms per frame: the solver's passes (steps, statistics, the frame grid the renderer
    /// reads), the reconstruction (every render pass but the composition) and the composition.
    double gpu_solver_ms = 0.0, gpu_reconstruction_ms = 0.0, gpu_compose_ms = 0.0;
    std::map<std::string, double> ms_per_pass;  ///< GPU ms per frame of every pass
    /// Simulated seconds per wall second: 1 is real time.
    double real_time_factor = 0.0;
};

/// The render pass that composes the picture; every other render_ pass is reconstruction.
inline constexpr const char* kComposePass = "render_compose";

/// Times frames of bench_scene(target_particles) on `ctx`; stops early (with the frames done)
/// when Ctrl-C is pressed. A scene too large for the device is a Failure of kind input.
FrameBenchRecord measure_frame(gpu::Context& ctx, uint32_t target_particles, const FrameBenchOptions& options);

nlohmann::json to_json(const FrameBenchRecord& record);

/// The H200 targets (issue 36): real-time factor >= 1 at 500k particles, >= 0.8 at 1M, both at
/// 1920x1080 or more. Judged on a discrete GPU only; elsewhere "not judged" with the reason.
struct FrameTarget {
    uint32_t particles;
    double min_real_time_factor;
    const char* key;
};
inline constexpr FrameTarget kFrameTargets[] = {{500000, 1.0, "realtime_500k"}, {1000000, 0.8, "realtime_1m"}};
Verdict frame_target(const FrameTarget& target, const std::vector<FrameBenchRecord>& records,
                     const gpu::DeviceInfo& device);

struct FrameBenchResult {
    nlohmann::json records = nlohmann::json::array();   ///< a record per size (to_json)
    nlohmann::json targets = nlohmann::json::object();  ///< each kFrameTargets verdict, by key
};
/// measure_frame at each size, a table row printed as each is measured, then the targets' verdicts;
/// nullopt when Ctrl-C stopped it (a size cut short is not a measurement).
std::optional<FrameBenchResult> run_frame_bench(gpu::Context& ctx, const std::vector<uint32_t>& sizes,
                                                const FrameBenchOptions& options);

}  // namespace aquaform::study
