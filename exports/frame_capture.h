// What a frame's due exports (exports/frame_exports.h) need from the device. The density
// volume is sampled after the solver's frame in the frame's own submission and copied into
// host memory there (the sampler's lattice is chosen on the device, so the whole capacity is
// copied); the particle snapshot is read after it. No submission of its own unless the lattice
// outgrew the sampler's buffers.
#pragma once

#include <memory>

#include "exports/frame_exports.h"
#include "gpu/buffer.h"
#include "render/density_sampler.h"
#include "render/surface_settings.h"
#include "sim/pbf_solver.h"

namespace aquaform {

class FrameCapturer {
public:
    /// `domain`: the solver's particles' (Scene::particle_domain). `field`: the renderer's
    /// settings whose field and iso value the volume samples. The
    /// sampler is made only when an export needs volumes.
    FrameCapturer(gpu::Context& ctx, const FrameExports& exports, PbfSolver& solver, const ParticleDomain& domain,
                  const SurfaceSettings& field);
    ~FrameCapturer();

    /// Records, after the solver's frame `frame` in its submission, what its due exports need.
    /// `frame_grid`: the solver's grid of this frame, read in place where it serves
    /// (SimulationSession::frame_grid, DensitySampler::share_grid); nullptr: the sampler's own.
    void record(VkCommandBuffer cmd, uint32_t frame, const NeighborGrid* frame_grid, gpu::GpuTimer* timer);
    /// Once that submission has completed, before the next frame is recorded: the capture
    /// (sampled again in a submission of its own where the lattice outgrew the buffers).
    FrameCapture collect(uint32_t frame);

private:
    void record_volume_readback(VkCommandBuffer cmd);
    DensityVolume collect_volume();

    gpu::Context* ctx_;
    const FrameExports* exports_;
    PbfSolver* solver_;
    std::unique_ptr<DensitySampler> sampler_;
    std::unique_ptr<gpu::BufferSet> host_;  // per sampler capacity
    gpu::Buffer* host_values_ = nullptr;
};

}  // namespace aquaform
