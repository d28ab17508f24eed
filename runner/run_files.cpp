#include "runner/run_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <regex>
#include <set>

#include <nlohmann/json.hpp>

#include "core/csv.h"
#include "core/file_write.h"
#include "core/text_escape.h"
#include "exports/frame_exports.h"
#include "exports/obstacle_export.h"
#include "pictures/svg_chart.h"
#include "sim/dam_break_reference.h"
#include "sim/front_chart.h"

namespace aquaform::runner {

Result<bool> write_run_description(const std::filesystem::path& dir, const Scene& scene, const char* up,
                                   uint32_t particles) {
    const auto xyz = [](const glm::vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
    const nlohmann::json run = {{"scene", scene.path.string()},
                                {"name", scene.name},
                                {"domain", {{"min", xyz(scene.domain.min)}, {"max", xyz(scene.domain.max)}}},
                                {"up", up},
                                {"frame_dt", scene.solver.frame_dt},
                                {"particles", particles},
                                {"particle_spacing", scene.particle_spacing},
                                {"obstacles", ObstacleExports::description(scene)}};
    return write_file_with(dir / kRunDescriptionName, [&](std::ostream& out) { out << json_text(run, 2) << '\n'; });
}

RunFiles::RunFiles(const std::filesystem::path& dir, const Scene& scene) : dir_(dir), probes_(dir, scene) {
    if (!probes_.ok()) {
        error_ = probes_.error();
        return;
    }
    auto stats = AppendedFile::open(dir / "stats.csv");
    if (!stats) {
        error_ = stats.error();
        return;
    }
    stats_ = std::move(stats.value());
    has_front_ = scene.column_width.has_value();
    if (has_front_) {
        auto front = AppendedFile::open(dir / "front.csv");
        auto header = front ? front.value().append("time_s,front_m\n") : Result<bool>(Error{front.error()});
        if (!header)
            error_ = header.error();
        else
            front_ = std::move(front.value());
    }
}

void RunFiles::warn_if_never_filled() const {
    // A shape that pulled for a second and never overlapped the fluid is almost always placed
    // where the fluid cannot reach, too weak, or attached to the wrong fluid: say so, not only in
    // stats.csv. (Within the first second a shape may still be filling.)
    if (!shaped_since_ || shaped_until_ - *shaped_since_ < kFillGraceSeconds || best_iou_ >= kNeverFilledIou) return;
    std::fprintf(stderr,
                 "aquaform run: warning: the control shape never filled: its IoU with the fluid peaked at %.2f (frame "
                 "%u; shape_iou in stats.csv) over %.1f s of pull. Place the shape where the fluid can reach it (or "
                 "add fluid near it), check the timeline's tags, or raise control.pressure\n",
                 best_iou_, best_iou_frame_, shaped_until_ - *shaped_since_);
}

Result<bool> RunFiles::write_frame_stats(uint32_t frame, const FrameStats& s, const ShapeColumns* shape) {
    if (shape && shape->active != "none") {
        if (!shaped_since_) shaped_since_ = s.time_s;
        shaped_until_ = s.time_s;
        if (shape->iou >= best_iou_) best_iou_ = shape->iou, best_iou_frame_ = frame;
    }
    if (has_front_ && s.front) {
        char row[64];
        std::snprintf(row, sizeof row, "%.6f,%.6f\n", s.time_s, *s.front);
        if (auto written = front_.append(row); !written) return written;
        front_samples_.push_back({s.time_s, *s.front});
    }
    if (s.whitewater) whitewater_samples_.push_back({s.time_s, *s.whitewater});
    if (s.flow) flow_samples_.push_back({s.time_s, s.particles, *s.flow});
    waiting_.push_back({frame, s, shape ? std::optional<ShapeColumns>(*shape) : std::nullopt});
    // Frame 0 (the state at t = 0) takes no step, so its timings name only a few passes: its row
    // waits for the first stepped frame, whose passes make the header's GPU columns.
    if (header_.empty() && s.substeps == 0) return true;
    return write_waiting_rows();
}

Result<bool> RunFiles::write_waiting_rows() {
    if (waiting_.empty()) return true;
    std::string text;  // the rows (the first after the header) in one piece: whole rows or none
    const bool has_shape = bool(waiting_.front().shape);
    if (header_.empty()) {
        for (const auto& [name, ms] : waiting_.back().stats.gpu_ms) pass_columns_.push_back(name);
        header_ =
            "frame,time_s,particles,density_err_mean,density_err_max,density_dev_mean,kinetic_energy_j,"
            "max_speed_mps,substeps,dt_s,cfl_number,speed_capped,outside,in_solid,non_finite,splash_fraction,droplets,"
            "runup_m,list_overflow,gpu_ms_total";
        if (has_shape) header_ += ",shape_iou,shape_fill_fraction,fluid_outside_shape,active_shapes";
        has_whitewater_ = bool(waiting_.front().stats.whitewater);
        if (has_whitewater_) header_ += ",spray,foam,bubbles,whitewater_emitted,whitewater_dropped";
        has_flow_ = bool(waiting_.front().stats.flow);
        if (has_flow_) header_ += ",emitted,removed,not_emitted";  // particle totals since the start
        for (const auto& name : pass_columns_) header_ += ",gpu_ms_" + name;
        text = header_ + "\n";
    }
    for (const WaitingRow& w : waiting_) {
        const FrameStats& s = w.stats;
        double total = 0.0;
        for (const auto& [name, ms] : s.gpu_ms) total += ms;
        char row[512];
        // Measures a frame does not have (no droplet count asked for, no particle at the wall) stay blank.
        const std::string droplets = s.droplets ? std::to_string(*s.droplets) : "";
        char runup[32] = "";
        if (s.runup) std::snprintf(runup, sizeof runup, "%.5f", *s.runup);
        std::snprintf(
            row, sizeof row, "%u,%.6f,%u,%.6g,%.6g,%.6g,%.6g,%.6g,%u,%.6g,%.4f,%d,%u,%u,%u,%.5f,%s,%s,%.5f,%.4f",
            w.frame, s.time_s, s.particles, s.mean_density_error, s.max_density_error, s.mean_density_deviation,
            s.kinetic_energy, s.max_speed, s.substeps, s.dt, s.cfl_number, s.speed_capped ? 1 : 0, s.outside,
            s.in_solid, s.non_finite, s.splash_fraction, droplets.c_str(), runup, s.list_overflow_fraction, total);
        text += row;
        if (w.shape) {
            std::snprintf(row, sizeof row, ",%.4f,%.4f,%.4f,", w.shape->iou, w.shape->fill_fraction,
                          w.shape->outside_fraction);
            text += row + csv_field(w.shape->active, true);  // the shapes' names are the scene's: any text
        }
        if (has_whitewater_) {
            const WhitewaterCounts c = s.whitewater.value_or(WhitewaterCounts{});
            std::snprintf(row, sizeof row, ",%u,%u,%u,%llu,%llu", c.spray, c.foam, c.bubbles,
                          (unsigned long long)c.emitted, (unsigned long long)c.dropped);
            text += row;
        }
        if (has_flow_) {
            const FlowCounts c = s.flow.value_or(FlowCounts{});
            std::snprintf(row, sizeof row, ",%llu,%llu,%llu", (unsigned long long)c.emitted,
                          (unsigned long long)c.removed, (unsigned long long)c.not_emitted);
            text += row;
        }
        for (const auto& name : pass_columns_) {
            auto it = s.gpu_ms.find(name);
            std::snprintf(row, sizeof row, ",%.4f", it == s.gpu_ms.end() ? 0.0 : it->second);
            text += row;
        }
        text += "\n";
    }
    if (auto written = stats_.append(text); !written) return written;
    waiting_.clear();
    return true;
}

Result<bool> RunFiles::finish(const Scene& scene) {
    if (auto written = write_waiting_rows(); !written) return written;  // a run of frame 0 alone
    warn_if_never_filled();
    if (auto charted = probes_.finish(scene); !charted) return charted;
    if (auto charted = write_whitewater_chart(scene); !charted) return charted;
    if (auto charted = write_flow_chart(scene); !charted) return charted;
    say_flow_totals(scene);
    if (!has_front_ || front_samples_.empty()) return true;
    const double a = *scene.column_width;
    const double g = std::max(1e-6f, std::abs(scene.gravity.y));
    const auto run = nondimensional_front(front_samples_, a, g);
    const Chart chart = front_chart("Dam-break surge front: " + scene.name, {front_series("aquaform", run, "#1f6fb4")});
    if (auto written = write_chart_svg(dir_ / "front.svg", chart); !written) return written;

    const Box& column = scene.fluid_blocks.front();
    const bool comparable = scene.fluid_blocks.size() == 1 && std::abs((column.max.y - column.min.y) / a - 2.0) < 0.1;
    auto cmp = compare_with_martin_moyce(run);
    if (comparable && cmp)
        std::printf("front against Martin & Moyce (1952): mean error %.1f %%, max %.1f %% over %d points (chart: %s)\n",
                    100.0 * cmp->mean_relative, 100.0 * cmp->max_relative, cmp->points,
                    (dir_ / "front.svg").string().c_str());
    return true;
}

Result<bool> RunFiles::write_whitewater_chart(const Scene& scene) const {
    if (whitewater_samples_.empty()) return true;
    Chart chart{"Whitewater alive: " + scene.name, "time [s]", "whitewater particles", {}};
    // The kinds, their sum, and what the full pool could not keep (summed over the run: a line
    // that leaves zero says the pool was too small; the scene's whitewater.capacity raises it).
    ChartSeries spray{"spray", {}, false, "#d62728"}, foam{"foam", {}, false, "#1f6fb4"},
        bubbles{"bubbles", {}, false, "#2ca02c"}, all{"all", {}, false, "#555555", true},
        dropped{"dropped (total)", {}, false, "#ff7f0e", true};
    uint64_t dropped_so_far = 0;
    for (const auto& [t, c] : whitewater_samples_) {
        dropped_so_far += c.dropped;
        spray.points.push_back({t, double(c.spray)});
        foam.points.push_back({t, double(c.foam)});
        bubbles.points.push_back({t, double(c.bubbles)});
        all.points.push_back({t, double(c.live())});
        dropped.points.push_back({t, double(dropped_so_far)});
    }
    chart.series = {spray, foam, bubbles, all};
    if (dropped_so_far > 0) chart.series.push_back(dropped);
    return write_chart_svg(dir_ / "whitewater.svg", chart);
}

void RunFiles::say_flow_totals(const Scene& scene) const {
    if (flow_samples_.empty()) return;
    const FlowSample& last = flow_samples_.back();
    std::printf("water: %llu particles emitted, %llu removed, %u alive at the end (flow.svg)\n",
                (unsigned long long)last.counts.emitted, (unsigned long long)last.counts.removed, last.alive);
    // Said once, at the end: the nozzles kept running and the layers that did not fit were skipped.
    const auto full = std::find_if(flow_samples_.begin(), flow_samples_.end(),
                                   [](const FlowSample& f) { return f.counts.not_emitted > 0; });
    if (full != flow_samples_.end())
        std::fprintf(stderr,
                     "aquaform run: warning: the fluid filled its capacity of %llu particles by t = %.3f s, and %llu "
                     "particles the emitters would have made were not emitted (not_emitted in stats.csv); raise the "
                     "scene's \"capacity\" or add a sink\n",
                     (unsigned long long)scene.particle_capacity(), full->time,
                     (unsigned long long)last.counts.not_emitted);
}

Result<bool> RunFiles::write_flow_chart(const Scene& scene) const {
    if (flow_samples_.empty()) return true;
    Chart chart{"Water that came and went: " + scene.name, "time [s]", "particles", {}};
    // A "not emitted" line that leaves zero says the capacity was full (the scene's "capacity").
    ChartSeries alive{"alive", {}, false, "#1f6fb4"}, emitted{"emitted (total)", {}, false, "#2ca02c", true},
        removed{"removed (total)", {}, false, "#d62728", true},
        refused{"not emitted (total)", {}, false, "#ff7f0e", true};
    for (const FlowSample& f : flow_samples_) {
        alive.points.push_back({f.time, double(f.alive)});
        emitted.points.push_back({f.time, double(f.counts.emitted)});
        removed.points.push_back({f.time, double(f.counts.removed)});
        refused.points.push_back({f.time, double(f.counts.not_emitted)});
    }
    chart.series = {alive, emitted, removed};
    if (flow_samples_.back().counts.not_emitted > 0) chart.series.push_back(refused);
    return write_chart_svg(dir_ / "flow.svg", chart);
}

Result<size_t> clear_earlier_run(const std::filesystem::path& dir) {
    // The numbered frames and the obstacles' meshes; diffuse_*: the whitewater's files' old name.
    static const std::regex written(
        R"((frame|particles|whitewater|diffuse|density|surface)_[0-9]{4,}\.(png|ply|vtu|vdb|obj|vtp)|obstacle_.+\.obj)");
    static const std::set<std::string> named{"stats.csv",   "front.csv",     "front.svg",        "whitewater.svg",
                                             "flow.svg",    "particles.pvd", "surface.pvd",      "whitewater.pvd",
                                             "diffuse.pvd", kExportListing,  kRunDescriptionName};
    static const std::set<std::string> probe_files(std::begin(ProbeFiles::kFileNames),
                                                   std::end(ProbeFiles::kFileNames));
    std::vector<std::filesystem::path> earlier;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (!named.count(name) && !probe_files.count(name) && !std::regex_match(name, written)) continue;
        // A link where the run writes would send its files elsewhere: refused before any work.
        if (entry.is_symlink(ec)) return link_refused(entry.path());
        if (entry.is_regular_file(ec) && name != kRunDescriptionName) earlier.push_back(entry.path());
    }
    size_t removed = 0;
    for (const auto& path : earlier) {
        // Found now, before any work: a file left in place would be written over at the end, or
        // pass for this run's (another user's file in a sticky folder such as /tmp cannot go).
        if (!std::filesystem::remove(path, ec) && ec)
            return Error{"cannot remove " + path.string() + ", an earlier run's file (" + ec.message() +
                         "; in a folder such as /tmp only its owner may remove it): remove it yourself, or give "
                         "another --out"};
        ++removed;
    }
    return removed;
}

}  // namespace aquaform::runner
