// The renderer's field phi(p) = V sum_j W(p - x_j, r) (shaders/shared/render/render_kernels.h) sampled
// on a lattice on the GPU, from the solver's particle buffer in place: the input of the surface
// mesher (render/surface_mesher.h) and of volume exports (DensityVolume). Same r, same V, same
// iso as the surface renderer with the same SurfaceSettings (radius_spacings, lone_radius).
// Passes, in order (timed together as "mesh_sample"):
//   (grid)         the particles' neighbour grid. Where the caller shares the solver's frame grid
//                  (share_grid) and its cells are at least r, the particles are read in place;
//                  otherwise the sampler builds its own grid of cells r over the domain and reads
//                  the particles through its order (no copy of the positions).
//   mesh_bounds    the particles' bounds (a workgroup reduction and atomics)
//   mesh_lattice   the lattice: the bounds padded by r + one voxel (so that its outermost samples
//                  are 0 and a closed fluid gives a closed surface), clipped to the domain padded
//                  the same way, snapped to the lattice anchored there; chosen on the device, so
//                  that sampling runs in the frame's own submission without a trip to the host
//   (kernels)      the anisotropic surface only (SurfaceSettings::surface): the renderer's kernels
//                  (render/surface_kernels.h) from the particles sorted by a grid of cells r (in
//                  place, or the own grid and a sorted copy of the positions)
//   mesh_sample    phi at every sample (indirect dispatch over the lattice)
// The lattice's buffers hold `capacity()` samples. A lattice beyond them is measured, not
// sampled (lattice().dims.w > capacity()): reserve() grows them and the caller samples again.
// Layout and conventions: shaders/shared/render/mesh_layout.h.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/box.h"
#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "grid/neighbor_grid.h"
#include "render/density_volume.h"
#include "render/surface_kernels.h"
#include "render/surface_settings.h"
#include "shaders/shared/render/mesh_layout.h"

namespace aquaform {

namespace gpu {
class Context;
class GpuTimer;
}  // namespace gpu

/// Lattice spacing of surface meshes and volumes, in particle radii (a quarter of the particle
/// spacing; r / 8 at the solver's usual h = 2 spacings): a lone droplet (lone_radius 1: one
/// particle radius) is four voxels across. Measured against the exhaustive ray-marched
/// reference on a cube and three droplets (tests/test_surface_mesh.cpp, 2002 surface pixels):
///   voxel 0.5 radii (default)   mean 0.015, max 0.094 particle radii from the mesh, 6800 triangles
///   voxel 1 radius              mean 0.067, max 0.42,                              1640 triangles
/// At one radius a droplet is two voxels across and comes out as a faceted blob (the max); half
/// a radius keeps every surface within a tenth of a radius for 4x the triangles.
constexpr float kDefaultMeshVoxelRadii = 0.5f;

class DensitySampler {
public:
    /// `field`: the renderer's settings whose field and iso value are sampled (radius_spacings,
    /// lone_radius). Buffers start sized for a compact blob of `max_particles` particles.
    /// Throws aquaform::Failure when the field's own grid does not fit (the message names the fix).
    DensitySampler(gpu::Context& ctx, const ParticleDomain& domain, uint32_t max_particles,
                   const SurfaceSettings& field = {}, float voxel_radii = kDefaultMeshVoxelRadii);
    ~DensitySampler();
    DensitySampler(const DensitySampler&) = delete;
    DensitySampler& operator=(const DensitySampler&) = delete;

    /// The positions given to record() are sorted by `grid`, a grid of those very positions (the
    /// solver's frame grid, SimulationSession::frame_grid()): read in place where its cells are
    /// at least r. nullptr: always build a grid. It must outlive its use.
    void share_grid(const NeighborGrid* grid) { shared_grid_ = grid; }
    bool reads_in_place() const;

    /// The volume of `count` particles of `positions` (vec4, xyz in metres): records, submits and
    /// waits (again with larger buffers when the lattice outgrew them), and reads it back.
    /// Stable entry point for volume exports.
    DensityVolume sample_volume(const gpu::Buffer& positions, uint32_t count);

    /// Records bounds, lattice and samples; `vertex_capacity` and `triangle_capacity` go into the
    /// parameter block for the mesher's passes.
    void record(VkCommandBuffer cmd, const gpu::Buffer& positions, uint32_t count, gpu::GpuTimer* timer,
                uint32_t vertex_capacity = 0, uint32_t triangle_capacity = 0);
    /// Records the copy of the lattice block (with the mesher's totals) into host memory.
    void record_readback(VkCommandBuffer cmd);
    /// The lattice block of the last recording, once its submission has completed.
    shader::MeshLattice lattice() const;
    /// Grows the lattice's buffers to hold `samples` (at most the lattice over the whole clip box).
    /// Throws a resource Failure naming the figures and the fix beyond sample_limit().
    void reserve(uint64_t samples);
    /// The most samples the device can take: the mesher's prefix sums dispatch a thread per sample
    /// in one row of workgroups, and each per-sample array must fit one storage (and texel) buffer.
    uint64_t sample_limit() const;

    uint32_t capacity() const { return capacity_; }
    /// Dispatches the last sample pass was split into (the device's work budget).
    uint32_t sample_slices() const { return params_.sample_slices; }
    float iso() const { return params_.iso; }
    float voxel() const { return params_.clip_min.w; }
    float radius() const { return params_.radius; }
    const ParticleDomain& domain() const { return domain_; }
    gpu::Context& context() const { return *ctx_; }
    const gpu::Buffer& params_buffer() const { return *params_buf_; }
    const gpu::Buffer& lattice_buffer() const { return *lattice_; }
    const gpu::Buffer& values() const { return *values_; }
    std::vector<gpu::BufferReport> memory_report() const;

private:
    void make_own_grid();
    void make_kernels();  ///< the anisotropic surface's kernels and what making them needs

    gpu::Context* ctx_;
    SurfaceSettings field_;
    ParticleDomain domain_;
    uint32_t max_particles_;
    shader::MeshParams params_{};
    uint64_t clip_samples_ = 0;  // the lattice over the whole clip box: no frame needs more
    uint32_t capacity_ = 0;
    gpu::BufferSet buffers_;
    std::unique_ptr<gpu::BufferSet> lattice_buffers_;  // per capacity
    std::unique_ptr<gpu::BufferSet> own_buffers_;      // the own grid, made on first use
    std::unique_ptr<NeighborGrid> own_grid_;
    GridGeometry own_geometry_;
    const NeighborGrid* shared_grid_ = nullptr;
    std::unique_ptr<gpu::BufferSet> kernel_buffers_;  // the anisotropic surface's kernels, made on first use
    std::unique_ptr<SurfaceKernels> kernels_;
    gpu::Buffer *kernel_params_ = nullptr, *sorted_copy_ = nullptr, *no_classes_ = nullptr;
    gpu::ComputePass gather_pass_;
    gpu::Buffer *params_buf_, *bounds_, *lattice_, *lattice_host_;
    gpu::Buffer* sample_groups_;  ///< the sample pass's indirect dispatch (one slice's share)
    gpu::Buffer* values_ = nullptr;
    gpu::ComputePass bounds_pass_, lattice_pass_, sample_pass_;
};

}  // namespace aquaform
