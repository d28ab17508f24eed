// `run --mesh-every K [--mesh-format obj|ply]`: the fluid's surface as a welded triangle mesh
// every K frames (render/surface_mesher.h: the SPH surface renderer's field and iso value,
// marching cubes on the GPU), extracted in the frame's own submission after the solver, read back
// with it, and written as surface_NNNN.obj or .ply with the frame's other files.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "apps/cli.h"
#include "exports/mesh_export.h"
#include "render/surface_mesher.h"
#include "sim/frame_stats.h"

namespace aquaform::cli {

struct MeshOptions {
    uint32_t every = 0;  ///< 0: no meshes
    MeshFormat format = MeshFormat::obj;
};

/// The value flags it reads.
inline constexpr const char* kMeshEveryFlag = "--mesh-every";
inline constexpr const char* kMeshFormatFlag = "--mesh-format";

/// --mesh-every and --mesh-format; nullopt with `error` naming the flag and what it accepts.
std::optional<MeshOptions> mesh_options_from(const Args& args, std::string* error);

class RunMeshes {
public:
    /// `field`: the renderer settings whose surface is meshed (the defaults for the other families).
    RunMeshes(gpu::Context& ctx, const MeshOptions& options, const ParticleDomain& domain, uint32_t particles,
              const SurfaceSettings& field, std::filesystem::path out_dir);

    bool due(uint32_t frame) const { return frame % options_.every == 0; }
    /// Records frame `frame`'s mesh, when due, reading the solver's grid in place where it serves.
    void record(VkCommandBuffer cmd, uint32_t frame, const gpu::Buffer& positions, uint32_t count,
                const NeighborGrid* frame_grid, gpu::GpuTimer* timer);
    /// After the frame's submission has completed (before the next is recorded): its mesh, when
    /// due. Where the mesh outgrew its buffers it is extracted again, and `stats` gets the GPU time
    /// of both attempts.
    std::optional<SurfaceMesh> collect(uint32_t frame, gpu::GpuTimer& timer, FrameStats& stats);
    /// surface_NNNN.obj or .ply in the output folder; the error names the file and the fix.
    Result<bool> write(uint32_t frame, const SurfaceMesh& mesh) const;
    /// "surface mesh (obj every 5)   12.3 MiB" for the run's header.
    std::string memory_line() const;

private:
    MeshOptions options_;
    SurfaceMesher mesher_;
    std::filesystem::path out_dir_;
};

}  // namespace aquaform::cli
