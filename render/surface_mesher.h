// The fluid's surface as a welded triangle mesh, extracted on the GPU from the solver's particle
// buffer: the renderer's field sampled on a lattice (render/density_sampler.h), then marching
// cubes (the table of render/marching_cubes.h, whose CPU reference it equals index for index).
// Passes, after the sampler's (timed together as "mesh_march"):
//   mesh_classify   per sample: its crossing edges (vertex count) and its cell's triangle count
//   (prefix sums)   both into offsets (grid/prefix_sum.h); their ends are the totals
//   mesh_vertices   one vertex per crossing edge (linear interpolation; normal -grad phi)
//   mesh_triangles  per cell, the table's triangles over the edges' vertices
// Every triangle corner names the one vertex of its lattice edge, shared by the four cells around
// that edge, so the mesh is welded; with the table's face-consistent rule it is closed and
// consistently oriented (outward) wherever the fluid is closed: every edge has two triangles.
//
// Memory, in two phases: the sizes are counted on the device and the output is written up to
// the capacity of its buffers (host-visible: no copy to read them). collect() reads the counts
// back; where the lattice, the vertices or the triangles outgrew their buffers, it grows them
// (by half again) and extracts once more in a submission of its own, which reads the positions
// again: call it before they change (the run does, before the next frame is recorded). Sizes
// beyond what the device can hold are a resource Failure naming them and the fix.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "grid/prefix_sum.h"
#include "render/density_sampler.h"
#include "render/marching_cubes.h"

namespace aquaform {

class SurfaceMesher {
public:
    /// `field`: the renderer's settings whose surface is meshed (its radius and iso value).
    SurfaceMesher(gpu::Context& ctx, const ParticleDomain& domain, uint32_t max_particles,
                  const SurfaceSettings& field = {}, float voxel_radii = kDefaultMeshVoxelRadii);
    ~SurfaceMesher();
    SurfaceMesher(const SurfaceMesher&) = delete;
    SurfaceMesher& operator=(const SurfaceMesher&) = delete;

    /// The solver's frame grid, read in place where it serves (DensitySampler::share_grid).
    void share_grid(const NeighborGrid* grid) { sampler_.share_grid(grid); }

    /// Records the extraction for `count` particles of `positions` into `cmd` (e.g. after the
    /// solver's frame, in its submission) and the read-back of its counts.
    void record(VkCommandBuffer cmd, const gpu::Buffer& positions, uint32_t count, gpu::GpuTimer* timer);
    /// Once the recording's submission has completed: the mesh (extracting again, larger, where
    /// it outgrew the buffers, timed on `timer`; the positions given to record() must not have
    /// changed).
    SurfaceMesh collect(gpu::GpuTimer* timer = nullptr);
    /// record, submit, wait, collect.
    SurfaceMesh extract(const gpu::Buffer& positions, uint32_t count);

    DensitySampler& sampler() { return sampler_; }
    const DensitySampler& sampler() const { return sampler_; }
    uint32_t vertex_capacity() const { return vertex_capacity_; }
    uint32_t triangle_capacity() const { return triangle_capacity_; }
    std::vector<gpu::BufferReport> memory_report() const;

private:
    /// Buffers for `samples` lattice samples (the sampler's too).
    void reserve_lattice(uint64_t samples);
    void reserve_output(uint64_t vertices, uint64_t triangles);
    void record_march(VkCommandBuffer cmd);

    gpu::Context* ctx_;
    DensitySampler sampler_;
    gpu::BufferSet buffers_;
    std::unique_ptr<gpu::BufferSet> lattice_buffers_;  // per lattice capacity
    std::unique_ptr<gpu::BufferSet> output_buffers_;   // per output capacity
    gpu::PrefixSum scan_;
    gpu::Buffer* table_;
    gpu::Buffer *vertex_offset_ = nullptr, *triangle_offset_ = nullptr;
    gpu::Buffer *vertices_ = nullptr, *normals_ = nullptr, *triangles_ = nullptr;
    uint32_t vertex_capacity_ = 0, triangle_capacity_ = 0;
    // What the last record() read, for an extraction again in collect().
    const gpu::Buffer* positions_ = nullptr;
    uint32_t count_ = 0;
    gpu::ComputePass classify_, vertices_pass_, triangles_pass_;
};

}  // namespace aquaform
