#include "sim/energy_budget.h"

#include "core/error.h"
#include "gpu/barriers.h"
#include "gpu/compute_pass.h"

namespace aquaform {

EnergyBudget::EnergyBudget(gpu::Context& ctx, uint32_t particles, uint32_t max_records)
    : ctx_(&ctx), particles_(particles) {
    const VkDeviceSize bytes = 3 * VkDeviceSize(particles) * sizeof(glm::vec4);
    for (uint32_t r = 0; r < max_records; ++r)
        copies_.push_back(gpu::create_buffer(ctx, "sim.energy_budget", bytes, gpu::MemoryUse::host));
}

EnergyBudget::~EnergyBudget() {
    for (gpu::Buffer& copy : copies_) gpu::destroy_buffer(*ctx_, copy);
}

void EnergyBudget::after(VkCommandBuffer cmd, const char* pass, const FluidArrays& fluid, PassState state) {
    if (records_.size() >= copies_.size() || fluid.count > particles_)
        throw Failure("energy budget: room for " + std::to_string(copies_.size()) + " records of " +
                      std::to_string(particles_) + " particles a frame, asked for more; size it for the frame");
    const uint32_t step = records_.empty() ? 0 : records_.back().step + (std::string(pass) == "start" ? 1 : 0);
    const gpu::Buffer& copy = copies_[records_.size()];
    const VkDeviceSize array = VkDeviceSize(fluid.count) * sizeof(glm::vec4);
    const gpu::Buffer* sources[] = {fluid.x, fluid.v, fluid.p};
    for (VkDeviceSize i = 0; i < 3; ++i) gpu::copy(*ctx_, cmd, *sources[i], copy, {0, i * array, array});
    gpu::host_read_barrier(cmd);
    records_.push_back({step, pass, state, fluid.count});
}

std::vector<PassEnergy> EnergyBudget::collect(double mass, const glm::dvec3& gravity, double dt) {
    std::vector<PassEnergy> energies;
    for (size_t r = 0; r < records_.size(); ++r) {
        const Record& record = records_[r];
        const auto* arrays = static_cast<const glm::vec4*>(copies_[r].mapped);
        const glm::vec4 *x = arrays, *v = arrays + record.count, *p = arrays + 2 * record.count;
        PassEnergy e{record.step, record.pass, 0.0, 0.0};
        for (uint32_t i = 0; i < record.count; ++i) {
            const bool settled = record.state == PassState::settled;
            const glm::dvec3 at = settled ? glm::dvec3(x[i]) : glm::dvec3(p[i]);
            const glm::dvec3 velocity = settled ? glm::dvec3(v[i]) : (glm::dvec3(p[i]) - glm::dvec3(x[i])) / dt;
            e.kinetic += 0.5 * mass * glm::dot(velocity, velocity);
            e.potential -= mass * glm::dot(gravity, at);
        }
        energies.push_back(std::move(e));
    }
    records_.clear();
    return energies;
}

}  // namespace aquaform
