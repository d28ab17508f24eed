// Surface meshes (render/surface_mesher.h) as files other tools open: Wavefront OBJ (text:
// positions, normals, faces), binary little-endian PLY (vertices with normals, faces as lists),
// for Blender, Houdini and MeshLab, and VTK PolyData (exports/vtk_export.h) for ParaView. Faces
// are counter-clockwise seen from outside the fluid, so the tools' face normals point out, as the
// vertex normals do.
#pragma once

#include <filesystem>
#include <string>

#include "core/result.h"
#include "render/marching_cubes.h"

namespace aquaform {

enum class MeshFormat { obj, ply, vtp };

/// "obj", "ply" or "vtp"; otherwise an error listing the choices.
Result<MeshFormat> parse_mesh_format(const std::string& text);
/// The file extension without the dot: "obj", "ply" or "vtp".
const char* mesh_format_extension(MeshFormat format);

/// The mesh as OBJ: "v x y z", "vn x y z" per vertex, "f a//a b//b c//c" per triangle (1-based).
Result<bool> write_mesh_obj(const std::filesystem::path& path, const SurfaceMesh& mesh);
/// The mesh as binary little-endian PLY: vertex (float x y z nx ny nz), face (list uchar int
/// vertex_indices).
Result<bool> write_mesh_ply(const std::filesystem::path& path, const SurfaceMesh& mesh);
Result<bool> write_mesh(const std::filesystem::path& path, const SurfaceMesh& mesh, MeshFormat format);

}  // namespace aquaform
