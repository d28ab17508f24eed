#include "exports/frame_exports.h"

#include <cstdio>

#include "exports/vdb_export.h"
#include "sim/particle_io.h"

namespace aquaform {

const std::array<FrameExportKind, kFrameExportKinds>& frame_export_kinds() {
    static const std::array<FrameExportKind, kFrameExportKinds> kinds = {{
        {FrameExport::ply, "--ply-every", "particles_%04u.ply", true, false},
        {FrameExport::vtk, "--vtk-every", "particles_%04u.vtu", true, false},
        {FrameExport::vdb, "--vdb-every", "density_%04u.vdb", false, true},
    }};
    return kinds;
}

FrameExports::FrameExports(std::filesystem::path dir, const std::array<uint32_t, kFrameExportKinds>& every)
    : dir_(std::move(dir)), every_(every), vtk_collection_(dir_ / "particles.pvd") {}

bool FrameExports::due(FrameExport kind, uint32_t frame) const {
    const uint32_t every = every_[size_t(kind)];
    return every > 0 && frame % every == 0;
}

bool FrameExports::needs_particles(uint32_t frame) const {
    for (const FrameExportKind& k : frame_export_kinds())
        if (k.needs_particles && due(k.kind, frame)) return true;
    return false;
}

bool FrameExports::needs_volume(uint32_t frame) const {
    for (const FrameExportKind& k : frame_export_kinds())
        if (k.needs_volume && due(k.kind, frame)) return true;
    return false;
}

std::filesystem::path FrameExports::file(FrameExport kind, uint32_t frame) const {
    char name[64];
    std::snprintf(name, sizeof name, frame_export_kinds()[size_t(kind)].file_pattern, frame);
    return dir_ / name;
}

Result<bool> FrameExports::write(uint32_t frame, double time_s, const FrameCapture& capture) {
    for (const FrameExportKind& k : frame_export_kinds()) {
        if (!due(k.kind, frame)) continue;
        const std::filesystem::path path = file(k.kind, frame);
        if ((k.needs_particles && !capture.particles) || (k.needs_volume && !capture.volume))
            return Error{"cannot write " + path.string() + ": frame " + std::to_string(frame) +
                         " captured no " + (k.needs_particles ? "particles" : "density volume") +
                         " (a bug in aquaform: please report it)"};
        Result<bool> written = true;
        switch (k.kind) {
            case FrameExport::ply: written = write_particles_ply(path, *capture.particles); break;
            case FrameExport::vtk:
                written = write_particles_vtu(path, *capture.particles);
                if (written) written = vtk_collection_.add(time_s, path.filename().string());
                break;
            case FrameExport::vdb: written = write_density_vdb(path, *capture.volume); break;
        }
        if (!written) return written;
    }
    return true;
}

}  // namespace aquaform
