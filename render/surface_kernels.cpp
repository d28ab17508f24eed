#include "render/surface_kernels.h"

namespace aquaform {

SurfaceKernels::SurfaceKernels(gpu::Context& ctx, gpu::BufferSet& buffers, const GridGeometry& geometry,
                               uint32_t max_particles, const std::string& prefix)
    : ctx_(&ctx), geometry_(geometry), max_particles_(std::max(max_particles, 1u)), prefix_(prefix) {
    shape_ = &buffers.add(prefix + ".shape", uint64_t(max_particles_) * 48);
    centres_ = &buffers.add(prefix + ".centres", uint64_t(max_particles_) * 16);
    shape_pass_ = gpu::ComputePass(ctx, {"render/classify_shape.comp", 6});
    gather_pass_ = gpu::ComputePass(ctx, {"render/kernel_gather.comp", 10});
}

void SurfaceKernels::record_shapes(VkCommandBuffer cmd, const gpu::Buffer& params, const gpu::Buffer& sorted,
                                   const gpu::Buffer& cell_rank, const gpu::Buffer& cell_start, uint32_t count) {
    gpu::dispatch(*ctx_, cmd, shape_pass_, std::max(count, 1u),
                  {{"params", &params},
                   {"sorted", &sorted},
                   {"cell_rank", &cell_rank},
                   {"cell_start", &cell_start},
                   {"shape", shape_},
                   {"centres", centres_}});
}

void SurfaceKernels::record_kernels(VkCommandBuffer cmd, const gpu::Buffer& params, const gpu::Buffer& aggregate,
                                    const gpu::Buffer& class_density, uint32_t count) {
    if (!grid_) {
        const uint64_t n = max_particles_;
        kernel_buffers_ = std::make_unique<gpu::BufferSet>(*ctx_);
        grid_ = std::make_unique<NeighborGrid>(*ctx_, *kernel_buffers_, geometry_, max_particles_,
                                               prefix_ + ".kernel_grid");
        kernel_centres_ = &kernel_buffers_->add(prefix_ + ".kernel_centres", n * 16);
        kernel_shape_ = &kernel_buffers_->add(prefix_ + ".kernel_shape", n * 48);
        kernel_aggregate_ = &kernel_buffers_->add(prefix_ + ".kernel_aggregate", n * 4);
        kernel_class_density_ = &kernel_buffers_->add(prefix_ + ".kernel_class_density", n * 4);
    }
    grid_->build(cmd, *centres_, count, nullptr);
    gpu::dispatch(*ctx_, cmd, gather_pass_, std::max(count, 1u),
                  {{"params", &params},
                   {"order", &grid_->order()},
                   {"centres", centres_},
                   {"shape", shape_},
                   {"aggregate", &aggregate},
                   {"kernel_centres", kernel_centres_},
                   {"kernel_shape", kernel_shape_},
                   {"kernel_aggregate", kernel_aggregate_},
                   {"class_density", &class_density},
                   {"kernel_class_density", kernel_class_density_}});
}

std::vector<gpu::BufferReport> SurfaceKernels::kernel_memory_report() const {
    return kernel_buffers_ ? kernel_buffers_->report() : std::vector<gpu::BufferReport>{};
}

}  // namespace aquaform
