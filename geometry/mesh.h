// Triangle meshes for mesh-controlled flow (Karpati et al., section 3.2): OBJ input, sanity checks and
// placement in the scene. Hard input errors are refused with a message naming the file, the line and
// the element; meshes that cannot be filled (no volume, large holes) are refused; faces flipped against
// their neighbours are turned back and reported; problems the inside test tolerates (small holes,
// duplicated vertices, ...) are only reported.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <glm/glm.hpp>

#include "core/result.h"
#include "core/box.h"

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

/// Problems that do not stop the mesh from being used, each as a count plus the first few offenders.
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
    glm::dvec3 bounds_size{0.0};         ///< extent of the vertices' bounding box
    size_t hole_count = 0;                 ///< connected groups of boundary edges
    double hole_area = 0.0;                ///< sum over holes of |vector area| of their boundary loops
    size_t reoriented_face_count = 0;      ///< faces load_obj() turned to agree with their neighbours

    std::vector<glm::uvec2> boundary_edges;      ///< vertex index pairs
    std::vector<glm::uvec2> non_manifold_edges;  ///< vertex index pairs
    std::vector<uint32_t> non_manifold_vertices;
    std::vector<glm::uvec2> inconsistent_edges;  ///< vertex index pairs
    std::vector<uint32_t> rejected_faces;
    std::vector<uint32_t> degenerate_faces;
    std::vector<uint32_t> duplicated_vertices;  ///< the later copy of each duplicated position

    bool inward_facing() const { return signed_volume < 0.0; }
    /// The area a flat patch over each hole would need, against the surface: 0 for a closed mesh.
    double hole_fraction() const { return surface_area > 0.0 ? hole_area / surface_area : 0.0; }
    /// Closed, manifold and consistently oriented: a ray-parity inside test would be reliable.
    bool watertight() const;
};

MeshReport check_mesh(const Mesh& mesh);

/// Turns faces so that every face agrees with its neighbours across manifold edges (walking each
/// connected part from face to face); each part keeps the orientation most of its area had (on a tie,
/// the one with positive volume), so a part authored inward (a cavity) stays so. Returns how many
/// faces were turned.
size_t orient_consistently(Mesh& mesh);

/// Holes bigger than this share of the surface make a mesh unusable: the winding number inside the
/// mesh falls towards 0.5 and the raster fill leaves every column through a hole empty.
inline constexpr double kMaxHoleFraction = 0.01;
/// The smallest mesh (its bounding box's diagonal, in the file's units): placement, the lattice
/// and the solver work in single precision, where lengths of 1e-30 square to nothing. (The
/// largest is bounded by the reader: coordinates beyond +-1e6 are refused.)
inline constexpr double kMinMeshDiagonal = 1e-6;
/// Why the inside test and the raster fill cannot use the mesh (no volume, large holes), with the
/// fix; empty when it can be used.
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

/// Load a Wavefront OBJ (polygons are triangulated), orient its faces consistently and check it.
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
