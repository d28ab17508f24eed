#include "exports/frame_exports.h"

#include <cstdio>

#include "exports/vdb_export.h"
#include "sim/particle_io.h"

namespace aquaform {

const std::array<FrameExportKind, kFrameExportKinds>& frame_export_kinds() {
    static const std::array<FrameExportKind, kFrameExportKinds> kinds = {{
        {FrameExport::ply, "--ply-every", "particles_%04u.ply", FrameData::particles},
        {FrameExport::vtk, "--vtk-every", "particles_%04u.vtu", FrameData::particles},
        {FrameExport::vdb, "--vdb-every", "density_%04u.vdb", FrameData::volume},
        {FrameExport::mesh, "--mesh-every", "surface_%04u.obj", FrameData::mesh},
    }};
    return kinds;
}

FrameExports::FrameExports(std::filesystem::path dir, const FrameExportOptions& options)
    : dir_(std::move(dir)), options_(options), vtk_collection_(dir_ / "particles.pvd") {}

bool FrameExports::due(FrameExport kind, uint32_t frame) const {
    const uint32_t every = options_.every[size_t(kind)];
    return every > 0 && frame % every == 0;
}

bool FrameExports::needs(FrameData data, uint32_t frame) const {
    for (const FrameExportKind& k : frame_export_kinds())
        if (k.needs == data && due(k.kind, frame)) return true;
    return false;
}

std::filesystem::path FrameExports::file(FrameExport kind, uint32_t frame) const {
    char name[64];
    std::snprintf(name, sizeof name, frame_export_kinds()[size_t(kind)].file_pattern, frame);
    std::filesystem::path path = dir_ / name;
    if (kind == FrameExport::mesh) path.replace_extension(mesh_format_extension(options_.mesh_format));
    return path;
}

Result<bool> FrameExports::write(uint32_t frame, double time_s, const FrameCapture& capture) {
    for (const FrameExportKind& k : frame_export_kinds()) {
        if (!due(k.kind, frame)) continue;
        const std::filesystem::path path = file(k.kind, frame);
        if (!capture.has(k.needs))
            return Error{"cannot write " + path.string() + ": frame " + std::to_string(frame) +
                         " captured nothing for it (a bug in aquaform: please report it)"};
        Result<bool> written = true;
        switch (k.kind) {
            case FrameExport::ply: written = write_particles_ply(path, *capture.particles); break;
            case FrameExport::vtk:
                written = write_particles_vtu(path, *capture.particles);
                if (written) written = vtk_collection_.add(time_s, path.filename().string());
                break;
            case FrameExport::vdb: written = write_density_vdb(path, *capture.volume); break;
            case FrameExport::mesh: written = write_mesh(path, *capture.mesh, options_.mesh_format); break;
        }
        if (!written) return written;
    }
    return true;
}

}  // namespace aquaform
