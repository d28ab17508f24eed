// The files `run` writes every K frames besides its images - particle dumps (PLY, VTK), density
// volumes (OpenVDB), surface meshes (OBJ, PLY or VTK) and the whitewater's particles (PLY or VTK) - under one rule: a kind whose flag gave
// K is written at the frames f with f % K == 0, as its file number f / K, so that each kind's
// files are numbered 0, 1, 2, ... (Blender's sequence imports stop at a gap). exports.csv maps
// every file to its frame and simulated time; the .pvd collections (VTK particles, VTK surfaces)
// list theirs with the time too (VTK particles, surfaces and whitewater). A new kind is a row in frame_export_kinds(), a field in
// FrameCapture if it needs new data, and a case in FrameExports::write.
//
// Up axis: the simulation is y-up (as ParaView and Houdini are); with UpAxis::z every file is
// written in a z-up frame (Blender's) by the rotation about x that takes +y to +z, (x, y, z) ->
// (x, -z, y), applied to positions, velocities, normals and the volume's lattice. A rotation keeps
// the handedness, so triangles keep their winding and normals still point out.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "core/file_write.h"
#include "core/result.h"
#include "exports/mesh_export.h"
#include "exports/vtk_export.h"
#include "render/density_volume.h"
#include "render/marching_cubes.h"
#include "sim/pbf_solver.h"

namespace aquaform {

enum class FrameExport : uint8_t { ply, vtk, vdb, mesh, whitewater };
constexpr size_t kFrameExportKinds = 5;

/// What a kind is written from (a field of FrameCapture).
enum class FrameData : uint8_t { particles, volume, mesh, whitewater };

struct FrameExportKind {
    FrameExport kind;
    const char* name;       ///< the kind in exports.csv: "ply", "vtk", "vdb", "mesh", "whitewater"
    const char* flag;       ///< the `run` flag that gives K, e.g. "--vtk-every"
    const char* file_stem;  ///< the file is <stem>_NNNN<extension>, numbered by file
    const char* extension;  ///< (a mesh's and the whitewater's follow their formats)
    FrameData needs;        ///< what it is written from
};

/// Every kind, in FrameExport order.
const std::array<FrameExportKind, kFrameExportKinds>& frame_export_kinds();

/// What a frame captured for its exports: only what a due kind needs.
struct FrameCapture {
    std::optional<ParticleSnapshot> particles;
    std::optional<DensityVolume> volume;
    std::optional<SurfaceMesh> mesh;
    std::optional<WhitewaterSnapshot> whitewater;  ///< the whitewater's particles
    bool has(FrameData data) const {
        switch (data) {
            case FrameData::particles:
                return bool(particles);
            case FrameData::volume:
                return bool(volume);
            case FrameData::mesh:
                return bool(mesh);
            case FrameData::whitewater:
                return bool(whitewater);
        }
        return false;
    }
};

enum class UpAxis : uint8_t { y, z };

/// The rotation about x that takes +y to +z: a y-up point in the z-up frame (UpAxis::z).
glm::vec3 z_up(const glm::vec3& p);

/// "y" or "z"; otherwise an error listing the choices.
Result<UpAxis> parse_up_axis(const std::string& text);

/// The whitewater's file format: PLY for Blender (blender_scene.py reads it), VTK PolyData with
/// a whitewater.pvd for ParaView (whose PLY reader keeps neither the vertices as cells nor the
/// velocity, kind and life; a .vtp keeps them all and draws as points).
enum class WhitewaterFormat : uint8_t { ply, vtp };

/// "ply" or "vtp"; otherwise an error listing the choices.
Result<WhitewaterFormat> parse_whitewater_format(const std::string& text);

struct FrameExportOptions {
    std::array<uint32_t, kFrameExportKinds> every{};  ///< per kind: every K frames; 0: never
    MeshFormat mesh_format = MeshFormat::obj;
    WhitewaterFormat whitewater_format = WhitewaterFormat::ply;
    UpAxis up = UpAxis::y;
};

/// The files' listing in the export folder: "file,kind,frame,time_s", a row per file written.
inline constexpr const char* kExportListing = "exports.csv";

class FrameExports {
public:
    FrameExports(std::filesystem::path dir, const FrameExportOptions& options);

    bool enabled(FrameExport kind) const { return options_.every[size_t(kind)] > 0; }
    uint32_t every(FrameExport kind) const { return options_.every[size_t(kind)]; }
    bool due(FrameExport kind, uint32_t frame) const;
    /// Whether a kind due at `frame` is written from `data`.
    bool needs(FrameData data, uint32_t frame) const;
    bool needs_particles(uint32_t frame) const { return needs(FrameData::particles, frame); }
    bool needs_volume(uint32_t frame) const { return needs(FrameData::volume, frame); }

    /// Writes the files due at `frame` from `capture`, each followed by its row in exports.csv
    /// (and its entry in a .pvd); `time_s` is the frame's simulated time. The error names the file
    /// and the fix.
    Result<bool> write(uint32_t frame, double time_s, const FrameCapture& capture);

private:
    std::filesystem::path file(FrameExport kind, uint32_t frame) const;
    Result<bool> write_file(FrameExport kind, const std::filesystem::path& path, double time_s,
                            const FrameCapture& frame);
    Result<bool> list(const std::filesystem::path& file, const FrameExportKind& kind, uint32_t frame, double time_s);

    std::filesystem::path dir_;
    FrameExportOptions options_;
    VtkCollection particles_pvd_;
    VtkCollection surface_pvd_;
    VtkCollection whitewater_pvd_;
    AppendedFile listing_;  // exports.csv, opened with the first file
};

}  // namespace aquaform
