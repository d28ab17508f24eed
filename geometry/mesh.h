// Triangle meshes for mesh-controlled flow (Karpati et al., section 3.2): OBJ input, sanity checks and
// placement in the scene. Hard input errors are refused with a message naming the file, the line and
// the element; meshes without a meaningful inside (flat, one open sheet, faces that cancel out) are
// refused; faces flipped against their neighbours are turned back and holes are closed with caps
// (geometry/hole_fill.h), both reported; problems the inside test tolerates (duplicated vertices,
// non-manifold edges, ...) are only reported.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <glm/glm.hpp>

#include "core/box.h"
#include "core/result.h"

namespace aquaform::geometry {

/// Indexed triangle mesh as it came from the file (after triangulation). Kept separate from the
/// OpenMesh half-edge structure because OpenMesh drops faces it cannot represent (non-manifold or
/// inconsistently oriented), while the inside test must still see every triangle.
struct Mesh {
    std::vector<glm::vec3> vertices;
    std::vector<glm::uvec3> faces;

    /// Three consecutive points per triangle, the input of the inside test and of place_inside().
    std::vector<glm::vec3> triangle_soup() const;
    /// Axis-aligned bounds of the vertices; min = max = 0 for a mesh without vertices.
    Box bounds() const;
};

using HalfEdgeMesh = OpenMesh::TriMesh_ArrayKernelT<>;

/// The mesh in OpenMesh's half-edge form. Faces OpenMesh refuses ("complex" faces: they would make an
/// edge or vertex non-manifold, or they are oriented against their neighbours) and faces with a repeated
/// vertex index are left out; their indices go to `rejected_faces` when it is given.
HalfEdgeMesh to_half_edge_mesh(const Mesh& mesh, std::vector<uint32_t>* rejected_faces = nullptr);

/// One boundary loop that load_obj() closed with a cap (geometry/hole_fill.h).
struct ClosedHole {
    size_t edges = 0;        ///< boundary edges around the hole
    glm::dvec3 centre{0.0};  ///< the mean of its corners: where the cap's fan meets
    double area = 0.0;       ///< |vector area| of its loop: the area of a flat patch over it
};

/// Problems that do not stop the mesh from being used, each as a count plus the first few offenders.
/// For a mesh from load_obj() the counts describe the mesh as used, its caps included; the closed_*
/// fields say what was closed.
struct MeshReport {
    static constexpr size_t kMaxListed = 8;  ///< how many offending indices each list keeps

    size_t vertex_count = 0;
    size_t face_count = 0;
    // Edges are counted between positions: vertices at the same position (a seam) count as one.
    size_t boundary_edge_count = 0;        ///< edges with one face: holes, so not closed
    size_t non_manifold_edge_count = 0;    ///< edges shared by three or more faces
    size_t non_manifold_vertex_count = 0;  ///< vertices whose faces do not form one fan (OpenMesh)
    size_t inconsistent_edge_count = 0;    ///< edges that two faces traverse in the same direction
    size_t rejected_face_count = 0;        ///< faces OpenMesh could not add (non-manifold or flipped)
    size_t degenerate_face_count = 0;      ///< zero-area faces (area < 1e-12 * bbox diagonal^2)
    size_t duplicated_vertex_count = 0;    ///< vertices at exactly the position of an earlier vertex
    double signed_volume = 0.0;            ///< sum of signed tetrahedron volumes; < 0: normals face inward
    double surface_area = 0.0;
    glm::dvec3 bounds_size{0.0};            ///< extent of the vertices' bounding box
    size_t hole_count = 0;                  ///< connected groups of boundary edges
    double hole_area = 0.0;                 ///< sum over holes of |vector area| of their boundary loops
    size_t reoriented_face_count = 0;       ///< faces load_obj() turned to agree with their neighbours
    size_t closed_hole_count = 0;           ///< boundary loops load_obj() closed with caps
    size_t closed_boundary_edge_count = 0;  ///< boundary edges around them
    double closed_hole_area = 0.0;          ///< sum over them of |vector area| of their loops
    double cap_area = 0.0;                  ///< area of the caps' triangles (part of surface_area)
    std::vector<ClosedHole> closed_holes;   ///< the largest few (by area), largest first

    std::vector<glm::uvec2> boundary_edges;      ///< vertex index pairs
    std::vector<glm::uvec2> non_manifold_edges;  ///< vertex index pairs
    std::vector<uint32_t> non_manifold_vertices;
    std::vector<glm::uvec2> inconsistent_edges;  ///< vertex index pairs
    std::vector<uint32_t> rejected_faces;
    std::vector<uint32_t> degenerate_faces;
    std::vector<uint32_t> duplicated_vertices;  ///< the later copy of each duplicated position

    bool inward_facing() const { return signed_volume < 0.0; }
    /// The surface as the file had it, without the caps load_obj() added.
    double surface_area_as_read() const { return surface_area - cap_area; }
    /// The area a flat patch over each hole still open would need, against the surface as read.
    double hole_fraction() const { return share_of_surface(hole_area); }
    /// The same for the holes load_obj() closed.
    double closed_hole_fraction() const { return share_of_surface(closed_hole_area); }
    /// Closed, manifold and consistently oriented as read: false where load_obj() had to close holes
    /// (the mesh it returns is then closed), so that callers that note an imperfect file note it.
    bool watertight() const;

private:
    double share_of_surface(double area) const {
        return surface_area_as_read() > 0.0 ? area / surface_area_as_read() : 0.0;
    }
};

MeshReport check_mesh(const Mesh& mesh);

/// Per vertex, the first vertex at exactly its position: the checks, the orientation walk and the
/// hole closing see through seams where an exporter split the surface, which are not holes.
std::vector<uint32_t> welded_vertex_ids(const Mesh& mesh);

/// Turns faces so that every face agrees with its neighbours across manifold edges (walking each
/// connected part from face to face); each part keeps the orientation most of its area had (on a tie,
/// the one with positive volume), so a part authored inward (a cavity) stays so. Returns how many
/// faces were turned.
size_t orient_consistently(Mesh& mesh);

/// A mesh whose holes (closed or open) would need caps of at least this share of its own surface is
/// one open sheet, not a solid, and is refused: capping a flat sheet gives its own mirror image, and
/// a sheet bent less than ~25 degrees (a spherical cap of half-angle 26 degrees: (1 + cos) / 2 = 0.95)
/// a lens far thinner than it is wide. A bowl (50 %), a box without a lid (20 %) or a scan's open
/// base (~2 %) are far below it.
inline constexpr double kOpenSheetHoleFraction = 0.95;
/// The smallest mesh (its bounding box's diagonal, in the file's units): placement, the lattice
/// and the solver work in single precision, where lengths of 1e-30 square to nothing. (The
/// largest is bounded by the reader: coordinates beyond +-1e6 are refused.)
inline constexpr double kMinMeshDiagonal = 1e-6;
/// Why the mesh has no meaningful inside for placement or as an obstacle (too small, flat, one open
/// sheet, faces that cancel out), with the fix; empty when it can be used. Holes alone are no reason:
/// load_obj() closes them. The volume is judged only once no hole that encloses area is open.
std::string unusable_reason(const MeshReport& report);
/// Multi-line human-readable summary of the report, one problem per line with the first offenders.
std::string describe(const MeshReport& report);

struct LoadedMesh {
    Mesh mesh;
    MeshReport report;
};

/// Coordinates beyond this magnitude are refused: float spacing there is > 0.06 units, so the
/// geometry no longer means anything at simulation scale.
inline constexpr double kMaxMeshCoordinate = 1e6;

/// A Wavefront OBJ as the file has it (polygons are triangulated), refused as load_obj() says
/// below for what the text alone shows (load_obj() is this, repaired and checked).
Result<Mesh> read_obj(const std::filesystem::path& path);

/// Load a Wavefront OBJ (polygons are triangulated), orient its faces consistently, close its holes
/// (close_holes(), recorded in the report's closed_* fields) and check it (geometry/mesh_load.cpp).
/// Refuses missing, unreadable, binary or UTF-16 files, any line that is not valid OBJ (a number that
/// is not finite or too large, an index that is 0, fractional or out of range, a face with fewer than
/// three corners, ...; the message names the line, 1-based), meshes without faces, and meshes that
/// unusable_reason() rejects. Shows progress on a large file; stops with an error when interrupted().
Result<LoadedMesh> load_obj(const std::filesystem::path& path);

/// Write vertices and faces as OBJ (1-based indices), e.g. for generated primitives.
Result<bool> write_obj(const std::filesystem::path& path, const Mesh& mesh);

/// Where a mesh goes in the scene. Without fit_into: scale, then rotate (Euler degrees about X, then Y,
/// then Z), then translate. With fit_into: rotate, then scale uniformly and centre so that the bounding
/// box fits inside the box with its aspect ratio kept; `scale` and `position` are then ignored.
struct MeshPlacement {
    glm::vec3 position{0.0f};
    glm::vec3 rotation_degrees{0.0f};
    float scale = 1.0f;
    std::optional<Box> fit_into;
};

void apply(const MeshPlacement& placement, Mesh& mesh);

}  // namespace aquaform::geometry
