#include "exports/vtk_export.h"

#include <bit>
#include <cstdint>
#include <limits>
#include <ostream>
#include <string_view>

#include "core/file_write.h"
#include "core/format_text.h"
#include "core/text_escape.h"

namespace aquaform {

static_assert(std::endian::native == std::endian::little, "the .vtu header says LittleEndian");

namespace {

/// One array of the appended block: its XML attributes and its bytes.
struct AppendedArray {
    std::string_view vtk_type;  // Float32, UInt32, Int32, UInt8
    std::string_view name;
    uint32_t components;
    const void* data;
    uint64_t bytes;
};

/// `<DataArray .../>` for an array whose bytes start `offset` bytes into the appended block.
void write_array_tag(std::ostream& out, const AppendedArray& a, uint64_t offset) {
    out << "        <DataArray type=\"" << a.vtk_type << "\"";
    if (!a.name.empty()) out << " Name=\"" << a.name << "\"";
    if (a.components > 1) out << " NumberOfComponents=\"" << a.components << "\"";
    out << " format=\"appended\" offset=\"" << offset << "\"/>\n";
}

/// The bytes of a block in the appended data: a UInt64 size header, then the data.
uint64_t block_bytes(const AppendedArray& a) { return sizeof(uint64_t) + a.bytes; }

template <typename T>
AppendedArray array_of(std::string_view vtk_type, std::string_view name, uint32_t components, const std::vector<T>& v) {
    return {vtk_type, name, components, v.data(), uint64_t(v.size()) * sizeof(T)};
}

/// A section of a piece: its element (PointData, Points, Cells, Polys), the element's attributes
/// and its arrays.
struct Section {
    std::string_view element;
    std::string_view attributes;
    std::vector<AppendedArray> arrays;
};

/// A VTK XML file of `type` ("UnstructuredGrid", "PolyData") holding one piece: the sections'
/// array tags in order, then their bytes in the appended block in that same order.
Result<bool> write_appended_vtk(const std::filesystem::path& path, std::string_view type,
                                const std::string& piece_attributes, const std::vector<Section>& sections) {
    return write_file_with(path, [&](std::ostream& out) {
        out << "<?xml version=\"1.0\"?>\n"
            << "<VTKFile type=\"" << type << "\" version=\"0.1\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
            << "  <" << type << ">\n    <Piece " << piece_attributes << ">\n";
        uint64_t offset = 0;
        for (const Section& s : sections) {
            out << "      <" << s.element << s.attributes << ">\n";
            for (const AppendedArray& a : s.arrays) {
                write_array_tag(out, a, offset);
                offset += block_bytes(a);
            }
            out << "      </" << s.element << ">\n";
        }
        out << "    </Piece>\n  </" << type << ">\n  <AppendedData encoding=\"raw\">\n   _";
        for (const Section& s : sections)
            for (const AppendedArray& a : s.arrays) {
                out.write(reinterpret_cast<const char*>(&a.bytes), sizeof a.bytes);
                out.write(static_cast<const char*>(a.data), std::streamsize(a.bytes));
            }
        out << "\n  </AppendedData>\n</VTKFile>\n";
    });
}

}  // namespace

Result<bool> write_particles_vtu(const std::filesystem::path& path, const ParticleSnapshot& s) {
    const size_t n = s.x.size();
    if (s.v.size() != n || (!s.density.empty() && s.density.size() != n))
        return Error{"cannot write " + path.string() + ": the snapshot has " + std::to_string(n) + " positions, " +
                     std::to_string(s.v.size()) + " velocities and " + std::to_string(s.density.size()) +
                     " densities; take the snapshot from one solver (PbfSolver::snapshot)"};
    if (n > size_t(std::numeric_limits<int32_t>::max()))
        return Error{"cannot write " + path.string() + ": " + std::to_string(n) +
                     " particles exceed the Int32 cell connectivity of the .vtu writer; write fewer particles"};
    // The snapshot keeps id and tag in w; VTK wants each field as its own array.
    std::vector<float> points(3 * n), velocity(3 * n), density(n, 0.0f);
    std::vector<uint32_t> id(n), tag(n);
    std::vector<int32_t> connectivity(n), offsets(n);
    const std::vector<uint8_t> types(n, uint8_t(1));  // VTK_VERTEX
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            points[3 * i + c] = s.x[i][c];
            velocity[3 * i + c] = s.v[i][c];
        }
        id[i] = static_cast<uint32_t>(s.x[i].w);
        tag[i] = static_cast<uint32_t>(s.v[i].w);
        connectivity[i] = int32_t(i);
        offsets[i] = int32_t(i + 1);
    }
    if (!s.density.empty()) density = s.density;

    return write_appended_vtk(
        path, "UnstructuredGrid",
        "NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfCells=\"" + std::to_string(n) + "\"",
        {{"PointData",
          " Scalars=\"density\" Vectors=\"velocity\"",
          {array_of("Float32", "velocity", 3, velocity), array_of("Float32", "density", 1, density),
           array_of("UInt32", "id", 1, id), array_of("UInt32", "tag", 1, tag)}},
         {"Points", "", {array_of("Float32", "", 3, points)}},
         {"Cells",
          "",
          {array_of("Int32", "connectivity", 1, connectivity), array_of("Int32", "offsets", 1, offsets),
           array_of("UInt8", "types", 1, types)}}});
}

Result<bool> write_mesh_vtp(const std::filesystem::path& path, const SurfaceMesh& mesh) {
    const size_t n = mesh.vertices.size(), triangles = mesh.triangles.size();
    if (3 * triangles > size_t(std::numeric_limits<int32_t>::max()))
        return Error{"cannot write " + path.string() + ": " + std::to_string(triangles) +
                     " triangles exceed the Int32 connectivity of the .vtp writer; mesh a coarser lattice"};
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "vertices and normals are written as they lie");
    std::vector<int32_t> connectivity(3 * triangles), offsets(triangles);
    for (size_t t = 0; t < triangles; ++t) {
        for (int c = 0; c < 3; ++c) connectivity[3 * t + c] = int32_t(mesh.triangles[t][c]);
        offsets[t] = int32_t(3 * t + 3);
    }
    // Normals only where every vertex has one (a mesh may come without them).
    const bool normals = mesh.normals.size() == n && n > 0;
    std::vector<AppendedArray> point_data;
    if (normals) point_data.push_back(array_of("Float32", "normals", 3, mesh.normals));

    return write_appended_vtk(
        path, "PolyData",
        "NumberOfPoints=\"" + std::to_string(n) +
            "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
            std::to_string(triangles) + "\"",
        {{"PointData", normals ? " Normals=\"normals\"" : "", point_data},
         {"Points", "", {array_of("Float32", "", 3, mesh.vertices)}},
         {"Polys",
          "",
          {array_of("Int32", "connectivity", 1, connectivity), array_of("Int32", "offsets", 1, offsets)}}});
}

Result<bool> write_whitewater_vtp(const std::filesystem::path& path, const WhitewaterSnapshot& d) {
    const size_t n = d.x.size();
    if (d.v.size() != n)
        return Error{"cannot write " + path.string() + ": the snapshot has " + std::to_string(n) + " positions and " +
                     std::to_string(d.v.size()) + " velocities; take it from one pool (Whitewater::snapshot)"};
    if (n > size_t(std::numeric_limits<int32_t>::max()))
        return Error{"cannot write " + path.string() + ": " + std::to_string(n) +
                     " particles exceed the Int32 connectivity of the .vtp writer; give the pool a smaller capacity"};
    // The snapshot keeps life and kind in w; VTK wants each field as its own array.
    std::vector<float> points(3 * n), velocity(3 * n), life(n);
    std::vector<uint8_t> kind(n);
    std::vector<int32_t> connectivity(n), offsets(n);
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            points[3 * i + c] = d.x[i][c];
            velocity[3 * i + c] = d.v[i][c];
        }
        life[i] = d.x[i].w;
        kind[i] = static_cast<uint8_t>(d.v[i].w);
        connectivity[i] = int32_t(i);
        offsets[i] = int32_t(i + 1);
    }
    return write_appended_vtk(
        path, "PolyData",
        "NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfVerts=\"" + std::to_string(n) +
            "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\"",
        {{"PointData",
          " Scalars=\"kind\" Vectors=\"velocity\"",
          {array_of("Float32", "velocity", 3, velocity), array_of("UInt8", "kind", 1, kind),
           array_of("Float32", "life", 1, life)}},
         {"Points", "", {array_of("Float32", "", 3, points)}},
         {"Verts",
          "",
          {array_of("Int32", "connectivity", 1, connectivity), array_of("Int32", "offsets", 1, offsets)}}});
}

Result<bool> VtkCollection::add(double time_s, const std::string& file) {
    entries_.push_back({time_s, file});
    return write_file_with(path_, [&](std::ostream& out) {
        out << "<?xml version=\"1.0\"?>\n"
            << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
        for (const Entry& e : entries_) {
            out << "    <DataSet timestep=\"" << format_text(kTimeFormat, e.time_s)
                << "\" group=\"\" part=\"0\" file=\"" << xml_text(e.file) << "\"/>\n";
        }
        out << "  </Collection>\n</VTKFile>\n";
    });
}

}  // namespace aquaform
