// Closing the holes of an open mesh when it is loaded, so that every inside decision downstream (the
// ray crossings of InsideTest and its generalized winding number, the raster fill's winding count per
// column, the distance field's sign, an obstacle's solid start) sees a closed surface. Scanned and
// modelled meshes have holes (the Stanford bunny's open base, a head's open eyes, a lid that does not
// meet its pot); the winding number of an open surface (Jacobson et al. 2013) drifts towards 0.5 near
// a large hole, and a column through one has no way out, so capping them is what makes them usable.
#pragma once

#include <cstddef>
#include <vector>

namespace aquaform::geometry {

struct Mesh;
struct MeshReport;
struct ClosedHole;

/// What close_holes() did.
struct HoleClosing {
    std::vector<ClosedHole> holes;  ///< every loop capped, largest area first
    size_t boundary_edges = 0;      ///< edges with one face before the closing
    size_t open_edges = 0;          ///< boundary edges left open: on no closed loop, or around no area
    size_t added_vertices = 0;
    size_t added_faces = 0;
    double loop_area = 0.0;  ///< sum of the holes' |vector area|
    double cap_area = 0.0;   ///< sum of the added triangles' areas
};

/// Caps every boundary loop of `mesh` (edges used by one face, on welded_vertex_ids()). Each loop is
/// walked against the face that uses each of its edges, so the cap runs every edge opposite to that
/// face and the closed surface stays consistently oriented (orient_consistently() first). Where
/// holes touch at a vertex the walk is split there, one loop and one cap per hole. A chain that does
/// not come back to its start (only where edges are non-manifold or cannot be oriented) and a loop
/// around no area (the rim of a degenerate face) are left open and counted in `open_edges`.
HoleClosing close_holes(Mesh& mesh);

/// Records `closing` in the closed_* fields of `report`, a check_mesh() of the closed mesh.
void record_closing(const HoleClosing& closing, MeshReport& report);

}  // namespace aquaform::geometry
