#include "apps/run_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gpu/context.h"
#include "sim/pbf_solver.h"

namespace aquaform::cli {

void print_run_header(const gpu::Context& ctx, const PbfSolver& solver) {
    const Scene& scene = solver.scene();
    const auto& p = solver.params();
    std::printf("scene %s: %s, spacing %g m, h %g m, %u to %u steps per frame (cfl %g), %u iterations%s\n",
                scene.name.c_str(), solver.count_phrase().c_str(), scene.particle_spacing, p.h, scene.solver.substeps,
                scene.solver.max_substeps, scene.solver.cfl, scene.solver.iterations,
                scene.solver.max_speed > 0.0f
                    ? (", speeds capped at " + std::to_string(scene.solver.max_speed) + " m/s").c_str()
                    : "");
    std::printf("device: %s (%s)\n", ctx.info().name.c_str(), gpu::device_type_name(ctx.info().type));
    std::string passes;
    for (const auto& name : solver.enabled_passes()) passes += (passes.empty() ? "" : ", ") + name;
    std::printf("passes: %s\nGPU memory:\n", passes.c_str());
    uint64_t total = 0;
    for (const auto& b : solver.memory_report()) {
        std::printf("  %-24s %10.3f MiB\n", b.name.c_str(), double(b.bytes) / (1 << 20));
        total += b.bytes;
    }
    const uint64_t cells = solver.grid().geometry().cell_count();
    const double per_particle = double(total - uint64_t(kGridBytesPerCell) * cells) / std::max(1u, solver.capacity());
    std::printf("  %-24s %10.3f MiB (%.0f B per particle + %u B per grid cell, %llu cells)\n", "total",
                double(total) / (1 << 20), per_particle, kGridBytesPerCell, (unsigned long long)cells);
    std::fflush(stdout);
}

void print_control_summary(const session::ControlSummary& summary, const char* command) {
    for (const std::string& note : summary.mesh_notes) std::printf("  %s\n", note.c_str());
    std::printf("  %s\n", summary.strength.c_str());
    if (!summary.warning.empty()) std::fprintf(stderr, "aquaform %s: warning: %s\n", command, summary.warning.c_str());
}

}  // namespace aquaform::cli
