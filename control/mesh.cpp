#include "control/mesh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <unordered_map>

#include <OpenMesh/Core/System/omstream.hh>
#include <glm/gtc/matrix_transform.hpp>
#include <tiny_obj_loader.h>

namespace aquaform::control {

namespace {

uint64_t edge_key(uint32_t a, uint32_t b) {
    return (uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

glm::uvec2 edge_from_key(uint64_t key) {
    return {static_cast<uint32_t>(key >> 32), static_cast<uint32_t>(key & 0xffffffffu)};
}

bool has_repeated_index(const glm::uvec3& face) {
    return face.x == face.y || face.y == face.z || face.z == face.x;
}

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

// tinyobjloader silently reads "nan", "inf" or garbage as 0, so vertex lines are checked here first.
std::optional<Error> check_vertex_lines(const std::filesystem::path& path, const std::string& text) {
    std::istringstream lines(text);
    std::string line;
    size_t line_number = 0;
    size_t vertex_index = 0;
    while (std::getline(lines, line)) {
        ++line_number;
        size_t start = line.find_first_not_of(" \t");
        if (start == std::string::npos || line[start] != 'v' || start + 1 >= line.size() ||
            (line[start + 1] != ' ' && line[start + 1] != '\t')) {
            continue;
        }
        std::istringstream tokens(line.substr(start + 2));
        const std::string where =
            "vertex " + std::to_string(vertex_index) + " (line " + std::to_string(line_number) + ")";
        for (int axis = 0; axis < 3; ++axis) {
            std::string token;
            if (!(tokens >> token)) {
                return mesh_error(path, where + " has fewer than three coordinates",
                                  "every 'v' line needs x y z; re-export the mesh as Wavefront OBJ");
            }
            char* end = nullptr;
            const double value = std::strtod(token.c_str(), &end);
            if (end == token.c_str() || *end != '\0') {
                return mesh_error(path, where + " has a coordinate '" + token + "' that is not a number",
                                  "re-export the mesh as Wavefront OBJ");
            }
            if (!std::isfinite(value)) {
                return mesh_error(path, where + " has a non-finite coordinate '" + token + "' (NaN or infinity)",
                                  "repair or re-export the mesh; a modelling tool can usually find such vertices");
            }
            if (std::abs(value) > kMaxMeshCoordinate) {
                return mesh_error(path,
                                  where + " has coordinate " + format_number(value) + ", too large: beyond +-" +
                                      format_number(kMaxMeshCoordinate) + " float precision is meaningless",
                                  "scale the mesh down in the modelling tool (the scene placement can scale it up)");
            }
        }
        ++vertex_index;
    }
    return std::nullopt;
}

}  // namespace

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
    return face_count > 0 && boundary_edge_count == 0 && non_manifold_edge_count == 0 &&
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
    for (const glm::uvec3& face : mesh.faces) {
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

    // Exact position match; -0 and +0 are the same position.
    struct PositionHash {
        size_t operator()(const glm::vec3& p) const {
            const auto bits = [](float value) { return std::bit_cast<uint32_t>(value + 0.0f); };
            return (size_t{bits(p.x)} * 73856093u) ^ (size_t{bits(p.y)} * 19349663u) ^ (size_t{bits(p.z)} * 83492791u);
        }
    };
    std::unordered_map<glm::vec3, uint32_t, PositionHash> first_at_position;
    for (uint32_t index = 0; index < mesh.vertices.size(); ++index) {
        if (first_at_position.emplace(mesh.vertices[index], index).second) continue;
        if (report.duplicated_vertices.size() < MeshReport::kMaxListed) report.duplicated_vertices.push_back(index);
        ++report.duplicated_vertex_count;
    }

    // Areas and volume in double, relative to the bounding-box centre, so large offsets do not cancel.
    const Box box = mesh.bounds();
    const glm::dvec3 centre = (glm::dvec3(box.min) + glm::dvec3(box.max)) * 0.5;
    const glm::dvec3 diagonal = glm::dvec3(box.max) - glm::dvec3(box.min);
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
    }
    return report;
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
    if (report.inward_facing()) {
        out << "negative volume: the face normals point inward (the inside test still works)\n";
    }
    return out.str();
}

Result<LoadedMesh> load_obj(const std::filesystem::path& path) {
    std::error_code error;
    if (!std::filesystem::exists(path, error)) {
        return mesh_error(path, "file does not exist",
                          "check the path (relative paths start at the working directory)");
    }
    if (!std::filesystem::is_regular_file(path, error)) {
        return mesh_error(path, "not a regular file", "give the path of a Wavefront .obj file");
    }
    std::ifstream file(path, std::ios::binary);
    std::ostringstream contents;
    if (!file || !(contents << file.rdbuf()) || file.bad()) {
        if (std::filesystem::file_size(path, error) == 0 && !error) {
            return mesh_error(path, "the file is empty (0 bytes)", "export the mesh again as Wavefront OBJ");
        }
        return mesh_error(path, "cannot read the file", "check that it is readable (permissions)");
    }
    const std::string text = contents.str();
    if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
        return mesh_error(path, "the file is empty", "export the mesh again as Wavefront OBJ");
    }
    if (auto vertex_error = check_vertex_lines(path, text)) return *vertex_error;

    tinyobj::attrib_t attributes;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warnings, errors;
    std::istringstream stream(text);
    // No material reader: materials are irrelevant here and must not make the load touch other files.
    const bool parsed = tinyobj::LoadObj(&attributes, &shapes, &materials, &warnings, &errors, &stream, nullptr,
                                         /*triangulate=*/true);
    if (!parsed || !errors.empty()) {
        return mesh_error(path, "not a valid OBJ file: " + (errors.empty() ? std::string("parser failed") : errors),
                          "export the mesh as Wavefront OBJ");
    }
    if (attributes.vertices.empty()) {
        return mesh_error(path, "not an OBJ file: no vertices ('v x y z' lines) found",
                          "export the mesh as Wavefront OBJ (.obj)");
    }

    LoadedMesh loaded;
    Mesh& mesh = loaded.mesh;
    const size_t vertex_count = attributes.vertices.size() / 3;
    mesh.vertices.reserve(vertex_count);
    for (size_t i = 0; i < vertex_count; ++i) {
        mesh.vertices.emplace_back(attributes.vertices[3 * i], attributes.vertices[3 * i + 1],
                                   attributes.vertices[3 * i + 2]);
    }
    for (const tinyobj::shape_t& shape : shapes) {
        size_t offset = 0;
        for (const unsigned char corners : shape.mesh.num_face_vertices) {
            // With triangulation on every face has 3 corners; anything else is skipped, not misread.
            if (corners == 3) {
                glm::uvec3 face;
                for (int corner = 0; corner < 3; ++corner) {
                    const int index = shape.mesh.indices[offset + corner].vertex_index;
                    if (index < 0 || static_cast<size_t>(index) >= vertex_count) {
                        return mesh_error(path,
                                          "face " + std::to_string(mesh.faces.size()) + " refers to vertex " +
                                              std::to_string(index) + " but the file has " +
                                              std::to_string(vertex_count) + " vertices",
                                          "repair or re-export the mesh");
                    }
                    face[corner] = static_cast<uint32_t>(index);
                }
                mesh.faces.push_back(face);
            }
            offset += corners;
        }
    }
    if (mesh.faces.empty()) {
        return mesh_error(path, "empty mesh: " + std::to_string(vertex_count) + " vertices but no faces",
                          "the mesh needs triangles or polygons ('f' lines); export faces, not only points");
    }
    loaded.report = check_mesh(mesh);
    return loaded;
}

Result<bool> write_obj(const std::filesystem::path& path, const Mesh& mesh) {
    std::ofstream file(path);
    if (!file) return Error{"cannot write mesh '" + path.string() + "': check the directory exists and is writable"};
    file.precision(std::numeric_limits<float>::max_digits10);
    file << "# written by aquaform\n";
    for (const glm::vec3& vertex : mesh.vertices) {
        file << "v " << vertex.x << ' ' << vertex.y << ' ' << vertex.z << '\n';
    }
    for (const glm::uvec3& face : mesh.faces) {
        file << "f " << face.x + 1 << ' ' << face.y + 1 << ' ' << face.z + 1 << '\n';
    }
    if (!file) return Error{"cannot write mesh '" + path.string() + "': write failed (disk full?)"};
    return true;
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

}  // namespace aquaform::control
