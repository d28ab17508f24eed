#include "exports/frame_capture.h"

#include <cstring>

namespace aquaform {

FrameCapturer::FrameCapturer(gpu::Context& ctx, const FrameExports& exports, PbfSolver& solver,
                             const ParticleDomain& domain, const SurfaceSettings& field)
    : ctx_(&ctx), exports_(&exports), solver_(&solver) {
    for (const FrameExportKind& kind : frame_export_kinds())
        if (kind.needs_volume && exports.enabled(kind.kind) && !sampler_)
            sampler_ = std::make_unique<DensitySampler>(ctx, domain, solver.particle_count(), field);
}

FrameCapturer::~FrameCapturer() = default;

void FrameCapturer::record(VkCommandBuffer cmd, uint32_t frame, const NeighborGrid* frame_grid,
                           gpu::GpuTimer* timer) {
    if (!exports_->needs_volume(frame)) return;
    sampler_->share_grid(frame_grid);
    sampler_->record(cmd, solver_->positions(), solver_->particle_count(), timer);
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

FrameCapture FrameCapturer::collect(uint32_t frame) {
    FrameCapture capture;
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

}  // namespace aquaform
