#include "sim/boundary.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/json_fields.h"
#include "geometry/animation.h"
#include "geometry/boundary_map.h"
#include "geometry/distance_field.h"
#include "shaders/shared/core/sph_kernels.h"
#include "shaders/shared/sim/pbf_boundary.h"
#include "sim/pbf_params.h"
#include "sim/scene.h"

namespace aquaform {

namespace {

/// Node spacing of the maps: half a particle spacing, and at most a quarter of h.
float map_cell(const Scene& scene) {
    const float h = scene.solver.kernel_radius_factor * scene.particle_spacing;
    return std::min(0.5f * scene.particle_spacing, 0.25f * h);
}

/// How far a map reaches beyond its solid: h (the density's reach) and a cell for interpolation.
float map_margin(const Scene& scene) {
    return scene.solver.kernel_radius_factor * scene.particle_spacing + map_cell(scene);
}

/// A static box that reaches a wall reaches through it: its faces on the walls are not faces
/// the fluid can meet, and a particle inside the box must be pushed out into the tank, not
/// through a wall. (Within a hundredth of a spacing counts as reaching.)
Box through_walls(Box box, const Scene& scene) {
    const float reach = map_margin(scene), eps = 0.01f * scene.particle_spacing;
    for (int a = 0; a < 3; ++a) {
        if (box.min[a] <= scene.domain.min[a] + eps) box.min[a] = scene.domain.min[a] - reach;
        if (box.max[a] >= scene.domain.max[a] - eps) box.max[a] = scene.domain.max[a] + reach;
    }
    return box;
}

/// Bounds of a deforming obstacle over its whole motion (sampled), so one grid holds every shape.
Box motion_bounds(const geometry::MeshAnimation& shape) {
    Box b = shape.mesh_at(0.0).bounds();
    const int samples = 240;
    for (int k = 1; k <= samples; ++k) {
        const Box s = shape.mesh_at(shape.duration() * k / samples).bounds();
        b.min = glm::min(b.min, s.min);
        b.max = glm::max(b.max, s.max);
    }
    return b;
}

/// The box a solid's map covers before the margin: a static box (through the walls), or a mesh's
/// bounds at rest (rigid motion moves the map with it) or over its motion (deforming).
Box solid_extent(const Scene& scene, size_t solid) {
    if (solid < scene.static_boxes.size()) return through_walls(scene.static_boxes[solid], scene);
    const ObstacleSpec& o = scene.obstacles[solid - scene.static_boxes.size()];
    return o.deforms ? motion_bounds(*o.shape) : o.shape->placed_rest().bounds();
}

std::string solid_name(const Scene& scene, size_t solid) {
    if (solid < scene.static_boxes.size()) return "static_boxes[" + std::to_string(solid) + "]";
    return "obstacles." + scene.obstacles[solid - scene.static_boxes.size()].name;
}

/// The rows of the world-to-local map of a rigid transform (rotation and translation).
void set_to_local(shader::SolidParams& table, const glm::mat4& to_world) {
    const glm::mat4 to_local = glm::inverse(to_world);
    for (int r = 0; r < 3; ++r)
        table.to_local[r] = glm::vec4(to_local[0][r], to_local[1][r], to_local[2][r], to_local[3][r]);
}

}  // namespace

uint64_t Boundary::planned_bytes(const Scene& scene) {
    double nodes = 0.0;
    const size_t solids = scene.static_boxes.size() + scene.obstacles.size();
    for (size_t s = 0; s < solids; ++s)
        nodes += geometry::GridSpec::count_covering(solid_extent(scene, s), map_cell(scene), map_margin(scene));
    return std::max<uint64_t>(uint64_t(nodes) * PBF_NODE_VEC4S * sizeof(glm::vec4), sizeof(glm::vec4));
}

Result<Boundary> Boundary::build(const Scene& scene) {
    Boundary b;
    const PbfConstants c = pbf_constants(scene);
    b.h_ = c.h;
    b.poly6_coeff_ = shader::poly6_coefficient(c.h);
    b.phi_ = c.wall_phi;
    const float cell = map_cell(scene), margin = map_margin(scene);
    b.margin_ = 0.25f * scene.particle_spacing;
    b.stride_ = 0.5f * cell;
    b.margin_of_map_ = margin;
    b.domain_ = scene.domain;
    const size_t solids = scene.static_boxes.size() + scene.obstacles.size();
    if (solids > PBF_MAX_SOLIDS)
        return Error{(scene.path.empty() ? scene.name : scene.path.string()) + ": " + std::to_string(solids) +
                     " solids (static_boxes and obstacles); the solver takes at most " +
                     std::to_string(PBF_MAX_SOLIDS) + ": merge boxes, or join meshes into one OBJ"};
    try {
        for (size_t s = 0; s < solids; ++s) {
            Solid solid;
            solid.name = solid_name(scene, s);
            const Box extent = solid_extent(scene, s);
            const double nodes = geometry::GridSpec::count_covering(extent, cell, margin);
            if (nodes > double(geometry::kMaxDistanceFieldNodes))
                return Error{solid.name + " is " + json_fields::fmt(extent) + ": its boundary map would need " +
                             json_fields::fmt(nodes) + " nodes at half a particle spacing (" + json_fields::fmt(cell) +
                             " m), more than " + std::to_string(geometry::kMaxDistanceFieldNodes) +
                             "; scale the obstacle down or increase particle_spacing"};
            solid.grid = geometry::GridSpec::covering(extent, cell, margin);
            const Box body = s < scene.static_boxes.size() ? scene.static_boxes[s] : extent;
            solid.centre = 0.5f * (body.min + body.max);
            if (s >= scene.static_boxes.size()) {
                const ObstacleSpec& o = scene.obstacles[s - scene.static_boxes.size()];
                solid.shape = o.shape;
                solid.moves = o.moves;
                solid.deforms = o.deforms;
                solid.max_speed = o.max_speed;
            }
            solid.first_node = b.nodes_.size() / PBF_NODE_VEC4S;
            b.nodes_.resize(b.nodes_.size() + solid.grid.node_count() * PBF_NODE_VEC4S);
            b.solids_.push_back(solid);
            Solid& placed = b.solids_.back();
            if (!placed.shape)
                b.store(placed, geometry::box_distance_field(extent, cell, margin), scene.domain);
            else if (auto made =
                         b.make_maps(placed, placed.deforms ? placed.shape->mesh_at(0.0) : placed.shape->placed_rest());
                     !made)
                return Error{placed.name + ": " + made.error()};
            placed.shape_key = placed.deforms ? 0 : -1;
        }
    } catch (const Failure& e) {
        return Error{e.what()};
    }
    if (b.nodes_.empty()) b.nodes_.push_back(glm::vec4(0.0f));  // a buffer to bind
    return b;
}

Result<bool> Boundary::make_maps(Solid& solid, const geometry::Mesh& mesh) {
    // A solid whose maps stand in the tank's frame (still or deforming; a rigid motion's are made
    // at rest and move) reaches through the walls, as a static box does, and is clipped to the
    // tank for its density: beyond the walls they count already.
    const std::optional<Box> walls = solid.moves && !solid.deforms ? std::optional<Box>() : std::optional<Box>(domain_);
    auto field =
        geometry::build_distance_field_on(mesh.triangle_soup(), solid.grid, margin_of_map_,
                                          solid.grid.node_count() > 1000000 ? solid.name : std::string(), walls);
    if (!field) return Error{field.error()};
    store(solid, field.value(), walls);
    return true;
}

void Boundary::store(Solid& solid, const geometry::DistanceField& field, std::optional<Box> clip) {
    if (field.grid.dims != solid.grid.dims) throw Failure(solid.name + ": its distance field is not on its map's grid");
    const geometry::BoundaryMap map =
        geometry::build_boundary_map(field, {h_, poly6_coeff_, phi_}, clip,
                                     solid.grid.node_count() > 1000000 ? solid.name + " density" : std::string());
    if (!map.complete) throw Failure(solid.name + ": the boundary map was stopped (Ctrl-C)");
    for (size_t n = 0; n < map.distance.size(); ++n) {
        nodes_[(solid.first_node + n) * PBF_NODE_VEC4S + PBF_NODE_DISTANCE] = map.distance[n];
        nodes_[(solid.first_node + n) * PBF_NODE_VEC4S + PBF_NODE_DENSITY] = map.density[n];
    }
}

std::vector<uint32_t> solid_constants(std::vector<uint32_t> own, bool solids) {
    own.resize(PBF_SOLIDS_CONSTANT, 0u);
    own.back() = solids ? 1u : 0u;
    return own;
}

bool Boundary::moves() const {
    return std::any_of(solids_.begin(), solids_.end(), [](const Solid& s) { return s.moves; });
}

bool Boundary::deforms() const {
    return std::any_of(solids_.begin(), solids_.end(), [](const Solid& s) { return s.deforms; });
}

void Boundary::write_params(shader::SimParams& params, double t) const {
    params.solid_count = uint32_t(solids_.size());
    params.solid_margin = margin_;
    params.solid_stride = stride_;
    for (size_t i = 0; i < solids_.size(); ++i) {
        const Solid& s = solids_[i];
        shader::SolidParams& table = params.solids[i];
        table.map_origin = glm::vec4(s.grid.origin, s.grid.cell);
        table.map_dims = glm::uvec4(s.grid.dims, uint32_t(s.first_node));
        // The maps of a rigid motion are made at rest; a deforming shape's in place (identity).
        set_to_local(table, s.shape && s.moves && !s.deforms ? s.shape->transform_at(t) : glm::mat4(1.0f));
    }
}

bool Boundary::reshape(double t) {
    bool changed = false;
    for (Solid& s : solids_) {
        if (!s.deforms) continue;
        // A sequence holds one shape per file: made again only when the file changes.
        const auto* sequence = std::get_if<geometry::SequenceAnimation>(&s.shape->kind());
        const int64_t key = sequence ? int64_t(sequence->frame_at(t)) : int64_t(std::llround(t * 1e6));
        if (key == s.shape_key) continue;
        auto made = make_maps(s, s.shape->mesh_at(t));
        if (!made) throw Failure(s.name + " at t = " + json_fields::fmt(t) + " s: " + made.error());
        s.shape_key = key;
        changed = true;
    }
    return changed;
}

std::vector<glm::vec3> Boundary::centres(double t) const {
    std::vector<glm::vec3> out;
    for (const Solid& s : solids_) {
        out.push_back(s.shape && s.moves && !s.deforms ? glm::vec3(s.shape->transform_at(t) * glm::vec4(s.centre, 1.0f))
                                                       : s.centre);
    }
    return out;
}

double Boundary::surface_speed(double t) const {
    double fastest = 0.0;
    for (const Solid& s : solids_) {
        if (!s.moves) continue;
        // Its fastest point over the motion (sim/obstacles.cpp samples it), while it moves.
        if (s.shape->duration() > 0.0 && !s.shape->loops() && t > s.shape->duration()) continue;
        fastest = std::max(fastest, s.max_speed);
    }
    return fastest;
}

}  // namespace aquaform
