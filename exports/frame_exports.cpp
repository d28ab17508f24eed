#include "exports/frame_exports.h"

#include <cstdio>

#include "core/format_text.h"
#include "exports/vdb_export.h"
#include "sim/particle_io.h"

namespace aquaform {

glm::vec3 z_up(const glm::vec3& p) { return {p.x, -p.z, p.y}; }

namespace {

const char* extension_of(WhitewaterFormat format) { return format == WhitewaterFormat::vtp ? "vtp" : "ply"; }

using aquaform::z_up;  // the point's, beside this namespace's overloads

/// z_up of the position, w (a particle's id or tag) kept.
glm::vec4 z_up(const glm::vec4& p) { return {p.x, -p.z, p.y, p.w}; }

/// The volume on the rotated lattice: a quarter turn maps samples onto samples, so this is a
/// reordering, not a resampling. Sample (i, j, k) goes to (i, dims.z - 1 - k, j), and the new
/// origin is the rotated corner with the lowest coordinates.
DensityVolume z_up(const DensityVolume& v) {
    DensityVolume out = v;
    out.dims = {v.dims.x, v.dims.z, v.dims.y};
    out.origin = z_up(v.origin + glm::vec3(0.0f, 0.0f, v.voxel * float(v.dims.z - 1)));
    for (uint32_t k = 0; k < v.dims.z; ++k)
        for (uint32_t j = 0; j < v.dims.y; ++j)
            for (uint32_t i = 0; i < v.dims.x; ++i) out.values[out.index(i, v.dims.z - 1 - k, j)] = v.at(i, j, k);
    return out;
}

/// `capture` in the z-up frame (a copy: the capture stays the simulation's).
FrameCapture z_up(const FrameCapture& capture) {
    FrameCapture out;
    out.particles = capture.particles;
    out.mesh = capture.mesh;
    if (out.particles) {
        for (glm::vec4& x : out.particles->x) x = z_up(x);
        for (glm::vec4& v : out.particles->v) v = z_up(v);
    }
    out.whitewater = capture.whitewater;
    if (out.whitewater) {
        for (glm::vec4& x : out.whitewater->x) x = z_up(x);
        for (glm::vec4& v : out.whitewater->v) v = z_up(v);
    }
    if (out.mesh) {  // its lattice fields stay the simulation's: no writer reads them
        for (glm::vec3& p : out.mesh->vertices) p = z_up(p);
        for (glm::vec3& n : out.mesh->normals) n = z_up(n);
    }
    // A malformed volume stays as it is, for the writer to refuse with the reason.
    if (capture.volume) {
        const bool whole = capture.volume->values.size() == capture.volume->sample_count();
        out.volume = whole ? z_up(*capture.volume) : *capture.volume;
    }
    return out;
}

}  // namespace

const std::array<FrameExportKind, kFrameExportKinds>& frame_export_kinds() {
    static const std::array<FrameExportKind, kFrameExportKinds> kinds = {{
        {FrameExport::ply, "ply", "--ply-every", "particles", ".ply", FrameData::particles},
        {FrameExport::vtk, "vtk", "--vtk-every", "particles", ".vtu", FrameData::particles},
        {FrameExport::vdb, "vdb", "--vdb-every", "density", ".vdb", FrameData::volume},
        {FrameExport::mesh, "mesh", "--mesh-every", "surface", ".obj", FrameData::mesh},
        {FrameExport::whitewater, "whitewater", "--whitewater-every", "whitewater", ".ply", FrameData::whitewater},
    }};
    return kinds;
}

Result<WhitewaterFormat> parse_whitewater_format(const std::string& text) {
    if (text == "ply") return WhitewaterFormat::ply;
    if (text == "vtp") return WhitewaterFormat::vtp;
    return Error{"unknown whitewater format '" + text + "'; use ply (Blender) or vtp (ParaView)"};
}

Result<UpAxis> parse_up_axis(const std::string& text) {
    if (text == "y") return UpAxis::y;
    if (text == "z") return UpAxis::z;
    return Error{"unknown up axis '" + text + "'; use y (the simulation's, ParaView's) or z (Blender's)"};
}

FrameExports::FrameExports(std::filesystem::path dir, const FrameExportOptions& options)
    : dir_(std::move(dir)),
      options_(options),
      particles_pvd_(dir_ / "particles.pvd"),
      surface_pvd_(dir_ / "surface.pvd"),
      whitewater_pvd_(dir_ / "whitewater.pvd") {}

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
    const FrameExportKind& k = frame_export_kinds()[size_t(kind)];
    std::filesystem::path path = dir_ / numbered_file(k.file_stem, frame / every(kind), k.extension);
    if (kind == FrameExport::mesh) path.replace_extension(mesh_format_extension(options_.mesh_format));
    if (kind == FrameExport::whitewater) path.replace_extension(extension_of(options_.whitewater_format));
    return path;
}

Result<bool> FrameExports::write(uint32_t frame, double time_s, const FrameCapture& capture) {
    std::optional<FrameCapture> rotated;
    for (const FrameExportKind& k : frame_export_kinds()) {
        if (!due(k.kind, frame)) continue;
        const std::filesystem::path path = file(k.kind, frame);
        if (!capture.has(k.needs))
            return Error{"cannot write " + path.string() + ": frame " + std::to_string(frame) +
                         " captured nothing for it (a bug in aquaform: please report it)"};
        if (options_.up == UpAxis::z && !rotated) rotated = z_up(capture);  // once for all kinds
        Result<bool> written = write_file(k.kind, path, time_s, rotated ? *rotated : capture);
        if (written) written = list(path, k, frame, time_s);
        if (!written) return written;
    }
    return true;
}

Result<bool> FrameExports::write_file(FrameExport kind, const std::filesystem::path& path, double time_s,
                                      const FrameCapture& frame) {
    switch (kind) {
        case FrameExport::ply:
            return write_particles_ply(path, *frame.particles);
        case FrameExport::vtk: {
            Result<bool> written = write_particles_vtu(path, *frame.particles);
            return written ? particles_pvd_.add(time_s, path.filename()) : written;
        }
        case FrameExport::vdb:
            return write_density_vdb(path, *frame.volume);
        case FrameExport::whitewater: {
            if (options_.whitewater_format == WhitewaterFormat::ply)
                return write_whitewater_ply(path, *frame.whitewater);
            Result<bool> written = write_whitewater_vtp(path, *frame.whitewater);
            return written ? whitewater_pvd_.add(time_s, path.filename()) : written;
        }
        case FrameExport::mesh: {
            Result<bool> written = write_mesh(path, *frame.mesh, options_.mesh_format);
            if (!written || options_.mesh_format != MeshFormat::vtp) return written;
            return surface_pvd_.add(time_s, path.filename());
        }
    }
    return true;
}

Result<bool> FrameExports::list(const std::filesystem::path& file, const FrameExportKind& kind, uint32_t frame,
                                double time_s) {
    if (!listing_.is_open()) {
        auto opened = AppendedFile::open(dir_ / kExportListing);
        if (!opened) return Error{opened.error()};
        listing_ = std::move(opened.value());
        if (auto header = listing_.append("file,kind,frame,time_s\n"); !header) return header;
    }
    return listing_.append(file.filename().string() + "," + kind.name + "," + std::to_string(frame) + "," +
                           format_text(kTimeFormat, time_s) + "\n");
}

}  // namespace aquaform
