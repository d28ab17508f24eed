#include "exports/mesh_export.h"

#include <bit>
#include <charconv>
#include <cstring>
#include <ostream>

#include "core/file_write.h"
#include "exports/vtk_export.h"

namespace aquaform {

namespace {

static_assert(std::endian::native == std::endian::little, "the PLY writer copies little-endian floats as they are");

/// Appends " x y z" with the shortest text that reads back as the same floats.
void append_vec3(std::string& line, const glm::vec3& v) {
    char text[64];
    for (int a = 0; a < 3; ++a) {
        text[0] = ' ';
        const auto end = std::to_chars(text + 1, text + sizeof text, v[a]).ptr;
        line.append(text, end);
    }
}

void append_index(std::string& line, uint32_t index) {
    char text[16];
    line.append(text, std::to_chars(text, text + sizeof text, index).ptr);
}

}  // namespace

Result<MeshFormat> parse_mesh_format(const std::string& text) {
    if (text == "obj") return MeshFormat::obj;
    if (text == "ply") return MeshFormat::ply;
    if (text == "vtp") return MeshFormat::vtp;
    return Error{"unknown mesh format '" + text + "'; use obj, ply or vtp"};
}

const char* mesh_format_extension(MeshFormat format) {
    switch (format) {
        case MeshFormat::obj:
            return "obj";
        case MeshFormat::ply:
            return "ply";
        case MeshFormat::vtp:
            return "vtp";
    }
    return "";
}

Result<bool> write_mesh_obj(const std::filesystem::path& path, const SurfaceMesh& mesh) {
    return write_file_with(path, [&](std::ostream& out) {
        out << "# aquaform fluid surface (marching cubes, SI units): " << mesh.vertices.size() << " vertices, "
            << mesh.triangles.size() << " triangles\n";
        // Written in blocks: a text line per element through the stream is several times slower.
        std::string block;
        auto flush = [&](bool last) {
            if (block.size() < (1u << 20) && !last) return;
            out.write(block.data(), std::streamsize(block.size()));
            block.clear();
        };
        for (const glm::vec3& v : mesh.vertices) {
            block += 'v';
            append_vec3(block, v);
            block += '\n';
            flush(false);
        }
        for (const glm::vec3& n : mesh.normals) {
            block += "vn";
            append_vec3(block, n);
            block += '\n';
            flush(false);
        }
        for (const glm::uvec3& t : mesh.triangles) {
            block += 'f';
            for (int k = 0; k < 3; ++k) {
                block += ' ';
                append_index(block, t[k] + 1);
                block += "//";
                append_index(block, t[k] + 1);
            }
            block += '\n';
            flush(false);
        }
        flush(true);
    });
}

Result<bool> write_mesh_ply(const std::filesystem::path& path, const SurfaceMesh& mesh) {
    return write_file_with(path, [&](std::ostream& out) {
        out << "ply\nformat binary_little_endian 1.0\ncomment aquaform fluid surface (marching cubes, SI units)\n"
            << "element vertex " << mesh.vertices.size() << "\n"
            << "property float x\nproperty float y\nproperty float z\n"
            << "property float nx\nproperty float ny\nproperty float nz\n"
            << "element face " << mesh.triangles.size() << "\n"
            << "property list uchar int vertex_indices\nend_header\n";
        std::vector<char> block;
        block.reserve(std::max(mesh.vertices.size() * 24, mesh.triangles.size() * 13));
        for (size_t i = 0; i < mesh.vertices.size(); ++i) {
            const glm::vec3 n = i < mesh.normals.size() ? mesh.normals[i] : glm::vec3(0.0f);
            const float record[6] = {mesh.vertices[i].x, mesh.vertices[i].y, mesh.vertices[i].z, n.x, n.y, n.z};
            block.insert(block.end(), reinterpret_cast<const char*>(record),
                         reinterpret_cast<const char*>(record) + 24);
        }
        out.write(block.data(), std::streamsize(block.size()));
        block.clear();
        for (const glm::uvec3& t : mesh.triangles) {
            char record[13];
            record[0] = 3;
            const int32_t corners[3] = {int32_t(t.x), int32_t(t.y), int32_t(t.z)};
            std::memcpy(record + 1, corners, 12);
            block.insert(block.end(), record, record + 13);
        }
        out.write(block.data(), std::streamsize(block.size()));
    });
}

Result<bool> write_mesh(const std::filesystem::path& path, const SurfaceMesh& mesh, MeshFormat format) {
    switch (format) {
        case MeshFormat::obj:
            return write_mesh_obj(path, mesh);
        case MeshFormat::ply:
            return write_mesh_ply(path, mesh);
        case MeshFormat::vtp:
            return write_mesh_vtp(path, mesh);
    }
    return Error{"cannot write " + path.string() + ": unknown mesh format"};
}

}  // namespace aquaform
