// Exports read back the way their users' tools read them, for the export tests: VTK files by VTK
// itself (Debian's Python, tests/read_vtk.py), volumes by OpenVDB's reader, PLY files byte by byte.
#pragma once

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <nlohmann/json.hpp>

#include "render/marching_cubes.h"
#include "tests/cli_helpers.h"

namespace aquaform::test_exports {

namespace fs = std::filesystem;
using nlohmann::json;

/// What tests/read_vtk.py (VTK's reader under Debian's Python) found in `file`.
inline json read_with_vtk(const fs::path& file) {
    const fs::path out = file.parent_path() / (file.filename().string() + ".json");
    const std::string command = "/usr/bin/python3 " + std::string(AQUAFORM_SOURCE_DIR) + "/tests/read_vtk.py '" +
                                file.string() + "' > '" + out.string() + "' 2>&1";
    const int status = std::system(command.c_str());
    const std::string text = test_cli::read_file(out);
    EXPECT_EQ(status, 0) << "VTK could not read " << file << ": " << text;
    if (status != 0) return json();
    return json::parse(text);
}

/// The FloatGrid named density of a .vdb, read with OpenVDB's own reader.
inline openvdb::FloatGrid::Ptr read_density_grid(const fs::path& path) {
    openvdb::initialize();
    openvdb::io::File file(path.string());
    file.open();
    auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
    file.close();
    return grid;
}

/// The PLY dump's records (sim/particle_io.cpp): 7 floats, then id and tag as uint32.
inline std::vector<std::array<float, 7>> read_ply_records(const fs::path& path, std::vector<uint32_t>* ids) {
    const std::string text = test_cli::read_file(path);
    const size_t body = text.find("end_header\n") + 11;
    std::vector<std::array<float, 7>> records;
    for (size_t at = body; at + 36 <= text.size(); at += 36) {
        std::array<float, 7> f;
        uint32_t u[2];
        std::memcpy(f.data(), text.data() + at, sizeof f);
        std::memcpy(u, text.data() + at + 28, sizeof u);
        records.push_back(f);
        ids->push_back(u[0]);
    }
    return records;
}

/// A binary little-endian PLY as exports/mesh_export.cpp writes it, read back.
inline SurfaceMesh read_mesh_ply(const fs::path& path) {
    const std::string text = test_cli::read_file(path);
    SurfaceMesh mesh;
    size_t vertices = 0, faces = 0;
    std::sscanf(text.c_str() + text.find("element vertex"), "element vertex %zu", &vertices);
    std::sscanf(text.c_str() + text.find("element face"), "element face %zu", &faces);
    size_t at = text.find("end_header\n") + 11;
    EXPECT_EQ(text.size(), at + vertices * 24 + faces * 13) << path;
    if (text.size() != at + vertices * 24 + faces * 13) return mesh;
    for (size_t i = 0; i < vertices; ++i, at += 24) {
        float f[6];
        std::memcpy(f, text.data() + at, 24);
        mesh.vertices.emplace_back(f[0], f[1], f[2]);
        mesh.normals.emplace_back(f[3], f[4], f[5]);
    }
    for (size_t i = 0; i < faces; ++i, at += 13) {
        EXPECT_EQ(text[at], 3);
        int32_t c[3];
        std::memcpy(c, text.data() + at + 1, 12);
        mesh.triangles.emplace_back(c[0], c[1], c[2]);
    }
    return mesh;
}

}  // namespace aquaform::test_exports
