#include "apps/run_meshes.h"

#include <cstdio>

#include "gpu/timer.h"

namespace aquaform::cli {

std::optional<MeshOptions> mesh_options_from(const Args& args, std::string* error) {
    MeshOptions options;
    if (args.has(kMeshEveryFlag)) {
        auto every = parse_positive(kMeshEveryFlag, args.value(kMeshEveryFlag), error, kMaxFrames);
        if (!every) return std::nullopt;
        options.every = static_cast<uint32_t>(*every);
    }
    if (args.has(kMeshFormatFlag)) {
        auto format = parse_mesh_format(args.value(kMeshFormatFlag));
        if (!format) {
            *error = std::string(kMeshFormatFlag) + ": " + format.error();
            return std::nullopt;
        }
        options.format = format.value();
        if (!options.every) {
            *error = std::string(kMeshFormatFlag) + " needs " + kMeshEveryFlag + " K (a mesh every K frames)";
            return std::nullopt;
        }
    }
    return options;
}

RunMeshes::RunMeshes(gpu::Context& ctx, const MeshOptions& options, const ParticleDomain& domain, uint32_t particles,
                     const SurfaceSettings& field, std::filesystem::path out_dir)
    : options_(options), mesher_(ctx, domain, particles, field), out_dir_(std::move(out_dir)) {}

void RunMeshes::record(VkCommandBuffer cmd, uint32_t frame, const gpu::Buffer& positions, uint32_t count,
                       const NeighborGrid* frame_grid, gpu::GpuTimer* timer) {
    if (!due(frame)) return;
    mesher_.share_grid(frame_grid);
    mesher_.record(cmd, positions, count, timer);
}

std::optional<SurfaceMesh> RunMeshes::collect(uint32_t frame, gpu::GpuTimer& timer, FrameStats& stats) {
    if (!due(frame)) return std::nullopt;
    SurfaceMesh mesh = mesher_.collect(&timer);
    // The timer holds the frame's totals, plus those of an extraction made again.
    for (const char* pass : {"mesh_sample", "mesh_march"})
        if (auto it = timer.totals_ms().find(pass); it != timer.totals_ms().end()) stats.gpu_ms[pass] = it->second;
    return mesh;
}

Result<bool> RunMeshes::write(uint32_t frame, const SurfaceMesh& mesh) const {
    char name[40];
    std::snprintf(name, sizeof name, "surface_%04u.%s", frame, mesh_format_extension(options_.format));
    return write_mesh(out_dir_ / name, mesh, options_.format);
}

std::string RunMeshes::memory_line() const {
    uint64_t bytes = 0;
    for (const auto& b : mesher_.memory_report()) bytes += b.bytes;
    char line[96];
    std::snprintf(line, sizeof line, "  surface mesh (%s every %u)    %.3f MiB (grows with the fluid's extent)",
                  mesh_format_extension(options_.format), options_.every, double(bytes) / (1024.0 * 1024.0));
    return line;
}

}  // namespace aquaform::cli
