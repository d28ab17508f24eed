// The solver's stability map of a study: one scene run over a grid of time steps x constraint
// iterations (x control pressures, for scenes with mesh control), recording the density error
// and whether, and when, the run blew up. Written as solver_map.csv, charted by
// scripts/study_charts.py.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "sim/blowup.h"
#include "sim/frame_stats.h"
#include "sim/scene.h"

namespace aquaform::gpu {
class Context;
}

namespace aquaform::study {

struct SolverMapSpec {
    std::filesystem::path scene;
    /// Solver time steps dt [s] (one PBF step, not a frame). A cell runs at exactly dt; its frames
    /// (measurement points) are round(scene frame_dt / dt) steps long, at least one.
    std::vector<float> frame_dts;
    std::vector<uint32_t> iterations;  ///< constraint iterations per step
    /// Control pressures [Pa] to try; empty runs the scene as it is (its own or the automatic
    /// pressure). Needs a scene with a control section.
    std::vector<float> control_pressures;
    float sim_time_s = 1.0f;  ///< simulated time per cell [s]
};

struct SolverMapRecord {
    std::string scene;  ///< the scene file's stem
    float dt = 0.0f;
    uint32_t iterations = 0;
    std::optional<float> control_pressure;  ///< empty: the scene as is
    double density_err_max = 0.0;           ///< max over frames of the max compression rho/rho0 - 1
    double density_err_mean = 0.0;          ///< mean over frames of the mean compression
    bool stable = true;
    double blowup_time_s = -1.0;  ///< simulated time of the first failing frame; -1 if stable
    std::string failure;          ///< why it blew up (empty when stable); not in the CSV
    uint32_t frames = 0;          ///< frames run (to the blow-up, or all)
    double wall_s = 0.0;
};

/// A line of progress per cell; empty prints "solver map: ..." to stderr.
using SolverMapProgress = std::function<void(const std::string& line)>;

/// Resuming and stopping a map: a cell `done` accepts (a record with the cell's scene, dt,
/// iterations and pressure) is skipped; `measured` gets each record as its cell ends (false
/// stops the map); Ctrl-C (core/interrupt.h) stops the map after the current cell.
struct SolverMapHooks {
    std::function<bool(const SolverMapRecord& cell)> done;
    std::function<bool(const SolverMapRecord& record)> measured;
};

/// Everything run_solver_map checks before its first cell, without the GPU: the scene loads,
/// the settings hold (steps per cell, a control pressure needs a control section), the scene's
/// control section loads. Errors name the field and the fix.
Result<bool> check_solver_map(const SolverMapSpec& spec);

/// Runs every cell (dt x iterations x pressure) from the scene's initial state. A blown-up cell
/// stops at its first failing frame and the map goes on; errors are for bad specs or scenes
/// (naming the field and the fix) and for device failures. Returns the records measured.
Result<std::vector<SolverMapRecord>> run_solver_map(gpu::Context& ctx, const SolverMapSpec& spec,
                                                    const SolverMapProgress& progress = {},
                                                    const SolverMapHooks& hooks = {});

/// solver_map.csv: scene,dt,iterations,control_pressure,density_err_max,density_err_mean,stable,
/// blowup_time_s,spec,cell (control_pressure empty for the scene as is; blowup_time_s empty when
/// stable; spec: the study's spec_hash, empty outside a study; cell: solver_map_cell_key).
Result<bool> write_solver_map_csv(const std::filesystem::path& path, const std::vector<SolverMapRecord>& records);
std::string solver_map_csv_header();
std::string solver_map_csv_line(const SolverMapRecord& r, const std::string& spec);
/// "tiny_column/dt 0.004/2 iterations[/500 Pa]": a cell's identity in solver_map.csv.
std::string solver_map_cell_key(const SolverMapRecord& r);

}  // namespace aquaform::study
