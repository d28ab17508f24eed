#include "sim/particle_io.h"

#include <ostream>

#include "core/file_write.h"

namespace aquaform {

Result<bool> write_particles_ply(const std::filesystem::path& path, const ParticleSnapshot& s) {
    return write_file_with(path, [&](std::ostream& out) {
        const size_t n = s.x.size();
        out << "ply\nformat binary_little_endian 1.0\ncomment aquaform particles (SI units)\n"
            << "element vertex " << n << "\n"
            << "property float x\nproperty float y\nproperty float z\n"
            << "property float vx\nproperty float vy\nproperty float vz\n"
            << "property float density\nproperty uint id\nproperty uint tag\nend_header\n";
        for (size_t i = 0; i < n && out; ++i) {
            float f[7] = {
                s.x[i].x, s.x[i].y, s.x[i].z, s.v[i].x, s.v[i].y, s.v[i].z, i < s.density.size() ? s.density[i] : 0.0f};
            uint32_t u[2] = {static_cast<uint32_t>(s.x[i].w), static_cast<uint32_t>(s.v[i].w)};
            out.write(reinterpret_cast<const char*>(f), sizeof f);
            out.write(reinterpret_cast<const char*>(u), sizeof u);
        }
    });
}

Result<bool> write_whitewater_ply(const std::filesystem::path& path, const WhitewaterSnapshot& d) {
    return write_file_with(path, [&](std::ostream& out) {
        const size_t n = d.x.size();
        out << "ply\nformat binary_little_endian 1.0\ncomment aquaform whitewater (SI units; kind 0 spray, 1 foam, 2 bubble)\n"
            << "element vertex " << n << "\n"
            << "property float x\nproperty float y\nproperty float z\n"
            << "property float vx\nproperty float vy\nproperty float vz\n"
            << "property uchar kind\nproperty float life\nend_header\n";
        for (size_t i = 0; i < n && out; ++i) {
            const float f[6] = {d.x[i].x, d.x[i].y, d.x[i].z, d.v[i].x, d.v[i].y, d.v[i].z};
            const uint8_t kind = static_cast<uint8_t>(d.v[i].w);
            const float life = d.x[i].w;
            out.write(reinterpret_cast<const char*>(f), sizeof f);
            out.write(reinterpret_cast<const char*>(&kind), 1);
            out.write(reinterpret_cast<const char*>(&life), sizeof life);
        }
    });
}

}  // namespace aquaform
