// `aquaform run`'s frame pipeline: a session's frames simulated, drawn and exported. Each frame's
// picture is recorded in the frame's own submission and copied into host memory there, and a
// frame's files (its PNG, its exports, its stats.csv row) are written while the next frame runs
// on the device.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "core/camera.h"
#include "exports/frame_capture.h"
#include "exports/frame_exports.h"
#include "exports/obstacle_export.h"
#include "gpu/buffer.h"
#include "gpu/timer.h"
#include "render/impostor_view.h"
#include "render/picture_size.h"
#include "render/registry.h"
#include "runner/run_files.h"
#include "session/simulation_session.h"

namespace aquaform::runner {

/// How each frame is drawn.
struct PictureOptions {
    enum class Kind { none, preview, surface };
    Kind kind = Kind::surface;  ///< none: no PNG; preview: quick sphere impostors; surface: `method`
    PictureSize size;
    MethodSettings method;   ///< the method of the surface (its field also makes the volumes and meshes)
    bool wireframe = false;  ///< the active control meshes drawn over each picture
};

/// What a run did, for its closing lines.
struct RunTotals {
    uint32_t frames = 0;  ///< frames whose files are all written
    double simulated_s = 0.0;
    uint64_t steps = 0;          ///< the time-step rule's steps
    uint64_t capped_frames = 0;  ///< frames the speed cap bound in
    double host_gap_ms = 0.0;    ///< mean host time a frame between the end of one and the next's submission
    bool failed = false;         ///< a file not written or the fluid left physics (said on stderr)
};

class FramePipeline {
public:
    /// Makes the renderer first: a picture the device cannot hold is refused before any work.
    FramePipeline(gpu::Context& ctx, session::SimulationSession& sim, const std::filesystem::path& out_dir,
                  const FrameExportOptions& exports, PictureOptions picture);
    ~FramePipeline();

    /// The memory of the renderer and of the exports' captures, a line each (empty: none).
    std::string renderer_memory_line() const;
    std::string capture_memory_line() const { return capturer_.memory_line(); }

    /// Frames 0 .. frames - 1 (frame 0 is the state at t = 0), fewer after Ctrl-C or a failure,
    /// each written with `files` last (stats.csv lists the frames whose files are all written).
    RunTotals run(uint32_t frames, RunFiles& files);

private:
    struct FinishedFrame;
    void record_picture(VkCommandBuffer cmd);
    FinishedFrame collect(uint32_t frame, gpu::Submission submitted);
    bool write(const FinishedFrame& f, RunFiles& files, RunTotals& totals);

    gpu::Context& ctx_;
    session::SimulationSession& sim_;
    std::filesystem::path out_dir_;
    PictureOptions picture_;
    std::unique_ptr<ImpostorView> preview_;
    std::unique_ptr<Renderer> surface_;
    FrameExports exports_;
    ObstacleExports obstacles_;  ///< the solids as they stand at each frame
    gpu::GpuTimer timer_;
    FrameCapturer capturer_;
    gpu::BufferSet readback_;
    const gpu::Buffer* color_ = nullptr;  ///< the surface's picture in host memory
    ViewCamera camera_;
    ImpostorStyle style_;
    uint32_t recording_ = 0;  ///< the frame being recorded
    bool said_iso_ = false;
};

}  // namespace aquaform::runner
