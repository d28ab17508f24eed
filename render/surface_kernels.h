// The anisotropic surface's kernels (Yu & Turk 2013, "Reconstructing surfaces of particle-based
// fluids using anisotropic kernels"), made on the GPU from particles sorted by a grid of cells r:
//   render_shapes   per particle, the weighted PCA of its neighbours within r: the kernel's shape
//                   G (shared/render/anisotropy.h, the same shapes Wu et al.'s classification uses) and
//                   its centre, smoothed towards its neighbours (Yu & Turk eq. 6)
//   (kernel grid)   a grid of cells r over the centres: a centre moves up to lambda r from its
//                   particle, so only a grid of the centres finds, in the 27 cells around a
//                   point, every kernel that reaches it
//   kernel_gather   centres, shapes and classes in that grid's order, where every field pass
//                   (march, mask, sprites, mesh samples) reads them as it reads particles
// GPU memory per particle: 48 B shape + 16 B centre in the particles' order (kShapeBytesPerParticle;
// what the classification needs too), and once the kernels are first recorded, the kernel grid's
// 16 B (kGridSortBytesPerParticle) and 16 + 48 + 4 + 4 B in kernel order (kKernelBytesPerParticle):
// 152 B in all, plus 8 B per cell.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "grid/neighbor_grid.h"

namespace aquaform {

/// Particle visits of one evaluation of the SPH field, for the per-dispatch work bound
/// (gpu::Context::dispatch_slices): the candidates of the 27 cells around the point (cells of
/// the kernel radius, 2 spacings, hold 8 particles at rest density).
constexpr double kFieldVisitsPerEvaluation = 27.0 * 8.0;

constexpr uint32_t kShapeBytesPerParticle = 48 + 16;
constexpr uint32_t kKernelBytesPerParticle = kGridSortBytesPerParticle + 16 + 48 + 4 + 4;

class SurfaceKernels {
public:
    /// Shape buffers for `max_particles` in `buffers` (their names start with `prefix`); `geometry`
    /// is the grid of cells r the kernels will be sorted by (their buffers are made on first use).
    SurfaceKernels(gpu::Context& ctx, gpu::BufferSet& buffers, const GridGeometry& geometry, uint32_t max_particles,
                   const std::string& prefix);

    /// Per particle of `sorted` (sorted by `cell_rank` / `cell_start`, a grid of cells r; `params`
    /// a SurfaceParams block with the field's radius, the shape parameters and the count): shapes
    /// and smoothed centres, in the particles' order.
    void record_shapes(VkCommandBuffer cmd, const gpu::Buffer& params, const gpu::Buffer& sorted,
                       const gpu::Buffer& cell_rank, const gpu::Buffer& cell_start, uint32_t count);
    /// The kernels in their own grid's order, with the particles' classes `aggregate` (per
    /// particle, in their order; record_shapes must have been recorded first). The first call
    /// makes the kernels' buffers.
    void record_kernels(VkCommandBuffer cmd, const gpu::Buffer& params, const gpu::Buffer& aggregate,
                        const gpu::Buffer& class_density, uint32_t count);

    /// In the particles' order (for the classification, which reads each particle's own shape).
    const gpu::Buffer& particle_shapes() const { return *shape_; }
    const gpu::Buffer& particle_centres() const { return *centres_; }
    // In the kernels' own grid order: what the field passes read.
    const gpu::Buffer& centres() const { return *kernel_centres_; }
    const gpu::Buffer& shapes() const { return *kernel_shape_; }
    const gpu::Buffer& aggregate() const { return *kernel_aggregate_; }
    const gpu::Buffer& class_density() const { return *kernel_class_density_; }
    const gpu::Buffer& cell_rank() const { return grid_->cell_rank(); }
    const gpu::Buffer& cell_start() const { return grid_->cell_start(); }
    bool has_kernels() const { return grid_ != nullptr; }
    /// The kernels' buffers (empty before the first record_kernels).
    std::vector<gpu::BufferReport> kernel_memory_report() const;

private:
    gpu::Context* ctx_;
    GridGeometry geometry_;
    uint32_t max_particles_;
    std::unique_ptr<gpu::BufferSet> kernel_buffers_;
    std::unique_ptr<NeighborGrid> grid_;
    std::string prefix_;
    gpu::Buffer *shape_, *centres_, *kernel_centres_ = nullptr, *kernel_shape_ = nullptr, *kernel_aggregate_ = nullptr,
                                    *kernel_class_density_ = nullptr;
    gpu::ComputePass shape_pass_, gather_pass_;
};

}  // namespace aquaform
