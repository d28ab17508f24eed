#include "exports/frame_capture.h"

#include <cstdio>
#include <cstring>

#include "gpu/staging.h"
#include "gpu/timer.h"

namespace aquaform {

FrameCapturer::FrameCapturer(gpu::Context& ctx, const FrameExports& exports, PbfSolver& solver,
                             const ParticleDomain& domain, const SurfaceSettings& field)
    : ctx_(&ctx), exports_(&exports), solver_(&solver) {
    if (exports.enabled(FrameExport::mesh)) {
        mesher_ = std::make_unique<SurfaceMesher>(ctx, domain, solver.capacity(), field);
        sampler_ = &mesher_->sampler();
    }
    for (const FrameExportKind& kind : frame_export_kinds())
        if (kind.needs == FrameData::volume && exports.enabled(kind.kind) && !sampler_) {
            own_sampler_ = std::make_unique<DensitySampler>(ctx, domain, solver.capacity(), field);
            sampler_ = own_sampler_.get();
        }
}

FrameCapturer::~FrameCapturer() = default;

void FrameCapturer::record(VkCommandBuffer cmd, uint32_t frame, const FrameInput& input, gpu::GpuTimer* timer) {
    const bool mesh = exports_->due(FrameExport::mesh, frame);
    if (mesh) {
        mesher_->share_grid(input.grid);
        mesher_->record(cmd, *input.positions, input.count, timer);
    }
    if (!exports_->needs_volume(frame)) return;
    if (!mesh) {  // the mesher sampled the field already
        sampler_->share_grid(input.grid);
        sampler_->record(cmd, *input.positions, input.count, timer);
    }
    record_volume_readback(cmd);
}

void FrameCapturer::record_volume_readback(VkCommandBuffer cmd) {
    const VkDeviceSize bytes = VkDeviceSize(sampler_->capacity()) * sizeof(float);
    if (!host_values_ || host_values_->size < bytes) {
        host_ = std::make_unique<gpu::BufferSet>(*ctx_);
        host_values_ = &host_->add("exports.volume_readback", bytes, gpu::MemoryUse::host);
    }
    sampler_->record_readback(cmd);
    gpu::record_download(*ctx_, cmd, sampler_->values(), *host_values_, bytes);
}

FrameCapture FrameCapturer::collect(uint32_t frame, gpu::GpuTimer& timer, FrameStats& stats) {
    FrameCapture capture;
    if (exports_->due(FrameExport::mesh, frame)) {
        capture.mesh = mesher_->collect(&timer);
        // The timer holds the frame's totals, plus those of an extraction made again.
        for (const char* pass : {"mesh_sample", "mesh_march"})
            if (auto it = timer.totals_ms().find(pass); it != timer.totals_ms().end()) stats.gpu_ms[pass] = it->second;
    }
    // After the mesh: an extraction made again there leaves the sampler's lattice of this frame.
    if (exports_->needs_volume(frame)) capture.volume = collect_volume();
    if (exports_->needs_particles(frame)) capture.particles = solver_->snapshot();
    return capture;
}

DensityVolume FrameCapturer::collect_volume() {
    const shader::MeshLattice lattice = sampler_->lattice();
    if (uint64_t(lattice.dims.w) * sizeof(float) > host_values_->size)  // not sampled: over the capacity then
        return sampler_->sample_volume(solver_->positions(), solver_->particle_count());
    DensityVolume volume;
    volume.origin = glm::vec3(lattice.origin_voxel);
    volume.voxel = lattice.origin_voxel.w;
    volume.dims = glm::uvec3(lattice.dims);
    volume.iso = sampler_->iso();
    const auto* values = static_cast<const float*>(host_values_->mapped);
    volume.values.assign(values, values + lattice.dims.w);
    return volume;
}

std::string FrameCapturer::memory_line() const {
    if (!sampler_) return {};
    uint64_t bytes = 0;
    for (const auto& b : mesher_ ? mesher_->memory_report() : own_sampler_->memory_report()) bytes += b.bytes;
    if (host_) bytes += host_->total_bytes();
    char line[128];
    std::snprintf(line, sizeof line, "  %-26s %.3f MiB (grows with the fluid's extent)",
                  !mesher_                              ? "density volume"
                  : exports_->enabled(FrameExport::vdb) ? "surface mesh and volume"
                                                        : "surface mesh",
                  double(bytes) / (1024.0 * 1024.0));
    return line;
}

}  // namespace aquaform
