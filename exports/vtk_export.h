// Frames for ParaView and VTK: particles as a VTK XML UnstructuredGrid (.vtu), surface meshes as
// a VTK XML PolyData (.vtp), and a .pvd collection that lists a series with its simulated times.
//
// Format choice: raw binary in an AppendedData block (UInt64 block headers, no compression):
// the smallest and quickest VTK XML encoding to write and read (base64 inline would add a third
// to the size and an encoding pass). Every particle is a VTK_VERTEX cell, so ParaView draws the
// points without a filter. Points: positions (Float32 x 3); point data: velocity (Float32 x 3),
// density (Float32), id (UInt32), tag (UInt32, the fluid block the particle came from) - the
// same fields as the PLY dump (sim/particle_io.h). A mesh's triangles are polys (Int32
// connectivity), its vertex normals the point data "normals". The whitewater's particles are a
// PolyData of vertex cells with the point data velocity (Float32 x 3), kind (UInt8: 0 spray,
// 1 foam, 2 bubble) and life (Float32, seconds left), the fields of its PLY (sim/particle_io.h).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"
#include "render/marching_cubes.h"
#include "sim/pbf_solver.h"

namespace aquaform {

/// The .pvd's timesteps and exports.csv's times: simulated seconds, to the float's precision.
inline constexpr const char* kTimeFormat = "%.12g";

Result<bool> write_particles_vtu(const std::filesystem::path& path, const ParticleSnapshot& particles);
/// Normals are written where the mesh has one per vertex.
Result<bool> write_mesh_vtp(const std::filesystem::path& path, const SurfaceMesh& mesh);
Result<bool> write_whitewater_vtp(const std::filesystem::path& path, const WhitewaterSnapshot& whitewater);

/// A ParaView collection (.pvd) of the files written so far, rewritten whole (atomically) after
/// each addition, so that a run stopped midway still leaves a collection ParaView opens.
class VtkCollection {
public:
    explicit VtkCollection(std::filesystem::path pvd_path) : path_(std::move(pvd_path)) {}
    /// Adds `file` (a name relative to the .pvd's folder) at simulated time `time_s`, and
    /// rewrites the .pvd.
    Result<bool> add(double time_s, const std::string& file);

private:
    struct Entry {
        double time_s;
        std::string file;
    };
    std::filesystem::path path_;
    std::vector<Entry> entries_;
};

}  // namespace aquaform
