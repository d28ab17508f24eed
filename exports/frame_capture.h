// What a frame's due exports (exports/frame_exports.h) need from the device, taken in the frame's
// own submission after the solver: the surface mesh (SurfaceMesher, its counts read back there),
// the density volume (the mesher's sampler when a mesh is due too, so the field is sampled once;
// its values are copied into host memory there: the lattice is chosen on the device, so the whole
// capacity is copied), and then the particle snapshot. A submission of its own only where a
// lattice or mesh outgrew its buffers.
#pragma once

#include <memory>
#include <string>

#include "exports/frame_exports.h"
#include "gpu/buffer.h"
#include "render/density_sampler.h"
#include "render/frame_input.h"
#include "render/surface_mesher.h"
#include "render/surface_settings.h"
#include "sim/frame_stats.h"
#include "sim/pbf_solver.h"

namespace aquaform {

namespace gpu {
class GpuTimer;
}  // namespace gpu

class FrameCapturer {
public:
    /// `domain`: the solver's particles' (Scene::particle_domain). `field`: the renderer's
    /// settings whose field, iso value and surface the volume and mesh show. The mesher and the
    /// sampler are made only for the kinds that are enabled.
    FrameCapturer(gpu::Context& ctx, const FrameExports& exports, PbfSolver& solver, const ParticleDomain& domain,
                  const SurfaceSettings& field);
    ~FrameCapturer();

    /// Records, after the solver's frame `frame` in its submission, what its due exports need of
    /// `input` (SimulationSession::frame_input): its particles, and its grid, read in place where
    /// it serves (DensitySampler::share_grid; nullptr: the sampler's own).
    void record(VkCommandBuffer cmd, uint32_t frame, const FrameInput& input, gpu::GpuTimer* timer);
    /// Once that submission has completed, before the next frame is recorded: the capture (but
    /// its whitewater, which the session gives: SimulationSession::whitewater_snapshot). Where
    /// the mesh was extracted again, `stats` gets the GPU time of both attempts from `timer`.
    FrameCapture collect(uint32_t frame, gpu::GpuTimer& timer, FrameStats& stats);
    /// "  surface mesh and volume    12.3 MiB (grows with the fluid's extent)" for the run's
    /// header; empty when nothing is made on the device.
    std::string memory_line() const;

private:
    void record_volume_readback(VkCommandBuffer cmd);
    DensityVolume collect_volume();

    gpu::Context* ctx_;
    const FrameExports* exports_;
    PbfSolver* solver_;
    std::unique_ptr<SurfaceMesher> mesher_;
    std::unique_ptr<DensitySampler> own_sampler_;  // for volumes without meshes
    DensitySampler* sampler_ = nullptr;            // the mesher's or its own
    std::unique_ptr<gpu::BufferSet> host_;         // per sampler capacity
    gpu::Buffer* host_values_ = nullptr;
};

}  // namespace aquaform
