// The viewer without a window (`aquaform view --headless`): the viewer's own worker (viewer/
// view_worker.h) plays the scene frame by frame, simulating and rendering as it does behind a
// window, with nothing presented, so that a GPU machine with no display can take the viewer's
// frame rate and real-time factor. Each frame is asked for and waited for (the worker's lockstep,
// as a scripted window does), so every frame is one simulation frame and one picture.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "session/simulation_session.h"
#include "viewer/viewer.h"

namespace aquaform::gpu {
class Context;
}

namespace aquaform::viewer {

/// One frame of a headless session.
struct HeadlessFrame {
    double wall_ms = 0.0;                             ///< from asking the worker for the frame to its picture
    uint32_t steps = 0;                               ///< the time-step rule's steps of its simulation frame
    double sim_s = 0.0;                               ///< simulated time it advanced
    double gpu_solver_ms = 0.0, gpu_render_ms = 0.0;  ///< the worker's timers: simulation, picture
};

struct HeadlessSummary {
    std::string scene, device, device_type;  ///< what was played where (run_headless_printed names them)
    std::vector<HeadlessFrame> frames;
    uint32_t particles = 0;
    uint32_t width = 0, height = 0;
    std::string method;
    double wall_seconds = 0.0, sim_seconds = 0.0;  ///< over every frame
    std::string fatal;                             ///< the worker's error, when it stopped on one
    std::string blowup;  ///< the verdict of the frame that left physics (blowup_verdict), where it stopped
    double frames_per_s() const { return wall_seconds > 0.0 ? double(frames.size()) / wall_seconds : 0.0; }
    /// Simulated seconds per wall second: 1 is real time.
    double real_time_factor() const { return wall_seconds > 0.0 ? sim_seconds / wall_seconds : 0.0; }
    /// Means over the frames played (0 with none).
    double mean_steps() const;
    double mean_gpu_solver_ms() const;
    double mean_gpu_render_ms() const;
};

/// `view --headless --out FILE`'s document: the scene and the device, every frame, the means and
/// the real-time factor.
nlohmann::json to_json(const HeadlessSummary& run);

/// Plays `frames` frames of `plan` at `width` x `height` (options.picture_scale applies) with
/// options' method and surface settings; stops early on Ctrl-C or a worker error.
/// `on_frame` (may be empty) is called after each frame, for progress lines.
HeadlessSummary run_headless(gpu::Context& ctx, session::SessionPlan plan, const ViewerOptions& options, uint32_t width,
                             uint32_t height, uint32_t frames,
                             const std::function<void(uint32_t, const HeadlessFrame&)>& on_frame = {});
/// run_headless with its table printed: a line naming `scene_name` and the device, a line per
/// frame, and the summary (frames a second, GPU time, the real-time factor).
HeadlessSummary run_headless_printed(gpu::Context& ctx, session::SessionPlan plan, const ViewerOptions& options,
                                     uint32_t width, uint32_t height, const std::string& scene_name);

}  // namespace aquaform::viewer
