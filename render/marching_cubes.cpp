#include "render/marching_cubes.h"

#include <cmath>
#include <stdexcept>

#include "core/error.h"

namespace aquaform {

namespace {

using shader::mesh_corner;
using shader::mesh_edge_axis;
using shader::mesh_edge_origin;

/// The cell edge between corners p and q (which differ along one axis).
uint32_t edge_between(uint32_t p, uint32_t q) {
    const glm::uvec3 a = mesh_corner(p), b = mesh_corner(q);
    const glm::uvec3 lo = glm::min(a, b);
    const uint32_t axis = a.x != b.x ? 0u : a.y != b.y ? 1u : 2u;
    const uint32_t k = axis == 0 ? lo.y + 2 * lo.z : axis == 1 ? lo.x + 2 * lo.z : lo.x + 2 * lo.y;
    return axis * 4 + k;
}

glm::vec3 edge_midpoint(uint32_t e) {
    glm::vec3 p(mesh_edge_origin(e));
    p[mesh_edge_axis(e)] += 0.5f;
    return p;
}

struct Face {
    std::array<uint32_t, 4> corners;  // in order around the face
    glm::vec3 outward;
};

std::array<Face, 6> cube_faces() {
    std::array<Face, 6> faces{};
    for (uint32_t axis = 0; axis < 3; ++axis)
        for (uint32_t side = 0; side < 2; ++side) {
            const uint32_t u = (axis + 1) % 3, v = (axis + 2) % 3;
            const glm::uvec2 around[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            Face& f = faces[axis * 2 + side];
            for (int i = 0; i < 4; ++i) f.corners[i] = (side << axis) | (around[i].x << u) | (around[i].y << v);
            f.outward = glm::vec3(0.0f);
            f.outward[axis] = side ? 1.0f : -1.0f;
        }
    return faces;
}

/// Whether cell edges a and b lie on one face of the cell.
bool on_one_face(uint32_t a, uint32_t b) {
    for (const Face& f : cube_faces()) {
        int found = 0;
        for (uint32_t i = 0; i < 4; ++i) {
            const uint32_t e = edge_between(f.corners[i], f.corners[(i + 1) % 4]);
            found += e == a || e == b;
        }
        if (found == 2) return true;
    }
    return false;
}

/// Triangles over a loop (in its order) whose diagonals never join two vertices on one face of
/// the cell: such a chord could also be drawn by the cell across that face, and an edge of
/// three or four triangles would not be a surface. Between vertices on one face, only the loop's
/// own segments (shared with the neighbour, once each way) are edges. A fan would draw such
/// chords where a loop passes both segments of an ambiguous face; the search finds another
/// triangulation (every loop of the 256 cases has one; make_table checks).
bool triangulate(const std::vector<uint32_t>& loop, std::vector<uint32_t>& out) {
    const size_t n = loop.size();
    if (n < 3) return n == 0;
    if (n == 3) {
        out.insert(out.end(), loop.begin(), loop.end());
        return true;
    }
    // The triangle on the side (loop[0], loop[1]) has its apex at some k; both new sides must be
    // allowed diagonals (or sides of the loop).
    for (size_t k = 2; k < n; ++k) {
        if (k != n - 1 && on_one_face(loop[0], loop[k])) continue;
        if (k != 2 && on_one_face(loop[1], loop[k])) continue;
        const size_t mark = out.size();
        out.insert(out.end(), {loop[0], loop[1], loop[k]});
        const std::vector<uint32_t> right(loop.begin() + 1, loop.begin() + k + 1);
        std::vector<uint32_t> left(loop.begin() + k, loop.end());
        left.push_back(loop[0]);
        if ((right.size() < 3 || triangulate(right, out)) && (left.size() < 3 || triangulate(left, out))) return true;
        out.resize(mark);
    }
    return false;
}

/// The triangles of one corner pattern (3 edges each), oriented by `flip`.
std::vector<uint32_t> case_triangles(uint32_t pattern, bool flip) {
    auto inside = [&](uint32_t c) { return (pattern >> c) & 1u; };
    std::array<int, 12> next;
    next.fill(-1);
    // A segment from edge a to edge b with the inside corner c on its left, seen from outside.
    auto add_segment = [&](const Face& f, uint32_t a, uint32_t b, uint32_t c) {
        const glm::vec3 p = edge_midpoint(a), q = edge_midpoint(b), corner(mesh_corner(c));
        if (glm::dot(glm::cross(q - p, corner - p), f.outward) < 0.0f) std::swap(a, b);
        if (next[a] != -1)
            throw internal_failure("marching cubes table: edge " + std::to_string(a) + " starts two segments");
        next[a] = int(b);
    };
    for (const Face& f : cube_faces()) {
        std::vector<uint32_t> crossings;  // positions i: the edge from corner i to corner i + 1
        for (uint32_t i = 0; i < 4; ++i)
            if (inside(f.corners[i]) != inside(f.corners[(i + 1) % 4])) crossings.push_back(i);
        auto edge_at = [&](uint32_t i) { return edge_between(f.corners[i % 4], f.corners[(i + 1) % 4]); };
        if (crossings.size() == 2) {
            uint32_t in = 0;
            while (!inside(f.corners[in])) ++in;
            add_segment(f, edge_at(crossings[0]), edge_at(crossings[1]), f.corners[in]);
        } else if (crossings.size() == 4) {
            // Ambiguous: each inside corner is cut off by the segment between its own two edges.
            for (uint32_t i = 0; i < 4; ++i)
                if (inside(f.corners[i])) add_segment(f, edge_at(i + 3), edge_at(i), f.corners[i]);
        }
    }
    std::vector<uint32_t> triangles;
    std::array<bool, 12> done{};
    for (uint32_t start = 0; start < 12; ++start) {
        if (next[start] == -1 || done[start]) continue;
        std::vector<uint32_t> loop;
        for (uint32_t e = start; !done[e]; e = uint32_t(next[e])) {
            done[e] = true;
            loop.push_back(e);
        }
        const size_t before = triangles.size();
        if (!triangulate(loop, triangles))
            throw internal_failure("marching cubes table: case " + std::to_string(pattern) + " has a loop of " +
                                   std::to_string(loop.size()) + " edges with no triangulation inside the cell");
        if (flip)
            for (size_t t = before; t < triangles.size(); t += 3) std::swap(triangles[t + 1], triangles[t + 2]);
    }
    return triangles;
}

MarchingCubesTable make_table() {
    // Orientation: the fan's normal by the right-hand rule must point away from the fluid. With
    // only corner 0 inside, the triangle must face away from corner 0, towards +(1, 1, 1).
    const std::vector<uint32_t> probe = case_triangles(1u, false);
    const glm::vec3 a = edge_midpoint(probe[0]), b = edge_midpoint(probe[1]), c = edge_midpoint(probe[2]);
    const bool flip = glm::dot(glm::cross(b - a, c - a), glm::vec3(1.0f)) < 0.0f;
    MarchingCubesTable table{};
    for (uint32_t pattern = 0; pattern < 256; ++pattern) {
        const std::vector<uint32_t> edges = case_triangles(pattern, flip);
        const uint32_t count = uint32_t(edges.size() / 3);
        if (count > MESH_MAX_CELL_TRIANGLES)
            throw internal_failure("marching cubes table: case " + std::to_string(pattern) + " has " +
                                   std::to_string(count) + " triangles, more than MESH_MAX_CELL_TRIANGLES");
        uint32_t* row = &table[pattern * MESH_TABLE_ROW];
        row[0] = count;
        for (size_t i = 0; i < edges.size(); ++i) row[1 + i] = edges[i];
    }
    return table;
}

}  // namespace

const MarchingCubesTable& marching_cubes_table() {
    static const MarchingCubesTable table = make_table();
    return table;
}

namespace {

/// Central differences of the samples (one-sided on the lattice's border), per voxel.
glm::vec3 lattice_gradient(const DensityVolume& v, glm::uvec3 s) {
    glm::vec3 g;
    for (int a = 0; a < 3; ++a) {
        glm::uvec3 lo = s, hi = s;
        if (s[a] > 0) --lo[a];
        if (s[a] + 1 < v.dims[a]) ++hi[a];
        g[a] = (v.at(hi.x, hi.y, hi.z) - v.at(lo.x, lo.y, lo.z)) / float(hi[a] - lo[a]);
    }
    return g;
}

}  // namespace

SurfaceMesh marching_cubes(const DensityVolume& volume) {
    SurfaceMesh mesh;
    mesh.origin = volume.origin;
    mesh.voxel = volume.voxel;
    mesh.dims = volume.dims;
    const glm::uvec3 d = volume.dims;
    if (d.x < 2 || d.y < 2 || d.z < 2) return mesh;
    if (volume.values.size() != volume.sample_count())
        throw internal_failure("marching cubes: the volume holds " + std::to_string(volume.values.size()) +
                               " values for " + std::to_string(volume.sample_count()) + " samples");
    auto inside = [&](uint32_t i, uint32_t j, uint32_t k) { return volume.at(i, j, k) >= volume.iso; };
    // Vertices: per sample in order, its crossing edges along +x, +y, +z.
    std::vector<uint32_t> first_vertex(volume.sample_count(), 0);
    for (uint32_t k = 0; k < d.z; ++k)
        for (uint32_t j = 0; j < d.y; ++j)
            for (uint32_t i = 0; i < d.x; ++i) {
                first_vertex[volume.index(i, j, k)] = uint32_t(mesh.vertices.size());
                const glm::uvec3 s{i, j, k};
                for (uint32_t a = 0; a < 3; ++a) {
                    glm::uvec3 n = s;
                    if (++n[a] >= d[a] || inside(i, j, k) == inside(n.x, n.y, n.z)) continue;
                    const float v0 = volume.at(i, j, k), v1 = volume.at(n.x, n.y, n.z);
                    const float t = glm::clamp((volume.iso - v0) / (v1 - v0), 0.0f, 1.0f);
                    glm::vec3 local(s);
                    local[a] += t;
                    mesh.vertices.push_back(volume.origin + volume.voxel * local);
                    const glm::vec3 g = glm::mix(lattice_gradient(volume, s), lattice_gradient(volume, n), t);
                    glm::vec3 outward(0.0f);
                    outward[a] = v0 >= volume.iso ? 1.0f : -1.0f;  // where the gradient vanishes
                    const float len = glm::length(g);
                    mesh.normals.push_back(len > 0.0f ? -g / len : outward);
                }
            }
    // The vertex on cell edge e of the cell at s.
    auto edge_vertex = [&](glm::uvec3 s, uint32_t e) {
        const glm::uvec3 o = s + mesh_edge_origin(e);
        const uint32_t axis = mesh_edge_axis(e);
        uint32_t before = 0;  // crossing edges of sample o along lower axes
        for (uint32_t a = 0; a < axis; ++a) {
            glm::uvec3 n = o;
            ++n[a];
            before += n[a] < d[a] && inside(o.x, o.y, o.z) != inside(n.x, n.y, n.z);
        }
        return first_vertex[volume.index(o.x, o.y, o.z)] + before;
    };
    const MarchingCubesTable& table = marching_cubes_table();
    for (uint32_t k = 0; k + 1 < d.z; ++k)
        for (uint32_t j = 0; j + 1 < d.y; ++j)
            for (uint32_t i = 0; i + 1 < d.x; ++i) {
                const glm::uvec3 s{i, j, k};
                uint32_t pattern = 0;
                for (uint32_t c = 0; c < 8; ++c) {
                    const glm::uvec3 p = s + mesh_corner(c);
                    pattern |= uint32_t(inside(p.x, p.y, p.z)) << c;
                }
                const uint32_t* row = &table[pattern * MESH_TABLE_ROW];
                for (uint32_t t = 0; t < row[0]; ++t)
                    mesh.triangles.emplace_back(edge_vertex(s, row[1 + 3 * t]), edge_vertex(s, row[2 + 3 * t]),
                                                edge_vertex(s, row[3 + 3 * t]));
            }
    return mesh;
}

}  // namespace aquaform
