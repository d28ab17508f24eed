// The files of `aquaform run` besides its frames and exports: run.json (what a tool needs to rebuild
// the run's world), stats.csv (every frame), front.csv and front.svg (dam breaks), whitewater.svg
// (with whitewater), flow.svg (with emitters or sinks), and the rule
// for a folder that holds an earlier run.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/file_write.h"
#include "runner/probe_files.h"
#include "session/simulation_session.h"
#include "sim/frame_stats.h"
#include "sim/scene.h"

namespace aquaform::runner {

using session::ShapeColumns;

/// run.json: what a tool needs to rebuild the run's world around its exports (scripts/
/// blender_scene.py): the scene, its tank (domain, in the simulation's y-up axes), the exports'
/// up axis, the frame time and the particle count.
Result<bool> write_run_description(const std::filesystem::path& dir, const Scene& scene, const char* up,
                                   uint32_t particles);
inline constexpr const char* kRunDescriptionName = "run.json";

/// stats.csv (every frame) and front.csv (dam-break scenes, those with column_width).
class RunFiles {
public:
    RunFiles(const std::filesystem::path& dir, const Scene& scene);
    bool ok() const { return error_.empty(); }
    const std::string& error() const { return error_; }
    /// `shape` adds the shape columns (give it every frame or never).
    /// The frame's row reaches the files whole or not at all (a full disk: the error says so);
    /// frame 0's waits for the first stepped frame (its passes name the columns) or finish().
    Result<bool> write_frame_stats(uint32_t frame, const FrameStats& stats, const ShapeColumns* shape = nullptr);
    /// The frame's probe readings (probes.csv; nothing without probes).
    Result<bool> write_probes(const ProbeFrame& frame) { return probes_.write_frame(frame); }
    /// The probes' charts (probe_*.svg); with whitewater, whitewater.svg (each kind alive over
    /// time, and the pool's drops); with emitters or sinks, flow.svg (the particles alive, emitted and
    /// removed over time). Dam-break scenes: writes front.svg (the run against Martin & Moyce 1952) and, for a
    /// single column of height 2a (their n^2 = 2), prints how far the front is from theirs.
    /// Also warns when a control shape pulled for kFillGraceSeconds and never reached an IoU of
    /// kNeverFilledIou with the fluid.
    Result<bool> finish(const Scene& scene);

    static constexpr double kFillGraceSeconds = 1.0;
    static constexpr double kNeverFilledIou = 0.1;

private:
    void warn_if_never_filled() const;
    std::filesystem::path dir_;
    AppendedFile stats_;
    AppendedFile front_;
    ProbeFiles probes_;
    /// A frame's figures waiting for the header (frame 0's, until a stepped frame names the passes).
    struct WaitingRow {
        uint32_t frame;
        FrameStats stats;
        std::optional<ShapeColumns> shape;
    };
    Result<bool> write_waiting_rows();
    std::vector<WaitingRow> waiting_;
    std::string header_;  ///< empty until written
    std::vector<std::string> pass_columns_;
    bool has_whitewater_ = false;  // the spray, foam, bubbles, whitewater_emitted, whitewater_dropped columns
    Result<bool> write_whitewater_chart(const Scene& scene) const;
    std::vector<std::pair<double, WhitewaterCounts>> whitewater_samples_;  // (time, counts) for whitewater.svg
    bool has_flow_ = false;                                                // the emitted, removed, not_emitted columns
    /// flow.svg: the particles alive and the totals that came and went, over time.
    Result<bool> write_flow_chart(const Scene& scene) const;
    /// The run's closing line on its water, and a warning when the capacity was full.
    void say_flow_totals(const Scene& scene) const;
    struct FlowSample {
        double time;
        uint32_t alive;
        FlowCounts counts;
    };
    std::vector<FlowSample> flow_samples_;
    bool has_front_ = false;
    std::vector<std::pair<double, double>> front_samples_;  // (time, front)
    std::string error_;
    std::optional<double> shaped_since_;  // first and last time a shape was active
    double shaped_until_ = 0.0;
    double best_iou_ = 0.0;
    uint32_t best_iou_frame_ = 0;
};

/// A folder's rule for `run`: it is the run's (hold_output_dir keeps others out while it
/// writes), and the files an earlier run left there (frames, exports with their .pvd and
/// exports.csv, stats.csv, front.*, whitewater.svg, probes.csv, probe_*.svg) are removed first, so that none of them pass for this run's;
/// other files stay. Returns how many were removed; a symbolic link where the run writes a file
/// is refused (naming it), before anything is removed.
Result<size_t> clear_earlier_run(const std::filesystem::path& dir);

}  // namespace aquaform::runner
