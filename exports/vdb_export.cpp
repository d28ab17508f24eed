#include "exports/vdb_export.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

#include <openvdb/io/Archive.h>
#include <openvdb/openvdb.h>

#include "core/file_write.h"

namespace aquaform {

namespace {

/// Why `volume` cannot be written, or empty.
std::string volume_problem(const DensityVolume& volume) {
    // No samples at all is a frame without fluid (a scene whose water all comes from nozzles, a
    // drain that took it all): an empty grid, so that a series keeps a file for every frame.
    if (volume.values.size() != volume.sample_count())
        return "the volume holds " + std::to_string(volume.values.size()) + " values for " +
               std::to_string(volume.dims.x) + "x" + std::to_string(volume.dims.y) + "x" +
               std::to_string(volume.dims.z) + " samples";
    if (!(volume.voxel > 0.0f) || !std::isfinite(volume.voxel))
        return "the voxel size is " + std::to_string(volume.voxel) + " m; it must be a positive number";
    if (!std::isfinite(volume.origin.x) || !std::isfinite(volume.origin.y) || !std::isfinite(volume.origin.z))
        return "the origin is not finite";
    // OpenVDB indexes voxels with 32-bit signed coordinates.
    if (std::max({volume.dims.x, volume.dims.y, volume.dims.z}) > uint32_t(std::numeric_limits<int32_t>::max()))
        return "the volume is too large for OpenVDB's 32-bit indices";
    return {};
}

/// OpenVDB's file format (with the grid offsets that random access needs, as io::File writes
/// it), encoded into memory so that the project's file writer does the writing: io::File does
/// not check its stream after writing, so a full disk would go unnoticed.
class InMemoryVdbFile : public openvdb::io::Archive {
public:
    std::string encode(const openvdb::GridCPtrVec& grids) const {
        std::ostringstream out(std::ios::binary);
        Archive::write(out, grids, /*seekable=*/true);
        return std::move(out).str();
    }
};

openvdb::FloatGrid::Ptr density_grid(const DensityVolume& volume) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->setSaveFloatAsHalf(false);
    openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(volume.voxel);
    transform->postTranslate(openvdb::Vec3d(volume.origin.x, volume.origin.y, volume.origin.z));
    grid->setTransform(transform);
    grid->insertMeta("aquaform_iso", openvdb::FloatMetadata(volume.iso));
    auto accessor = grid->getAccessor();
    for (uint32_t k = 0; k < volume.dims.z; ++k)
        for (uint32_t j = 0; j < volume.dims.y; ++j)
            for (uint32_t i = 0; i < volume.dims.x; ++i) {
                const float phi = volume.at(i, j, k);
                if (phi > kVdbZeroTolerance)  // also leaves out NaN
                    accessor.setValue(openvdb::Coord(int(i), int(j), int(k)), phi);
            }
    grid->pruneGrid(0.0f);  // uniform blocks become tiles
    return grid;
}

}  // namespace

Result<bool> write_density_vdb(const std::filesystem::path& path, const DensityVolume& volume) {
    if (const std::string problem = volume_problem(volume); !problem.empty())
        return Error{"cannot write " + path.string() + ": " + problem + "; sample the volume again"};
    static std::once_flag initialised;
    std::call_once(initialised, [] { openvdb::initialize(); });
    std::string bytes;
    try {
        bytes = InMemoryVdbFile().encode(openvdb::GridCPtrVec{density_grid(volume)});
    } catch (const std::exception& e) {
        return Error{"cannot write " + path.string() + ": OpenVDB failed to encode the volume (" + e.what() +
                     "); sample a smaller volume"};
    }
    return write_file_with(path, [&](std::ostream& out) { out.write(bytes.data(), std::streamsize(bytes.size())); });
}

}  // namespace aquaform
