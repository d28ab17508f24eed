// Runs a scene's control section alongside the solver: each frame it evaluates the timeline and
// the mesh animations, gives the driving force its points and sets, and measures how well the
// fluid takes the active shapes.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "control/control_force.h"
#include "control/control_scene.h"
#include "control/raster_placement.h"
#include "control/shape_metrics.h"
#include "control/strength.h"
#include "sim/pbf_solver.h"

namespace aquaform::control {

class ControlDriver {
public:
    /// `scene` must already run at strength.substeps (prepare_control_scene).
    ControlDriver(gpu::Context& ctx, const Scene& scene, ControlSection section, const Strength& strength);
    ~ControlDriver();

    /// The force to hand to PbfSolver::attach.
    ControlForce& force() { return *force_; }
    /// Sets the shapes, points and weights for simulated time t. Cheap when nothing changed.
    void update(double t);
    /// Shape fidelity of the fluid against the shapes active at the last update (weight >= 0.5).
    ShapeMetrics measure(const ParticleSnapshot& fluid);
    /// "ball (1.00), torus (0.40)" or "none".
    std::string active_description() const;
    const std::vector<ActiveShape>& active() const { return active_; }
    /// The active shapes' meshes in scene coordinates at the last update (for overlays).
    std::vector<geometry::Mesh> active_meshes() const;
    /// Wall time of the last update [ms] and its points.
    double update_ms() const { return update_ms_; }
    const ControlSection& section() const { return section_; }

private:
    const std::vector<glm::vec3>& base_points(int mesh);
    RasterPlacer& placer(size_t slot);
    /// Method (c) on the scene's lattice at `spacing`, growing the placer when points did not fit.
    RasterStats place_on(RasterPlacer& placer, const geometry::Mesh& mesh, float spacing, float w);
    /// Voxels inside a mesh at the last update's time (cached for meshes that do not move).
    const std::unordered_set<uint64_t>& shape_voxels(int mesh);

    gpu::Context* ctx_;
    Scene scene_;
    ControlSection section_;
    Strength strength_;
    std::unique_ptr<ControlForce> force_;
    std::vector<std::vector<glm::vec3>> base_points_;  // per mesh, placed once (meshes that do not deform)
    std::vector<bool> placed_;
    std::vector<std::unique_ptr<RasterPlacer>> placers_;  // one per active deforming shape, and one for metrics
    std::vector<ActiveShape> active_;
    struct VoxelCache {
        bool valid = false;
        std::unordered_set<uint64_t> keys;
    };
    std::vector<VoxelCache> voxels_;
    bool points_valid_ = false;
    double last_t_ = 0.0;
    double update_ms_ = 0.0;
    VoxelLattice lattice_;
};

/// Loads the control section and derives the strength; raises scene.solver.substeps to what the
/// strength needs. Prints nothing: the caller reports strength.describe() and warnings.
struct PreparedControl {
    ControlSection section;
    Strength strength;
};
Result<PreparedControl> prepare_control_scene(Scene& scene);

}  // namespace aquaform::control
