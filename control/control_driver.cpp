#include "control/control_driver.h"

#include <algorithm>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "control/placement.h"
#include "gpu/staging.h"
#include "sim/pbf_params.h"

namespace aquaform::control {

namespace {

glm::vec3 lattice_origin(const Scene& scene, float spacing) { return scene.domain.min + 0.5f * spacing; }

bool same_shapes(const std::vector<ActiveShape>& a, const std::vector<ActiveShape>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i].mesh != b[i].mesh) return false;
    return true;
}

}  // namespace

Result<PreparedControl> prepare_control_scene(Scene& scene) {
    auto section = load_control_section(scene);
    if (!section) return Error{section.error()};
    PreparedControl prepared{std::move(section.value()), {}};
    prepared.strength = automatic_strength(
        {&scene, prepared.section.spacing, prepared.section.shape_height(scene.gravity)}, prepared.section.overrides);
    scene.solver.substeps = prepared.strength.substeps;
    scene.solver.max_substeps = std::max(scene.solver.max_substeps, prepared.strength.substeps);
    return prepared;
}

ControlDriver::ControlDriver(gpu::Context& ctx, const Scene& scene, ControlSection section, const Strength& strength)
    : ctx_(&ctx), scene_(scene), section_(std::move(section)), strength_(strength) {
    force_ = std::make_unique<ControlForce>(ctx, scene, strength.support, std::pow(section_.spacing, 3.0f),
                                            section_.damping);
    base_points_.resize(section_.meshes.size());
    placed_.assign(section_.meshes.size(), false);
    voxels_.resize(section_.meshes.size());
    lattice_ = {scene.domain.min, scene.particle_spacing};
}

ControlDriver::~ControlDriver() = default;

RasterPlacer& ControlDriver::placer(size_t slot) {
    if (placers_.size() <= slot) placers_.resize(slot + 1);
    if (!placers_[slot]) placers_[slot] = std::make_unique<RasterPlacer>(*ctx_, 4096, 65536, 65536);
    return *placers_[slot];
}

const std::vector<glm::vec3>& ControlDriver::base_points(int mesh) {
    if (!placed_[mesh]) {
        const ControlMesh& m = section_.meshes[mesh];
        const geometry::Mesh& rest = m.animation.placed_rest();
        const glm::vec3 origin = lattice_origin(scene_, section_.spacing);
        switch (m.method) {
            case PlacementMethod::vertices:
                base_points_[mesh] = place_on_vertices(rest, section_.spacing).points;
                break;
            case PlacementMethod::inside:
                base_points_[mesh] = place_inside(rest.triangle_soup(), section_.spacing, false, 1, origin).points;
                break;
            case PlacementMethod::raster:
                base_points_[mesh] = place_raster(*ctx_, rest.triangle_soup(), section_.spacing, origin).points;
                break;
        }
        placed_[mesh] = true;
    }
    return base_points_[mesh];
}

void ControlDriver::update(double t) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<ActiveShape> active = section_.timeline.active_at(t);
    bool moving = false;
    for (const ActiveShape& s : active) moving = moving || section_.meshes[s.mesh].animation.moves();
    if (!points_valid_ || moving || !same_shapes(active, active_)) {
        std::vector<glm::vec4> cpu;
        std::vector<ControlForce::GpuPoints> gpu;
        for (size_t k = 0; k < active.size(); ++k) {
            const ControlMesh& m = section_.meshes[active[k].mesh];
            if (m.animation.deforms()) {
                RasterPlacer& p = placer(k + 1);
                gpu.push_back({&p.points(), place_on(p, m.animation.mesh_at(t), section_.spacing, float(k)).points});
                continue;
            }
            const glm::mat4 transform = m.animation.transform_at(t);
            for (const glm::vec3& p : base_points(active[k].mesh))
                cpu.emplace_back(glm::vec3(transform * glm::vec4(p, 1.0f)), float(k));
        }
        force_->set_points(cpu, gpu);
        points_valid_ = true;
    }
    std::vector<ForceSet> sets;
    for (const ActiveShape& s : active) sets.push_back({strength_.pressure, s.weight, s.tag_mask});
    force_->set_sets(sets);
    active_ = std::move(active);
    last_t_ = t;
    update_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

RasterStats ControlDriver::place_on(RasterPlacer& placer, const geometry::Mesh& mesh, float spacing, float w) {
    const auto triangles = mesh.triangle_soup();
    const glm::vec3 origin = lattice_origin(scene_, spacing);
    RasterStats stats = placer.place_on_gpu(triangles, spacing, origin, w);
    if (stats.dropped_points) {  // grow once (with room for a growing shape) and place again
        placer.set_point_capacity(stats.points + stats.dropped_points + stats.points / 4);
        stats = placer.place_on_gpu(triangles, spacing, origin, w);
    }
    return stats;
}

const std::unordered_set<uint64_t>& ControlDriver::shape_voxels(int mesh) {
    const ControlMesh& m = section_.meshes[mesh];
    auto& cached = voxels_[mesh];
    if (cached.valid && !m.animation.moves()) return cached.keys;
    RasterPlacer& p = placer(0);
    const RasterStats stats = place_on(p, m.animation.mesh_at(last_t_), lattice_.spacing, 0.0f);
    cached.keys.clear();
    for (const glm::vec4& c : gpu::download_vector<glm::vec4>(*ctx_, p.points(), stats.points))
        cached.keys.insert(VoxelLattice::key(lattice_.index_of(glm::vec3(c))));
    cached.valid = true;
    return cached.keys;
}

ShapeMetrics ControlDriver::measure(const ParticleSnapshot& fluid) {
    std::unordered_set<uint64_t> shape;
    uint32_t tags = 0;
    for (const ActiveShape& s : active_) {
        if (s.weight < 0.5f) continue;  // a shape fading out of a morph is no longer the target
        tags |= s.tag_mask;
        const auto& keys = shape_voxels(s.mesh);
        shape.insert(keys.begin(), keys.end());
    }
    const PbfConstants k = pbf_constants(scene_);
    return shape_metrics({&fluid.x, &fluid.v, tags, k.h, k.mass, scene_.rest_density}, lattice_, shape);
}

std::string ControlDriver::active_description() const {
    if (active_.empty()) return "none";
    std::string s;
    char buf[32];
    for (const ActiveShape& a : active_) {
        std::snprintf(buf, sizeof buf, " (%.2f)", a.weight);
        s += (s.empty() ? "" : ", ") + section_.meshes[a.mesh].name + buf;
    }
    return s;
}

std::vector<geometry::Mesh> ControlDriver::active_meshes() const {
    std::vector<geometry::Mesh> meshes;
    for (const ActiveShape& s : active_) meshes.push_back(section_.meshes[s.mesh].animation.mesh_at(last_t_));
    return meshes;
}

}  // namespace aquaform::control
