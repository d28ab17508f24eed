// The driving force of mesh control (Karpati et al., section 3.1; formula and units in
// shaders/shared/control/control_layout.h): control points pull fluid particles of chosen tags into the
// region they fill. The points live on the GPU in their own Morton-sorted grid (cell = support
// radius H), rebuilt whenever the points change; the force is one pass per solver step.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "grid/neighbor_grid.h"
#include "shaders/shared/control/control_layout.h"
#include "sim/pbf_solver.h"
#include "sim/scene.h"

namespace aquaform::control {

/// Velocity decay rate inside a shape [1/s]: a held sphere's sloshing halves in about 0.15 s, and
/// a shape moving at 0.2 m/s drags its fluid by only 1 m/s^2.
inline constexpr float kDefaultDamping = 5.0f;

/// One control set (a mesh's points) as the force sees it.
struct ForceSet {
    float pressure = 0.0f;    ///< control pressure P [Pa], a suction: > 0 attracts
    float weight = 1.0f;      ///< blend weight in [0, 1] (cross-fading morphs)
    uint32_t tag_mask = ~0u;  ///< fluid tags it acts on (bit t: tag t)
};

class ControlForce final : public StepForce {
public:
    /// `support` is H (at least the solver's kernel radius), `point_volume` the volume V_c each
    /// control point stands for (control spacing^3). Memory grows with the points given.
    /// `damping` [1/s] slows the fluid where phi ~ 1 (inside a shape): our addition to the
    /// paper's force, which is conservative, so that a held shape comes to rest.
    ControlForce(gpu::Context& ctx, const Scene& scene, float support, float point_volume,
                 float damping = kDefaultDamping);
    ~ControlForce() override;

    /// A range of control points already on the GPU (vec4: xyz, w = set index), e.g. placed by
    /// the rasteriser this frame.
    struct GpuPoints {
        const gpu::Buffer* buffer = nullptr;
        uint32_t count = 0;
    };
    /// Replaces every control point: `cpu_points` then each of `gpu_points`, w = the index of its
    /// set in set_sets(). Rebuilds the grid (one submission, waits).
    void set_points(const std::vector<glm::vec4>& cpu_points, const std::vector<GpuPoints>& gpu_points = {});
    /// At most CONTROL_MAX_SETS sets; a set with weight or pressure 0 exerts nothing.
    void set_sets(const std::vector<ForceSet>& sets);

    void record(VkCommandBuffer cmd, const gpu::Buffer& sim_params, const gpu::Buffer& x, gpu::Buffer& v,
                uint32_t count, gpu::GpuTimer* timer) override;

    uint32_t point_count() const { return count_; }
    float support() const { return params_.support; }
    /// Sorted control points (tests, pictures).
    std::vector<glm::vec4> download_points() const;
    std::vector<gpu::BufferReport> memory_report() const;

private:
    void reserve(uint32_t points);

    gpu::Context* ctx_;
    GridGeometry geometry_;
    float point_volume_;
    float rest_density_;
    shader::ControlParams params_{};
    bool active_ = false;  // some set exerts a force
    uint32_t count_ = 0;
    uint32_t capacity_ = 0;
    std::unique_ptr<gpu::BufferSet> params_buffers_;
    std::unique_ptr<gpu::BufferSet> point_buffers_;  // reallocated when the points outgrow them
    gpu::Buffer* params_buf_ = nullptr;
    gpu::Buffer* points_ = nullptr;
    gpu::Buffer* sorted_ = nullptr;
    std::unique_ptr<NeighborGrid> grid_;
    gpu::ComputePass gather_, force_;
};

}  // namespace aquaform::control
