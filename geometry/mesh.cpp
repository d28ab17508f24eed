#include "geometry/mesh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <numeric>
#include <span>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include <OpenMesh/Core/System/omstream.hh>
#include <glm/gtc/matrix_transform.hpp>

#include "core/file_write.h"
#include "core/host_memory.h"
#include "core/interrupt.h"
#include "core/progress.h"

namespace aquaform::geometry {

namespace {

uint64_t edge_key(uint32_t a, uint32_t b) { return (uint64_t{std::min(a, b)} << 32) | std::max(a, b); }

glm::uvec2 edge_from_key(uint64_t key) {
    return {static_cast<uint32_t>(key >> 32), static_cast<uint32_t>(key & 0xffffffffu)};
}

bool has_repeated_index(const glm::uvec3& face) { return face.x == face.y || face.y == face.z || face.z == face.x; }

template <typename T>
void keep_first(std::vector<T>& list, size_t count) {
    if (list.size() > count) list.resize(count);
}

Error mesh_error(const std::filesystem::path& path, const std::string& problem, const std::string& fix) {
    return Error{"mesh '" + path.string() + "': " + problem + "; " + fix};
}

std::string format_number(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

// A token echoed back in a message: printable ASCII only, at most 24 characters, so binary junk
// cannot break the one-line message.
std::string shown(std::string_view token) {
    std::string out;
    for (const char c : token.substr(0, 24)) out += (c >= 32 && c < 127) ? c : '?';
    return token.size() > 24 ? out + "..." : out;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Concave polygons with more corners than this are refused: ear clipping is O(n^2) or worse.
constexpr size_t kMaxEarClipCorners = 256;

// Convex (or flat-degenerate) polygons as a fan; concave ones by ear clipping in the plane of the
// Newell normal. False for a concave polygon too large to clip.
bool triangulate(const std::vector<glm::vec3>& vertices, const std::vector<uint32_t>& corners,
                 std::vector<glm::uvec3>& faces) {
    const size_t n = corners.size();
    const auto fan = [&](const std::vector<size_t>& ring) {
        for (size_t k = 1; k + 1 < ring.size(); ++k)
            faces.emplace_back(corners[ring[0]], corners[ring[k]], corners[ring[k + 1]]);
    };
    std::vector<size_t> ring(n);
    std::iota(ring.begin(), ring.end(), size_t{0});
    glm::dvec3 normal(0.0);
    for (size_t i = 0; i < n; ++i) {
        const glm::dvec3 a(vertices[corners[i]]), b(vertices[corners[(i + 1) % n]]);
        normal += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    const glm::dvec3 size = glm::abs(normal);
    const int drop = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
    const double sign = normal[drop] >= 0.0 ? 1.0 : -1.0;
    std::vector<glm::dvec2> p(n);
    for (size_t i = 0; i < n; ++i) p[i] = {vertices[corners[i]][(drop + 1) % 3], vertices[corners[i]][(drop + 2) % 3]};
    const auto turn = [&](size_t a, size_t b, size_t c) {
        return sign * ((p[b].x - p[a].x) * (p[c].y - p[a].y) - (p[b].y - p[a].y) * (p[c].x - p[a].x));
    };
    // Convex where no corner turns the other way by more than the corners' own rounding: the file's
    // coordinates are floats, so a corner can sit up to an ulp of the largest coordinate off its
    // line, and a polygon of 100,000 corners on a circle turns by ~1e-10 per corner, below that.
    double largest = 0.0;
    for (const glm::dvec2& q : p) largest = std::max({largest, std::abs(q.x), std::abs(q.y)});
    const double rounding = 4.0 * largest * double(std::numeric_limits<float>::epsilon());
    bool convex = true;
    for (size_t i = 0; i < n && convex; ++i) {
        const size_t b = (i + 1) % n, c = (i + 2) % n;
        const double reach = glm::length(p[b] - p[i]) + glm::length(p[c] - p[b]);
        convex = turn(i, b, c) >= -rounding * reach;
    }
    if (convex || normal == glm::dvec3(0.0)) return fan(ring), true;
    if (n > kMaxEarClipCorners) return false;
    while (ring.size() > 3) {
        bool clipped = false;
        for (size_t i = 0; i < ring.size() && !clipped; ++i) {
            const size_t a = ring[(i + ring.size() - 1) % ring.size()], b = ring[i], c = ring[(i + 1) % ring.size()];
            if (turn(a, b, c) <= 0.0) continue;
            bool empty = true;
            for (size_t k : ring)
                if (k != a && k != b && k != c && turn(a, b, k) >= 0.0 && turn(b, c, k) >= 0.0 && turn(c, a, k) >= 0.0)
                    empty = false;
            if (!empty) continue;
            faces.emplace_back(corners[a], corners[b], corners[c]);
            ring.erase(ring.begin() + std::ptrdiff_t(i));
            clipped = true;
        }
        if (!clipped) break;  // self-intersecting outline: no ear left, the rest becomes a fan
    }
    return fan(ring), true;
}

// Hand-written rather than tinyobjloader, which reads garbage, "nan" and fractional indices as
// numbers, wraps huge indices onto the last vertex and counts nothing in its messages.
class ObjReader {
public:
    ObjReader(const std::filesystem::path& path, std::string_view text) : path_(path), text_(text) {}

    Result<Mesh> read() {
        std::optional<ProgressBar> progress;  // only where reading takes about a second or more
        if (text_.size() > kLargeText) progress.emplace("reading " + path_.filename().string(), text_.size());
        size_t position = 0;
        std::string joined;  // a statement continued over several lines with a trailing backslash
        while (position < text_.size()) {
            ++line_;
            // Lines end with LF, CR LF or (old Mac files) a lone CR.
            const size_t end = std::min(text_.find_first_of("\r\n", position), text_.size());
            std::string_view line = text_.substr(position, end - position);
            position = end + (text_.compare(end, 2, "\r\n") == 0 ? 2 : 1);
            if (!line.empty() && line.back() == '\\') {
                if (joined.empty()) first_line_ = line_;
                joined.append(line.substr(0, line.size() - 1)).push_back(' ');
                continue;
            }
            const size_t reported_line = joined.empty() ? line_ : first_line_;
            if (!joined.empty()) line = joined.append(line);
            if (auto error = statement(line, reported_line)) return *error;
            joined.clear();
            if ((line_ & 0xffff) == 0) {
                if (progress) progress->update(position);
                if (interrupted()) return mesh_error(path_, "interrupted while reading", "run again to load it");
            }
        }
        if (!joined.empty())  // the last line ended with a backslash
            if (auto error = statement(joined, first_line_)) return *error;
        if (progress) progress->finish();
        return std::move(mesh_);
    }

private:
    Error fail(size_t line, const std::string& problem, const std::string& fix) const {
        return mesh_error(path_, "line " + std::to_string(line) + ": " + problem, fix);
    }

    std::optional<Error> statement(std::string_view line, size_t at) {
        if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        std::vector<std::string_view> tokens;
        for (size_t i = 0; i < line.size();) {
            while (i < line.size() && is_space(line[i])) ++i;
            const size_t start = i;
            while (i < line.size() && !is_space(line[i])) ++i;
            if (i > start) tokens.push_back(line.substr(start, i - start));
        }
        if (tokens.empty()) return std::nullopt;
        const std::string_view key = tokens[0];
        const std::span<const std::string_view> values(tokens.begin() + 1, tokens.end());
        if (key == "v") return vertex(values, at);
        if (key == "vt") return numbers(values, at, "texture coordinate", 1, 3, ++texcoords_);
        if (key == "vn") return numbers(values, at, "normal", 3, 3, ++normals_);
        if (key == "f") return face(values, at);
        for (const char* ignored : {"vp", "o", "g", "s", "usemtl", "mtllib", "mg", "l", "p", "lod", "maplib", "usemap",
                                    "shadow_obj", "trace_obj", "bevel", "c_interp", "d_interp"})
            if (key == ignored) return std::nullopt;
        for (const char* freeform : {"cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole",
                                     "scrv", "sp", "end", "con"})
            if (key == freeform)
                return fail(at, "free-form geometry ('" + std::string(key) + "') is not supported",
                            "export the mesh as polygons (triangles or quads)");
        return fail(at, "not an OBJ statement: '" + shown(key) + "'",
                    "remove the line, or export the mesh again as Wavefront OBJ (ASCII or UTF-8)");
    }

    // Strict: the whole token is a number (strtod also reads "inf", "nan" and hex, refused below).
    std::optional<double> number(std::string_view token) const {
        const std::string text(token);
        // Decimal only: strtod also reads hexadecimal ("0x1p3"); "inf" and "nan" get their own message.
        if (text.find_first_not_of("0123456789.eE+-infatyINFATY") != std::string::npos) return std::nullopt;
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size()) return std::nullopt;
        return value;
    }

    std::optional<Error> numbers(std::span<const std::string_view> values, size_t at, const std::string& what,
                                 size_t min_count, size_t max_count, size_t ordinal, double* out = nullptr) {
        const std::string element = what + " " + std::to_string(ordinal);
        if (values.size() < min_count || values.size() > max_count)
            return fail(
                at, element + " has " + std::to_string(values.size()) + (values.size() == 1 ? " number" : " numbers"),
                "it needs " +
                    (min_count == max_count ? std::to_string(min_count)
                                            : std::to_string(min_count) + " to " + std::to_string(max_count)) +
                    (what == "vertex" ? " (x y z, optionally w or r g b)" : "") + "; repair or re-export the mesh");
        for (size_t i = 0; i < values.size(); ++i) {
            const std::optional<double> value = number(values[i]);
            if (!value)
                return fail(at, element + " has '" + shown(values[i]) + "', which is not a number",
                            "write plain decimal numbers, or re-export the mesh");
            if (!std::isfinite(*value))
                return fail(at, element + " has a non-finite number '" + shown(values[i]) + "' (NaN or infinity)",
                            "repair or re-export the mesh; a modelling tool can usually find such vertices");
            if (out && i < 3) {
                if (std::abs(*value) > kMaxMeshCoordinate)
                    return fail(at,
                                element + " has coordinate " + format_number(*value) + ", too large: beyond +-" +
                                    format_number(kMaxMeshCoordinate) + " float precision is meaningless",
                                "scale the mesh down in the modelling tool (the scene placement can scale it up)");
                out[i] = *value;
            }
        }
        return std::nullopt;
    }

    std::optional<Error> vertex(std::span<const std::string_view> values, size_t at) {
        double xyz[3] = {0, 0, 0};
        if (mesh_.vertices.size() >= kMaxVertices)
            return fail(at, "more than " + std::to_string(kMaxVertices) + " vertices", "simplify the mesh");
        if (values.size() == 5)  // neither x y z w nor x y z r g b
            return fail(at, "vertex " + std::to_string(mesh_.vertices.size() + 1) + " has 5 numbers",
                        "it needs x y z, optionally w or r g b; repair or re-export the mesh");
        if (auto error = numbers(values, at, "vertex", 3, 6, mesh_.vertices.size() + 1, xyz)) return error;
        mesh_.vertices.emplace_back(float(xyz[0]), float(xyz[1]), float(xyz[2]));
        return std::nullopt;
    }

    // One index of a corner: 1-based, or negative counting back from the last element defined so far.
    std::optional<Error> index(std::string_view token, size_t defined, const std::string& kind, size_t at,
                               const std::string& where, uint32_t* out) const {
        int64_t value = 0;
        const char* first = token.data() + (!token.empty() && token[0] == '+');
        const auto [end, error] = std::from_chars(first, token.data() + token.size(), value);
        if (token.empty() || end != token.data() + token.size() || error == std::errc::invalid_argument)
            return fail(
                at, where + " has " + kind + " index '" + shown(token) + "', not a whole number",
                "OBJ indices are whole numbers counting from 1 (negative ones count back from the last " + kind + ")");
        const bool too_large = error == std::errc::result_out_of_range;
        if (!too_large && value == 0)
            return fail(at, where + " has " + kind + " index 0",
                        "OBJ indices count from 1 (negative ones count back from the last " + kind + ")");
        const int64_t resolved = value > 0 ? value - 1 : int64_t(defined) + value;
        if (too_large || resolved < 0 || resolved >= int64_t(defined))
            return fail(at,
                        where + " refers to " + kind + " " + shown(token) + " but " + std::to_string(defined) + " " +
                            (defined == 1 ? kind + " is" : (kind == "vertex" ? "vertices" : kind + "s") + " are") +
                            " defined above this line",
                        "correct the index (1 to " + std::to_string(defined) + ", or -1 to -" +
                            std::to_string(defined) + ") or re-export the mesh");
        if (out) *out = uint32_t(resolved);
        return std::nullopt;
    }

    std::optional<Error> face(std::span<const std::string_view> values, size_t at) {
        ++face_number_;
        const std::string element = "face " + std::to_string(face_number_);
        if (values.size() < 3)
            return fail(at,
                        element + " has " + std::to_string(values.size()) + " corner" + (values.size() == 1 ? "" : "s"),
                        "a face needs at least 3 vertex indices ('f 1 2 3'); repair or re-export the mesh");
        std::vector<uint32_t> corners(values.size());
        for (size_t c = 0; c < values.size(); ++c) {
            const std::string where = element + " corner " + std::to_string(c + 1);
            std::string_view parts[3];
            size_t count = 0;
            for (std::string_view rest = values[c];; ++count) {
                const size_t slash = rest.find('/');
                if (count == 3)
                    return fail(at, where + " '" + shown(values[c]) + "' has more than three parts",
                                "write v, v/vt, v//vn or v/vt/vn");
                parts[count] = rest.substr(0, slash);
                if (slash == std::string_view::npos) {
                    ++count;
                    break;
                }
                rest = rest.substr(slash + 1);
            }
            if (auto error = index(parts[0], mesh_.vertices.size(), "vertex", at, where, &corners[c])) return error;
            if (count > 1 && (count == 2 || !parts[1].empty()))
                if (auto error = index(parts[1], texcoords_, "texture coordinate", at, where, nullptr)) return error;
            if (count == 3)
                if (auto error = index(parts[2], normals_, "normal", at, where, nullptr)) return error;
        }
        if (!triangulate(mesh_.vertices, corners, mesh_.faces))
            return fail(at, element + " is a concave polygon with " + std::to_string(corners.size()) + " corners",
                        "triangulate it in the modelling tool (at most " + std::to_string(kMaxEarClipCorners) +
                            " corners are triangulated here)");
        return std::nullopt;
    }

    static constexpr size_t kMaxVertices = size_t(1) << 31;
    static constexpr size_t kLargeText = size_t(32) << 20;

    const std::filesystem::path& path_;
    std::string_view text_;
    Mesh mesh_;
    size_t line_ = 0, first_line_ = 0, face_number_ = 0, texcoords_ = 0, normals_ = 0;
};

// Per vertex, the first vertex at exactly its position (-0 and +0 the same): the topology checks and
// the orientation walk see through seams where an exporter split the surface (per-face normals or
// texture coordinates), which are not holes.
std::vector<uint32_t> welded_ids(const Mesh& mesh) {
    struct PositionHash {
        size_t operator()(const glm::vec3& p) const {
            const auto bits = [](float value) { return std::bit_cast<uint32_t>(value + 0.0f); };
            return (size_t{bits(p.x)} * 73856093u) ^ (size_t{bits(p.y)} * 19349663u) ^ (size_t{bits(p.z)} * 83492791u);
        }
    };
    std::unordered_map<glm::vec3, uint32_t, PositionHash> first_at_position;
    first_at_position.reserve(mesh.vertices.size());
    std::vector<uint32_t> ids(mesh.vertices.size());
    for (uint32_t index = 0; index < mesh.vertices.size(); ++index)
        ids[index] = first_at_position.emplace(mesh.vertices[index], index).first->second;
    return ids;
}

glm::uvec3 weld(const glm::uvec3& face, const std::vector<uint32_t>& ids) {
    return {ids[face.x], ids[face.y], ids[face.z]};
}

// Groups boundary edges into holes (union-find on their vertices) and sums |vector area| of each
// hole's boundary loop: the area a flat patch over it needs. Per hole, so that holes at the two ends
// of a tube do not cancel.
template <typename EdgeMap>
void measure_holes(const Mesh& mesh, const EdgeMap& edges, MeshReport& report) {
    std::unordered_map<uint32_t, uint32_t> parent;
    const auto root = [&](uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (const auto& [key, use] : edges) {
        if (use.faces != 1) continue;
        const glm::uvec2 e = edge_from_key(key);
        parent.try_emplace(e.x, e.x);
        parent.try_emplace(e.y, e.y);
        parent[root(e.x)] = root(e.y);
    }
    const Box box = mesh.bounds();
    const glm::dvec3 centre = (glm::dvec3(box.min) + glm::dvec3(box.max)) * 0.5;
    std::unordered_map<uint32_t, glm::dvec3> loop_area;
    for (const auto& [key, use] : edges) {
        if (use.faces != 1) continue;
        glm::uvec2 e = edge_from_key(key);  // low to high; the face runs it so when low_to_high
        if (!use.low_to_high) std::swap(e.x, e.y);
        loop_area[root(e.x)] +=
            0.5 * glm::cross(glm::dvec3(mesh.vertices[e.x]) - centre, glm::dvec3(mesh.vertices[e.y]) - centre);
    }
    report.hole_count = loop_area.size();
    for (const auto& [hole, area] : loop_area) report.hole_area += glm::length(area);
}

}  // namespace

std::vector<uint32_t> welded_vertex_ids(const Mesh& mesh) { return welded_ids(mesh); }

std::vector<glm::vec3> Mesh::triangle_soup() const {
    std::vector<glm::vec3> soup;
    soup.reserve(faces.size() * 3);
    for (const glm::uvec3& face : faces) {
        soup.push_back(vertices[face.x]);
        soup.push_back(vertices[face.y]);
        soup.push_back(vertices[face.z]);
    }
    return soup;
}

Box Mesh::bounds() const {
    if (vertices.empty()) return Box{};
    Box box{vertices.front(), vertices.front()};
    for (const glm::vec3& vertex : vertices) {
        box.min = glm::min(box.min, vertex);
        box.max = glm::max(box.max, vertex);
    }
    return box;
}

HalfEdgeMesh to_half_edge_mesh(const Mesh& mesh, std::vector<uint32_t>* rejected_faces) {
    HalfEdgeMesh half_edge;
    std::vector<HalfEdgeMesh::VertexHandle> handles;
    handles.reserve(mesh.vertices.size());
    for (const glm::vec3& vertex : mesh.vertices) {
        handles.push_back(half_edge.add_vertex(HalfEdgeMesh::Point(vertex.x, vertex.y, vertex.z)));
    }
    // OpenMesh prints "complex edge" for every face it refuses; the caller gets the list instead.
    const bool error_stream_was_enabled = omerr().is_enabled();
    omerr().disable();
    for (uint32_t face_index = 0; face_index < mesh.faces.size(); ++face_index) {
        const glm::uvec3& face = mesh.faces[face_index];
        bool added = false;
        if (!has_repeated_index(face)) {
            added = half_edge.add_face(handles[face.x], handles[face.y], handles[face.z]).is_valid();
        }
        if (!added && rejected_faces) rejected_faces->push_back(face_index);
    }
    if (error_stream_was_enabled) omerr().enable();
    return half_edge;
}

bool MeshReport::watertight() const {
    return face_count > 0 && boundary_edge_count == 0 && closed_hole_count == 0 && non_manifold_edge_count == 0 &&
           non_manifold_vertex_count == 0 && inconsistent_edge_count == 0 && rejected_face_count == 0;
}

MeshReport check_mesh(const Mesh& mesh) {
    MeshReport report;
    report.vertex_count = mesh.vertices.size();
    report.face_count = mesh.faces.size();

    // Edge use counted on the indexed faces, so that faces OpenMesh refuses are still seen.
    struct EdgeUse {
        uint32_t faces = 0;
        uint32_t low_to_high = 0;  // faces that traverse the edge from the smaller to the larger index
    };
    std::unordered_map<uint64_t, EdgeUse> edges;
    edges.reserve(mesh.faces.size() * 2);
    const std::vector<uint32_t> ids = welded_ids(mesh);
    for (const glm::uvec3& corner_indices : mesh.faces) {
        const glm::uvec3 face = weld(corner_indices, ids);
        if (has_repeated_index(face)) continue;
        const uint32_t corners[3] = {face.x, face.y, face.z};
        for (int i = 0; i < 3; ++i) {
            const uint32_t from = corners[i];
            const uint32_t to = corners[(i + 1) % 3];
            EdgeUse& use = edges[edge_key(from, to)];
            ++use.faces;
            if (from < to) ++use.low_to_high;
        }
    }
    std::vector<uint64_t> boundary, non_manifold, inconsistent;
    for (const auto& [key, use] : edges) {
        if (use.faces == 1) boundary.push_back(key);
        if (use.faces > 2) non_manifold.push_back(key);
        if (use.faces == 2 && use.low_to_high != 1) inconsistent.push_back(key);
    }
    const auto list_edges = [](std::vector<uint64_t>& keys, size_t& count, std::vector<glm::uvec2>& listed) {
        count = keys.size();
        std::sort(keys.begin(), keys.end());
        keep_first(keys, MeshReport::kMaxListed);
        for (uint64_t key : keys) listed.push_back(edge_from_key(key));
    };
    measure_holes(mesh, edges, report);
    list_edges(boundary, report.boundary_edge_count, report.boundary_edges);
    list_edges(non_manifold, report.non_manifold_edge_count, report.non_manifold_edges);
    list_edges(inconsistent, report.inconsistent_edge_count, report.inconsistent_edges);

    std::vector<uint32_t> rejected;
    const HalfEdgeMesh half_edge = to_half_edge_mesh(mesh, &rejected);
    report.rejected_face_count = rejected.size();
    keep_first(rejected, MeshReport::kMaxListed);
    report.rejected_faces = rejected;
    for (const auto vertex : half_edge.vertices()) {
        if (half_edge.is_manifold(vertex)) continue;
        if (report.non_manifold_vertices.size() < MeshReport::kMaxListed) {
            report.non_manifold_vertices.push_back(static_cast<uint32_t>(vertex.idx()));
        }
        ++report.non_manifold_vertex_count;
    }

    for (uint32_t index = 0; index < mesh.vertices.size(); ++index) {
        if (ids[index] == index) continue;
        if (report.duplicated_vertices.size() < MeshReport::kMaxListed) report.duplicated_vertices.push_back(index);
        ++report.duplicated_vertex_count;
    }

    // Areas and volume in double, relative to the bounding-box centre, so large offsets do not cancel.
    const Box box = mesh.bounds();
    const glm::dvec3 centre = (glm::dvec3(box.min) + glm::dvec3(box.max)) * 0.5;
    const glm::dvec3 diagonal = glm::dvec3(box.max) - glm::dvec3(box.min);
    report.bounds_size = diagonal;
    const double min_area = 1e-12 * glm::dot(diagonal, diagonal);
    for (uint32_t face_index = 0; face_index < mesh.faces.size(); ++face_index) {
        const glm::uvec3& face = mesh.faces[face_index];
        const glm::dvec3 a = glm::dvec3(mesh.vertices[face.x]) - centre;
        const glm::dvec3 b = glm::dvec3(mesh.vertices[face.y]) - centre;
        const glm::dvec3 c = glm::dvec3(mesh.vertices[face.z]) - centre;
        const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
        if (has_repeated_index(face) || area <= min_area) {
            if (report.degenerate_faces.size() < MeshReport::kMaxListed) report.degenerate_faces.push_back(face_index);
            ++report.degenerate_face_count;
        }
        report.signed_volume += glm::dot(a, glm::cross(b, c)) / 6.0;
        report.surface_area += area;
    }
    return report;
}

size_t orient_consistently(Mesh& mesh) {
    // (edge, face, direction) sorted by edge: the faces of a manifold edge are then neighbours in the list.
    struct Use {
        uint64_t edge;
        uint32_t face;
        bool low_to_high;
    };
    std::vector<Use> uses;
    uses.reserve(mesh.faces.size() * 3);
    const std::vector<uint32_t> ids = welded_ids(mesh);
    for (uint32_t f = 0; f < mesh.faces.size(); ++f) {
        const glm::uvec3 face = weld(mesh.faces[f], ids);
        if (has_repeated_index(face)) continue;
        for (int i = 0; i < 3; ++i)
            uses.push_back({edge_key(face[i], face[(i + 1) % 3]), f, face[i] < face[(i + 1) % 3]});
    }
    std::sort(uses.begin(), uses.end(), [](const Use& a, const Use& b) { return a.edge < b.edge; });
    // Up to three neighbours per face; `same` marks one that runs the shared edge the same way (flipped).
    struct Link {
        uint32_t face;
        bool same;
    };
    std::vector<std::array<Link, 3>> links(mesh.faces.size());
    std::vector<uint8_t> link_count(mesh.faces.size(), 0);
    for (size_t i = 0; i + 1 < uses.size(); ++i) {
        if (uses[i].edge != uses[i + 1].edge || (i + 2 < uses.size() && uses[i + 2].edge == uses[i].edge) ||
            (i > 0 && uses[i - 1].edge == uses[i].edge) || uses[i].face == uses[i + 1].face)
            continue;  // only edges with exactly two faces: a non-manifold edge gives no reliable neighbour
        const bool same = uses[i].low_to_high == uses[i + 1].low_to_high;
        for (const auto& [from, to] :
             {std::pair{uses[i].face, uses[i + 1].face}, std::pair{uses[i + 1].face, uses[i].face}})
            if (link_count[from] < 3) links[from][link_count[from]++] = {to, same};
    }
    const Box box = mesh.bounds();
    const glm::dvec3 centre = (glm::dvec3(box.min) + glm::dvec3(box.max)) * 0.5;
    std::vector<int8_t> flip(mesh.faces.size(), -1);  // -1: not reached yet
    size_t turned = 0;
    std::vector<uint32_t> part;
    for (uint32_t seed = 0; seed < mesh.faces.size(); ++seed) {
        if (flip[seed] >= 0) continue;
        part.assign(1, seed);
        flip[seed] = 0;
        for (size_t next = 0; next < part.size(); ++next) {
            const uint32_t f = part[next];
            for (uint8_t k = 0; k < link_count[f]; ++k) {
                const Link& link = links[f][k];
                if (flip[link.face] >= 0) continue;  // a conflict here means a non-orientable part: left as is
                flip[link.face] = int8_t(flip[f] ^ int8_t(link.same));
                part.push_back(link.face);
            }
        }
        // Keep the orientation most of the part's area had; on a tie, the one that gives positive volume.
        double kept_area = 0.0, turned_area = 0.0, volume = 0.0;
        for (const uint32_t f : part) {
            const glm::uvec3& face = mesh.faces[f];
            const glm::dvec3 a = glm::dvec3(mesh.vertices[face.x]) - centre;
            const glm::dvec3 b = glm::dvec3(mesh.vertices[face.y]) - centre;
            const glm::dvec3 c = glm::dvec3(mesh.vertices[face.z]) - centre;
            const double area = glm::length(glm::cross(b - a, c - a));
            (flip[f] ? turned_area : kept_area) += area;
            volume += (flip[f] ? -1.0 : 1.0) * glm::dot(a, glm::cross(b, c));
        }
        const bool tie = std::abs(kept_area - turned_area) <= 1e-9 * (kept_area + turned_area);
        const bool invert = tie ? volume < 0.0 : turned_area > kept_area;
        for (const uint32_t f : part) {
            if (bool(flip[f]) == invert) continue;
            std::swap(mesh.faces[f].y, mesh.faces[f].z);
            ++turned;
        }
    }
    return turned;
}

std::string unusable_reason(const MeshReport& report) {
    const glm::dvec3 size = report.bounds_size;
    const double diagonal = glm::length(size);
    std::ostringstream out;
    out.precision(3);
    if (!(diagonal >= kMinMeshDiagonal)) {
        out << "the mesh is " << diagonal << " units across (its bounding box's diagonal; " << size.x << " x " << size.y
            << " x " << size.z << "), below the " << kMinMeshDiagonal
            << " that single-precision placement can hold; scale it up in a modelling tool (or export it in other units) "
               "and size it in the scene with its placement's \"scale\" or \"fit_into\"";
        return out.str();
    }
    // Shared by control meshes and obstacles, so the words name neither use alone.
    constexpr const char* kNoInside = "so it has no inside: nothing to fill and nothing to keep fluid out of";
    if (std::min({size.x, size.y, size.z}) <= 1e-6 * diagonal) {
        out << "the mesh encloses no volume: it is flat (a bounding box of " << size.x << " x " << size.y << " x "
            << size.z << "), " << kNoInside
            << "; use a closed solid mesh (a modelling tool's Solidify or Extrude gives a flat shape thickness)";
        return out.str();
    }
    const size_t holes = report.hole_count + report.closed_hole_count;
    const double opening = report.hole_fraction() + report.closed_hole_fraction();
    if (holes > 0 && opening >= kOpenSheetHoleFraction) {
        out << "the mesh is an open sheet, not a solid: closing its " << holes << " hole(s) ("
            << report.boundary_edge_count + report.closed_boundary_edge_count << " boundary edges) would take "
            << 100.0 * opening << "% of its own surface area (" << 100.0 * kOpenSheetHoleFraction
            << "% or more: the caps would be about the sheet itself), " << kNoInside
            << "; give it thickness in a modelling tool (Blender: Solidify modifier) or model it as a closed solid, "
               "and export again";
        return out.str();
    }
    // An open surface's signed volume depends on where it is measured from: judged once closed.
    if (report.hole_fraction() < 1e-6 && !(std::abs(report.signed_volume) > 1e-6 * diagonal * diagonal * diagonal)) {
        out << "the mesh encloses no volume (" << std::abs(report.signed_volume) << " in a bounding box of " << size.x
            << " x " << size.y << " x " << size.z
            << "): its faces cancel out (degenerate faces, or every face doubled by a flipped copy as a double-sided "
               "export writes them), "
            << kNoInside << "; use a closed solid mesh, exported single-sided";
        return out.str();
    }
    return {};
}

std::string describe(const MeshReport& report) {
    std::ostringstream out;
    const auto list = [&out](const auto& items) {
        out << " (first:";
        for (const auto& item : items) {
            if constexpr (std::is_same_v<std::decay_t<decltype(item)>, glm::uvec2>) {
                out << ' ' << item.x << '-' << item.y;
            } else {
                out << ' ' << item;
            }
        }
        out << ')';
    };
    out << report.vertex_count << " vertices, " << report.face_count << " faces, "
        << (report.watertight() ? "watertight" : "NOT watertight") << ", volume " << report.signed_volume << '\n';
    if (report.boundary_edge_count) {
        out << report.boundary_edge_count << " boundary edges: the mesh has holes, it is not closed";
        list(report.boundary_edges);
        out << '\n';
    }
    if (report.non_manifold_edge_count) {
        out << report.non_manifold_edge_count << " non-manifold edges (shared by 3+ faces)";
        list(report.non_manifold_edges);
        out << '\n';
    }
    if (report.non_manifold_vertex_count) {
        out << report.non_manifold_vertex_count << " non-manifold vertices";
        list(report.non_manifold_vertices);
        out << '\n';
    }
    if (report.inconsistent_edge_count) {
        out << report.inconsistent_edge_count << " edges with inconsistent orientation (neighbouring faces flipped)";
        list(report.inconsistent_edges);
        out << '\n';
    }
    if (report.rejected_face_count) {
        out << report.rejected_face_count << " faces not representable as a manifold half-edge mesh";
        list(report.rejected_faces);
        out << '\n';
    }
    if (report.degenerate_face_count) {
        out << report.degenerate_face_count << " degenerate (zero-area) faces";
        list(report.degenerate_faces);
        out << '\n';
    }
    if (report.duplicated_vertex_count) {
        out << report.duplicated_vertex_count << " duplicated vertices (same position as an earlier vertex)";
        list(report.duplicated_vertices);
        out << '\n';
    }
    if (report.reoriented_face_count) {
        out << report.reoriented_face_count
            << " faces were turned to agree with their neighbours (they were flipped; the mesh is used repaired)\n";
    }
    if (report.closed_hole_count) {
        out << "closed " << report.closed_hole_count << " hole(s) (" << report.closed_boundary_edge_count
            << " boundary edges, " << 100.0 * report.closed_hole_fraction()
            << "% of its surface area) with caps: the mesh is used closed (";
        for (size_t i = 0; i < report.closed_holes.size(); ++i) {
            const ClosedHole& hole = report.closed_holes[i];
            out << (i                                                       ? "; "
                    : report.closed_holes.size() < report.closed_hole_count ? "largest: "
                                                                            : "")
                << hole.edges << " edges around (" << hole.centre.x << ", " << hole.centre.y << ", " << hole.centre.z
                << ")";
        }
        out << ")\n";
    }
    if (report.hole_count) {
        out << report.hole_count
            << " holes left open (their edges form no closed loop, or enclose no area); closing them would take "
            << 100.0 * report.hole_fraction() << "% of the surface area (points near them may be missing)\n";
    }
    if (report.inward_facing()) {
        out << "negative volume: all face normals point inward; placement does not depend on it\n";
    }
    return out.str();
}

Result<Mesh> read_obj(const std::filesystem::path& path) {
    std::error_code error;
    if (!std::filesystem::exists(path, error)) {
        return mesh_error(path, "file does not exist",
                          "check the path (relative paths start at the working directory)");
    }
    if (!std::filesystem::is_regular_file(path, error)) {
        return mesh_error(path, "not a regular file", "give the path of a Wavefront .obj file");
    }
    const uint64_t bytes = std::filesystem::file_size(path, error);
    if (!error && bytes == 0)
        return mesh_error(path, "the file is empty (0 bytes)", "export the mesh again as Wavefront OBJ");
    // The text, the parsed mesh and the checks' edge and half-edge tables: about 6 times the file
    // (a 76 MB OBJ of 2M triangles peaks at 430 MB).
    const std::optional<uint64_t> available = available_host_memory();
    if (!error && available && 6 * bytes > *available)
        return mesh_error(path,
                          "reading this " + memory_size_text(bytes) + " file needs about " +
                              memory_size_text(6 * bytes) + " of memory but " + available_memory_text(*available),
                          "simplify (decimate) the mesh in a modelling tool, or free memory");
    std::ifstream file(path, std::ios::binary);
    std::string text(error ? 0 : size_t(bytes), '\0');  // read in place: one copy of a large file, not two
    if (!file || !file.read(text.data(), std::streamsize(text.size()))) {
        return mesh_error(path, "cannot read the file", "check that it is readable (permissions)");
    }
    std::string_view body = text;
    if (body.starts_with("\xEF\xBB\xBF")) body.remove_prefix(3);  // UTF-8 byte order mark
    if (body.starts_with("\xFF\xFE") || body.starts_with("\xFE\xFF"))
        return mesh_error(path, "the file is UTF-16 text", "save it as UTF-8 or ASCII (Wavefront OBJ is plain text)");
    if (const size_t zero = body.find('\0'); zero != std::string_view::npos)
        return mesh_error(path,
                          "not OBJ text: byte " + std::to_string(zero + 1) +
                              " is 0 (a binary file, or UTF-16 text without a byte order mark)",
                          "give a Wavefront OBJ text file, saved as UTF-8 or ASCII");
    if (body.find_first_not_of(" \t\r\n") == std::string_view::npos) {
        return mesh_error(path, "the file is empty", "export the mesh again as Wavefront OBJ");
    }
    Result<Mesh> read = ObjReader(path, body).read();
    if (!read) return Error{read.error()};
    Mesh mesh = std::move(read).value();
    if (mesh.vertices.empty()) {
        return mesh_error(path, "not an OBJ file: no vertices ('v x y z' lines) found",
                          "export the mesh as Wavefront OBJ (.obj)");
    }
    if (mesh.faces.empty()) {
        return mesh_error(path, "empty mesh: " + std::to_string(mesh.vertices.size()) + " vertices but no faces",
                          "the mesh needs triangles or polygons ('f' lines); export faces, not only points");
    }
    return mesh;
}

Result<bool> write_obj(const std::filesystem::path& path, const Mesh& mesh) {
    return write_file_with(path, [&](std::ostream& file) {
        file.precision(std::numeric_limits<float>::max_digits10);
        file << "# written by aquaform\n";
        for (const glm::vec3& vertex : mesh.vertices) {
            file << "v " << vertex.x << ' ' << vertex.y << ' ' << vertex.z << '\n';
        }
        for (const glm::uvec3& face : mesh.faces) {
            file << "f " << face.x + 1 << ' ' << face.y + 1 << ' ' << face.z + 1 << '\n';
        }
    });
}

void apply(const MeshPlacement& placement, Mesh& mesh) {
    const glm::vec3 radians = glm::radians(placement.rotation_degrees);
    // X first, then Y, then Z: R = Rz * Ry * Rx.
    glm::mat4 rotation(1.0f);
    rotation = glm::rotate(rotation, radians.z, glm::vec3(0, 0, 1));
    rotation = glm::rotate(rotation, radians.y, glm::vec3(0, 1, 0));
    rotation = glm::rotate(rotation, radians.x, glm::vec3(1, 0, 0));
    const glm::mat3 rotate3(rotation);

    if (!placement.fit_into) {
        for (glm::vec3& vertex : mesh.vertices) vertex = rotate3 * (vertex * placement.scale) + placement.position;
        return;
    }
    for (glm::vec3& vertex : mesh.vertices) vertex = rotate3 * vertex;
    const Box rotated = mesh.bounds();
    const Box& target = *placement.fit_into;
    const glm::vec3 mesh_extent = rotated.max - rotated.min;
    const glm::vec3 target_extent = target.max - target.min;
    // The tightest axis decides, so the whole box fits; flat axes (extent 0) do not constrain.
    float scale = std::numeric_limits<float>::max();
    for (int axis = 0; axis < 3; ++axis) {
        if (mesh_extent[axis] > 0.0f) scale = std::min(scale, target_extent[axis] / mesh_extent[axis]);
    }
    if (scale == std::numeric_limits<float>::max()) scale = 1.0f;
    const glm::vec3 mesh_centre = (rotated.min + rotated.max) * 0.5f;
    const glm::vec3 target_centre = (target.min + target.max) * 0.5f;
    for (glm::vec3& vertex : mesh.vertices) vertex = (vertex - mesh_centre) * scale + target_centre;
}

}  // namespace aquaform::geometry
