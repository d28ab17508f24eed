// The solids of a scene as the solver takes them (shaders/shared/sim/pbf_boundary.h): its static
// boxes and its mesh obstacles, each a density map (Koschier & Bender 2017) made on the CPU in the
// solid's own frame, and where that frame stands at each step. The tank's walls need no map: their
// density is in closed form (pbf_wall_term), with the same kernel and calibration.
//
// Choices the paper leaves open:
// - Node spacing: half a particle spacing (a quarter of h at the usual h = 2 s), so a wall one
//   particle thick is two cells across and keeps negative distances at its core.
// - Collision margin: a quarter of a particle spacing outside the surface. The trilinear distance
//   near a sharp edge errs by a fraction of a cell; the margin keeps centres out of the true solid.
// - Moves are checked at half a node spacing (pbf_collide), so no move of a step crosses a solid.
// - A solid that stands still is clipped to the tank (what lies beyond the walls is the walls'
//   already); a moving one is not, so where it passes through a wall both count.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/box.h"
#include "core/result.h"
#include "geometry/distance_field.h"
#include "shaders/shared/sim/pbf_layout.h"

namespace aquaform {

struct Scene;
namespace geometry {
class MeshAnimation;
struct Mesh;
}  // namespace geometry

/// A pass's specialization constants: its own from constant_id 1, then whether the scene has
/// solids (static boxes or mesh obstacles) at PBF_SOLIDS_CONSTANT (shaders/shared/sim/pbf_boundary.h;
/// without, the solids compile down to the walls). For every pass that includes pbf_boundary.h.
std::vector<uint32_t> solid_constants(std::vector<uint32_t> own, bool solids);

class Boundary {
public:
    /// Makes every solid's maps (static boxes first, then the obstacles in the scene's order).
    /// Shows progress where that takes long; errors name the obstacle and the fix.
    static Result<Boundary> build(const Scene& scene);
    /// bytes() of what build() would make, without making it (the solver's memory plan).
    static uint64_t planned_bytes(const Scene& scene);

    size_t solid_count() const { return solids_.size(); }
    /// A solid's name as the scene gives it ("static_boxes[0]", "obstacles.rock").
    const std::string& name(size_t i) const { return solids_[i].name; }
    /// Any solid whose pose or shape changes with time: the table is rewritten every step.
    bool moves() const;
    /// Any solid whose shape changes (an OBJ sequence, a skeleton): its maps are made again.
    bool deforms() const;
    /// Every solid's node data, PBF_NODE_VEC4S vec4s a node (at least one vec4: a buffer to bind).
    const std::vector<glm::vec4>& nodes() const { return nodes_; }
    /// Writes the solids' table (count, margin, stride and each solid's frame) for time t.
    void write_params(shader::SimParams& params, double t) const;
    /// Makes the maps of the deforming solids again for time t, in place (same grids); returns
    /// whether any node changed. Nothing happens between two times of one shape (a sequence's frame).
    bool reshape(double t);
    /// Each solid's centre at time t (its map's box's centre, moved with it): what probes take
    /// torques about.
    std::vector<glm::vec3> centres(double t) const;
    /// The fastest any solid's surface moves at time t [m/s] (the time-step rule's share).
    double surface_speed(double t) const;
    /// Bytes of the node data.
    uint64_t bytes() const { return uint64_t(nodes_.size()) * sizeof(glm::vec4); }

private:
    struct Solid {
        std::string name;
        geometry::GridSpec grid;  ///< its maps' nodes, in its own frame
        size_t first_node = 0;    ///< its first node in nodes()
        glm::vec3 centre{0.0f};   ///< its bounds' centre at rest
        /// A mesh obstacle's shape and motion (null for a static box).
        std::shared_ptr<const geometry::MeshAnimation> shape;
        bool moves = false, deforms = false;
        double max_speed = 0.0;
        int64_t shape_key = -1;  ///< which shape its maps hold (deforming: see reshape)
    };
    /// Makes a mesh solid's maps for `mesh` (its frame's coordinates) on its grid.
    Result<bool> make_maps(Solid& solid, const geometry::Mesh& mesh);
    /// Integrates the density over `field`'s solid (clipped to `clip`) and stores both maps.
    void store(Solid& solid, const geometry::DistanceField& field, std::optional<Box> clip);
    Boundary() = default;
    std::vector<Solid> solids_;
    std::vector<glm::vec4> nodes_;
    float margin_ = 0.0f, stride_ = 0.0f;
    float margin_of_map_ = 0.0f;  ///< how far a map reaches beyond its solid (its exact band)
    Box domain_;
    float h_ = 0.0f, poly6_coeff_ = 0.0f, phi_ = 0.0f;
};

}  // namespace aquaform
