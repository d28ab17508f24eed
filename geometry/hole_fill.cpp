#include "geometry/hole_fill.h"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <unordered_map>

#include "geometry/mesh.h"

namespace aquaform::geometry {

namespace {

uint64_t undirected_key(uint32_t a, uint32_t b) { return (uint64_t{std::min(a, b)} << 32) | std::max(a, b); }

struct LoopEdge {
    uint32_t from, to;
};

// The boundary edges of `mesh` as closed loops, each visiting a vertex once, and the count of those
// on chains that do not close. Each boundary edge is walked against the face that uses it: a cap
// that follows the loop then runs every edge the other way, as neighbours on a closed, consistently
// oriented surface do.
std::vector<std::vector<LoopEdge>> boundary_loops(const Mesh& mesh, size_t& boundary_edges, size_t& open_edges) {
    struct EdgeUse {
        uint32_t faces = 0;
        uint32_t from = 0, to = 0;  // the direction the (last) face using it runs it
    };
    const std::vector<uint32_t> ids = welded_vertex_ids(mesh);
    std::unordered_map<uint64_t, EdgeUse> edges;
    edges.reserve(mesh.faces.size() * 2);
    for (const glm::uvec3& corners : mesh.faces) {
        const glm::uvec3 face(ids[corners.x], ids[corners.y], ids[corners.z]);
        if (face.x == face.y || face.y == face.z || face.z == face.x) continue;
        for (int i = 0; i < 3; ++i) {
            EdgeUse& use = edges[undirected_key(face[i], face[(i + 1) % 3])];
            ++use.faces;
            use.from = face[i];
            use.to = face[(i + 1) % 3];
        }
    }
    std::vector<LoopEdge> loop_edges;
    for (const auto& [key, use] : edges)
        if (use.faces == 1) loop_edges.push_back({use.to, use.from});
    edges.clear();
    boundary_edges = loop_edges.size();
    open_edges = 0;
    // Sorted by start vertex (then end, for a result independent of the hash map's order).
    std::sort(loop_edges.begin(), loop_edges.end(),
              [](const LoopEdge& a, const LoopEdge& b) { return a.from != b.from ? a.from < b.from : a.to < b.to; });
    std::unordered_map<uint32_t, uint32_t> first_out;  // vertex -> its first loop edge in the sorted list
    for (uint32_t e = uint32_t(loop_edges.size()); e-- > 0;) first_out[loop_edges[e].from] = e;
    std::vector<uint8_t> used(loop_edges.size(), 0);
    const auto unused_edge_from = [&](uint32_t v) -> std::optional<uint32_t> {
        const auto found = first_out.find(v);
        if (found == first_out.end()) return std::nullopt;
        for (uint32_t e = found->second; e < loop_edges.size() && loop_edges[e].from == v; ++e)
            if (!used[e]) return e;
        return std::nullopt;
    };
    // Where loops touch at a vertex (two holes meeting at a corner, or one hole's rim touching
    // itself), which way the walk leaves it cannot be read from the faces (the holes between them
    // have none). So the walk takes any edge on, and is split wherever it comes back to a vertex it
    // is still on: each piece between two visits runs around one hole, whichever way was taken.
    std::vector<std::vector<LoopEdge>> loops;
    std::vector<LoopEdge> walk;
    std::unordered_map<uint32_t, size_t> on_walk;  // vertex -> the walk's edge that leaves it
    for (uint32_t start = 0; start < loop_edges.size(); ++start) {
        if (used[start]) continue;
        for (std::optional<uint32_t> next = start; next;) {
            used[*next] = 1;
            const LoopEdge edge = loop_edges[*next];
            on_walk[edge.from] = walk.size();
            walk.push_back(edge);
            if (const auto back = on_walk.find(edge.to); back != on_walk.end()) {
                const size_t first = back->second;
                for (size_t i = first; i < walk.size(); ++i) on_walk.erase(walk[i].from);
                loops.emplace_back(walk.begin() + std::ptrdiff_t(first), walk.end());
                walk.resize(first);
            }
            next = unused_edge_from(edge.to);
        }
        open_edges += walk.size();  // a chain that did not close (non-manifold or unoriented edges)
        walk.clear();
        on_walk.clear();
    }
    return loops;
}

}  // namespace

HoleClosing close_holes(Mesh& mesh) {
    HoleClosing closing;
    const std::vector<std::vector<LoopEdge>> loops = boundary_loops(mesh, closing.boundary_edges, closing.open_edges);
    // Each loop is capped by a fan from its centroid (a new vertex), not by ear clipping: the fan
    // closes any loop, planar or not, convex or not, in O(n). Where a planar loop is concave the fan
    // folds over itself, but within the loop's plane, so the closed surface's winding number
    // (Jacobson et al. 2013) differs from that of any other planar cap only on the plane; a
    // cap differs from another only in the volume between the two. Ear clipping needs a plane to
    // clip in and fails on loops that are not simple there.
    const Box box = mesh.bounds();
    const glm::dvec3 diagonal = glm::dvec3(box.max) - glm::dvec3(box.min);
    const double min_area = 1e-12 * glm::dot(diagonal, diagonal);  // as check_mesh's degenerate faces
    for (const std::vector<LoopEdge>& loop : loops) {
        glm::dvec3 centre(0.0);
        for (const LoopEdge& e : loop) centre += glm::dvec3(mesh.vertices[e.from]);
        centre /= double(loop.size());
        glm::dvec3 vector_area(0.0);
        double cap_area = 0.0;
        for (const LoopEdge& e : loop) {
            const glm::dvec3 half =
                0.5 * glm::cross(glm::dvec3(mesh.vertices[e.from]) - centre, glm::dvec3(mesh.vertices[e.to]) - centre);
            vector_area += half;
            cap_area += glm::length(half);
        }
        if (cap_area <= min_area) {  // the rim of a sliver (a degenerate face): its cap would be one too
            closing.open_edges += loop.size();
            continue;
        }
        if (loop.size() == 3) {  // a triangle needs no centre
            mesh.faces.emplace_back(loop[0].from, loop[1].from, loop[2].from);
            cap_area = glm::length(vector_area);
            closing.added_faces += 1;
        } else {
            const uint32_t middle = uint32_t(mesh.vertices.size());
            mesh.vertices.emplace_back(centre);
            for (const LoopEdge& e : loop) mesh.faces.emplace_back(middle, e.from, e.to);
            closing.added_vertices += 1;
            closing.added_faces += loop.size();
        }
        closing.holes.push_back({loop.size(), centre, glm::length(vector_area)});
        closing.loop_area += glm::length(vector_area);
        closing.cap_area += cap_area;
    }
    std::stable_sort(closing.holes.begin(), closing.holes.end(),
                     [](const ClosedHole& a, const ClosedHole& b) { return a.area > b.area; });
    return closing;
}

void record_closing(const HoleClosing& closing, MeshReport& report) {
    report.closed_hole_count = closing.holes.size();
    report.closed_boundary_edge_count = closing.boundary_edges - closing.open_edges;
    report.closed_hole_area = closing.loop_area;
    report.cap_area = closing.cap_area;
    const size_t listed = std::min(closing.holes.size(), MeshReport::kMaxListed);
    report.closed_holes.assign(closing.holes.begin(), closing.holes.begin() + std::ptrdiff_t(listed));
}

}  // namespace aquaform::geometry
