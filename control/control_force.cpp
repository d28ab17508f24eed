#include "control/control_force.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"

namespace aquaform::control {

ControlForce::ControlForce(gpu::Context& ctx, const Scene& scene, float support, float point_volume, float damping)
    : ctx_(&ctx), point_volume_(point_volume), rest_density_(scene.rest_density) {
    auto geometry = grid_for_domain(scene.domain.min, scene.domain.max, support);
    if (!geometry) throw resource_failure("control support radius: " + geometry.error());
    geometry_ = geometry.value();
    params_.grid_origin_cell = glm::vec4(geometry_.origin, geometry_.cell_size);
    params_.grid_dims = glm::uvec4(geometry_.dims, geometry_.cell_count());
    params_.support = support;
    params_.support2 = support * support;
    params_.damping = damping;
    params_.gradient_coeff = shader::poly6_coefficient(support);
    gpu::UploadBatch uploads(ctx);
    params_buffers_ = std::make_unique<gpu::BufferSet>(ctx);
    params_buf_ = &params_buffers_->add("control.params", sizeof(shader::ControlParams));
    gpu::upload(ctx, *params_buf_, &params_, sizeof params_);
    gather_ = gpu::ComputePass(ctx, {"control/control_gather.comp", 3, sizeof(shader::CountPush)});
    force_ = gpu::ComputePass(ctx, {"control/control_force.comp", 7, sizeof(shader::CountPush)});
    reserve(1024);
}

ControlForce::~ControlForce() = default;

void ControlForce::reserve(uint32_t points) {
    if (points <= capacity_) return;
    capacity_ = std::max(points, capacity_ + capacity_ / 2);  // grow by half, so animated shapes settle quickly
    grid_.reset();
    point_buffers_ = std::make_unique<gpu::BufferSet>(*ctx_);
    points_ = &point_buffers_->add("control.points", uint64_t(capacity_) * 16);
    sorted_ = &point_buffers_->add("control.sorted_points", uint64_t(capacity_) * 16);
    grid_ = std::make_unique<NeighborGrid>(*ctx_, *point_buffers_, geometry_, capacity_, "control.grid");
}

void ControlForce::set_points(const std::vector<glm::vec4>& cpu_points, const std::vector<GpuPoints>& gpu_points) {
    uint64_t total = cpu_points.size();
    for (const auto& g : gpu_points) total += g.count;
    if (total >= (1ull << 24))
        throw resource_failure(std::to_string(total) +
                               " control points is more than 16,777,216; increase the control spacing");
    count_ = uint32_t(total);
    reserve(count_);
    gpu::UploadBatch uploads(*ctx_);  // the points join the grid's submission
    if (!cpu_points.empty()) gpu::upload(*ctx_, *points_, cpu_points.data(), cpu_points.size() * 16);
    if (count_ == 0) return;
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) {
        VkDeviceSize offset = cpu_points.size() * 16;
        for (const auto& g : gpu_points) {
            if (g.count == 0) continue;
            const VkBufferCopy copy{0, offset, VkDeviceSize(g.count) * 16};
            gpu::copy(*ctx_, cmd, *g.buffer, *points_, copy);
            offset += copy.size;
        }
        grid_->build(cmd, *points_, count_, nullptr);
        gpu::dispatch(*ctx_, cmd, gather_, count_, shader::CountPush{count_},
                      {{"points", points_}, {"order", &grid_->order()}, {"sorted", sorted_}});
    });
}

void ControlForce::set_sets(const std::vector<ForceSet>& sets) {
    if (sets.size() > CONTROL_MAX_SETS)
        throw resource_failure(std::to_string(sets.size()) + " control sets are active at once; at most " +
                               std::to_string(CONTROL_MAX_SETS) + " can be: release some before attaching more");
    params_.set_count = uint32_t(sets.size());
    active_ = false;
    for (size_t i = 0; i < sets.size(); ++i) {
        params_.sets[i].coefficient = sets[i].pressure / rest_density_ * point_volume_ * sets[i].weight;
        params_.sets[i].tag_mask = sets[i].tag_mask;
        params_.sets[i].weight_volume = point_volume_ * sets[i].weight;
        active_ = active_ || (params_.sets[i].coefficient != 0.0f && sets[i].tag_mask != 0u);
    }
    gpu::upload(*ctx_, *params_buf_, &params_, sizeof params_);
}

void ControlForce::record(VkCommandBuffer cmd, const gpu::Buffer& sim_params, const gpu::Buffer& x, gpu::Buffer& v,
                          uint32_t count, gpu::GpuTimer* timer) {
    if (!active_ || count_ == 0) return;  // released: the fluid runs plain physics at no cost
    gpu::GpuScope s(timer, cmd, "control_force");
    gpu::dispatch(*ctx_, cmd, force_, count, shader::CountPush{count},
                  {{"sim", &sim_params},
                   {"control", params_buf_},
                   {"x", &x},
                   {"v", &v},
                   {"points", sorted_},
                   {"cell_rank", &grid_->cell_rank()},
                   {"cell_start", &grid_->cell_start()}});
}

std::vector<glm::vec4> ControlForce::download_points() const {
    return gpu::download_vector<glm::vec4>(*ctx_, *sorted_, count_);
}

std::vector<gpu::BufferReport> ControlForce::memory_report() const {
    auto report = params_buffers_->report();
    for (auto& b : point_buffers_->report()) report.push_back(b);
    return report;
}

}  // namespace aquaform::control
