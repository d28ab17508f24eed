#include "runner/frame_pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "control/control_driver.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "render/wireframe.h"
#include "sim/blowup.h"
#include "sim/pbf_solver.h"

namespace aquaform::runner {

/// A frame whose device work has completed and whose files are not written yet.
struct FramePipeline::FinishedFrame {
    uint32_t index = 0;
    session::FrameReport report;
    std::optional<Image> image;
    FrameCapture capture;  ///< what its exports need
    std::string note;      ///< the progress line's figures
};

namespace {

std::unique_ptr<Renderer> make_surface(gpu::Context& ctx, session::SimulationSession& sim, const PictureOptions& p) {
    if (p.kind != PictureOptions::Kind::surface) return nullptr;
    return render_registry().create(ctx, sim.scene().particle_domain(), p.size.width, p.size.height,
                                    sim.solver().capacity(), p.method);
}

/// The progress line's figures: the density error, the speed, the steps; the shape's IoU and the
/// mesh's triangles where there are.
std::string progress_note(const session::FrameReport& report, const FrameCapture& capture, bool shape) {
    const FrameStats& stats = report.stats;
    char note[128];
    int used = std::snprintf(note, sizeof note, "density err %.2f%%  max speed %.2f m/s  %u steps",
                             100.0 * stats.mean_density_error, stats.max_speed, stats.substeps);
    if (shape) used += std::snprintf(note + used, sizeof note - used, "  shape IoU %.2f", report.shape->iou);
    if (capture.mesh)
        std::snprintf(note + used, sizeof note - used, "  mesh %zu triangles", capture.mesh->triangles.size());
    return note;
}

SurfaceSettings field_of(const MethodSettings& method) {
    const SurfaceSettings* field = method.get<SurfaceSettings>();
    return field ? *field : SurfaceSettings{};
}

}  // namespace

FramePipeline::FramePipeline(gpu::Context& ctx, session::SimulationSession& sim, const std::filesystem::path& out_dir,
                             const FrameExportOptions& exports, PictureOptions picture)
    : ctx_(ctx),
      sim_(sim),
      out_dir_(out_dir),
      picture_(std::move(picture)),
      preview_(picture_.kind == PictureOptions::Kind::preview
                   ? std::make_unique<ImpostorView>(ctx, picture_.size.width, picture_.size.height)
                   : nullptr),
      surface_(make_surface(ctx, sim, picture_)),
      exports_(out_dir, exports),
      obstacles_(out_dir, sim.scene(), exports.up),
      timer_(ctx),
      capturer_(ctx, exports_, sim.solver(), sim.scene().particle_domain(), field_of(picture_.method)),
      readback_(ctx),
      camera_(scene_camera(sim.scene(), float(picture_.size.width) / float(std::max(1u, picture_.size.height)))) {
    const Scene& scene = sim.scene();
    style_.radius = 0.5f * scene.particle_spacing;
    style_.speed_for_full_color =
        std::max(1.0f, 0.5f * std::sqrt(2.0f * 9.81f * (scene.domain.max.y - scene.domain.min.y)));
    if (surface_)  // the impostor view has its own read-back buffer
        color_ = &readback_.add("run.color", VkDeviceSize(picture_.size.width) * picture_.size.height * 4,
                                gpu::MemoryUse::host);
}

FramePipeline::~FramePipeline() = default;

std::string FramePipeline::renderer_memory_line() const {
    if (!surface_) return "";
    uint64_t bytes = 0;
    for (const auto& b : surface_->memory_report()) bytes += b.bytes;
    char line[160];
    std::snprintf(line, sizeof line, "  renderer (%s, %ux%u)    %.3f MiB", picture_.method.method().c_str(),
                  picture_.size.width, picture_.size.height, double(bytes) / (1024.0 * 1024.0));
    return line;
}

void FramePipeline::record_picture(VkCommandBuffer cmd) {
    PbfSolver& solver = sim_.solver();
    const Scene& scene = sim_.scene();
    const FrameInput frame = sim_.frame_input();
    if (preview_)
        preview_->record(cmd, solver.positions(), solver.velocities(), solver.particle_count(), camera_, style_,
                         scene.domain, scene.static_boxes);
    if (surface_) {
        surface_->record(cmd, frame, camera_, nullptr);
        gpu::record_download(ctx_, cmd, surface_->color_buffer(), *color_, color_->size);
    }
    capturer_.record(cmd, recording_, frame, &timer_);
}

FramePipeline::FinishedFrame FramePipeline::collect(uint32_t frame, gpu::Submission submitted) {
    FinishedFrame f{frame, sim_.finish_frame(submitted, &timer_), std::nullopt, {}, {}};
    if (preview_) f.image = preview_->image();
    if (color_) {
        const auto* bytes = static_cast<const uint8_t*>(color_->mapped);
        f.image = Image{picture_.size.width, picture_.size.height, std::vector<uint8_t>(bytes, bytes + color_->size)};
    }
    const control::ControlDriver* driver = sim_.control();
    if (f.image && driver && picture_.wireframe)
        for (const geometry::Mesh& mesh : driver->active_meshes())
            draw_wireframe(*f.image, mesh.vertices, mesh.faces, camera_);
    f.capture = capturer_.collect(frame, timer_, f.report.stats);
    if (exports_.needs(FrameData::whitewater, frame)) f.capture.whitewater = sim_.whitewater_snapshot();
    f.note = progress_note(f.report, f.capture, f.report.shape && !driver->active().empty());
    return f;
}

bool FramePipeline::write(const FinishedFrame& f, RunFiles& files, RunTotals& totals) {
    const FrameStats& stats = f.report.stats;
    auto failed = [](const std::string& error) {
        std::fprintf(stderr, "\naquaform run: %s\n", error.c_str());
        return false;
    };
    char name[32];
    if (f.image) {
        std::snprintf(name, sizeof name, "frame_%04u.png", f.index);
        if (auto written = write_png(out_dir_ / name, *f.image); !written) return failed(written.error());
    }
    if (auto written = exports_.write(f.index, stats.time_s, f.capture); !written) return failed(written.error());
    if (auto written = obstacles_.write(f.index, stats.time_s); !written) return failed(written.error());
    if (f.capture.volume && !said_iso_) {
        // The level the surface is drawn at: Blender shows no grid metadata (aquaform_iso).
        said_iso_ = true;
        std::printf(
            "\ndensity volumes: the surface is the level %.6g (the grid's aquaform_iso; Blender: the "
            "threshold of a Volume to Mesh modifier)\n",
            double(f.capture.volume->iso));
    }
    if (auto written = files.write_probes(f.report.probes); !written) return failed(written.error());
    // The row last: stats.csv lists the frames whose files are all written.
    if (auto written = files.write_frame_stats(f.index, stats, f.report.shape ? &*f.report.shape : nullptr); !written)
        return failed(written.error());
    ++totals.frames;
    totals.simulated_s = stats.time_s;
    totals.steps += stats.substeps;
    totals.capped_frames += stats.speed_capped;
    return true;
}

RunTotals FramePipeline::run(uint32_t frames, RunFiles& files) {
    const Scene& scene = sim_.scene();
    RunTotals totals;
    ProgressBar progress("simulating " + scene.name, frames);
    // Writes a finished frame's files and judges its physics; false ends the run.
    auto finish = [&](const FinishedFrame& f) {
        if (!write(f, files, totals)) return false;
        progress.update(totals.frames, f.note);
        if (const std::string verdict = blowup_verdict(f.report.stats, scene); !verdict.empty()) {
            progress.finish();
            std::fprintf(stderr, "aquaform run: %s. The frames up to it are in %s\n", verdict.c_str(),
                         out_dir_.string().c_str());
            return false;
        }
        return true;
    };
    const auto record = [this](VkCommandBuffer cmd) { record_picture(cmd); };
    // Frame N's files are written while frame N+1 runs on the device. The device waits only
    // from the end of a frame to the submission of the next (its statistics read, the next
    // frame's steps chosen and recorded): that host time is measured and said at the end.
    std::optional<FinishedFrame> finished;
    std::optional<std::chrono::steady_clock::time_point> device_idle_since;
    double host_gap_s = 0.0;
    uint32_t host_gaps = 0;
    for (uint32_t frame = 0;; ++frame) {
        const bool more = frame < frames && !interrupted();
        gpu::Submission next;
        try {
            if (more) {
                recording_ = frame;
                // Frame 0 is the state at t = 0 (the first picture and exports); frame f is f frames on.
                next = frame == 0 ? sim_.submit_initial_state(&timer_, record) : sim_.submit_frame(&timer_, record);
                if (device_idle_since) {
                    host_gap_s +=
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - *device_idle_since).count();
                    ++host_gaps;
                }
            }
        } catch (...) {
            if (finished) finish(*finished);  // the frame before a failure is still written
            throw;
        }
        const bool written = !finished || finish(*finished);
        finished.reset();
        if (!written) totals.failed = true;
        if (!more) break;
        ctx_.wait(next);  // when the run ends here, the next frame is dropped, not left running
        if (!written) break;
        device_idle_since = std::chrono::steady_clock::now();
        finished = collect(frame, next);
    }
    progress.finish();
    if (host_gaps > 0) totals.host_gap_ms = 1000.0 * host_gap_s / host_gaps;
    return totals;
}

}  // namespace aquaform::runner
