// What a scene's probes measured (sim/probes.h), as `aquaform run` writes it: probes.csv, one row
// per solver step (time, each gauge's height, each sensor's pressure; each solid's force and
// torque on the row that ends a frame), and at the end charts of them: probe_heights.svg,
// probe_pressures.svg, probe_forces.svg (those the scene has).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/file_write.h"
#include "core/result.h"
#include "sim/probes.h"
#include "sim/scene.h"

namespace aquaform::runner {

class ProbeFiles {
public:
    /// Nothing is written for a scene without probes.
    ProbeFiles(const std::filesystem::path& dir, const Scene& scene);
    bool ok() const { return error_.empty(); }
    const std::string& error() const { return error_; }
    /// The frame's steps as rows (whole rows or, on a full disk, an error that says so).
    Result<bool> write_frame(const ProbeFrame& frame);
    /// The charts.
    Result<bool> finish(const Scene& scene);

    static constexpr const char* kFileNames[] = {"probes.csv", "probe_heights.svg", "probe_pressures.svg",
                                                 "probe_forces.svg"};

private:
    std::filesystem::path dir_;
    bool on_ = false;
    AppendedFile csv_;
    std::string error_;
    std::vector<ProbeStep> steps_;                                  // for the charts
    std::vector<std::pair<double, std::vector<SolidLoad>>> loads_;  // (time, loads) per frame
};

}  // namespace aquaform::runner
