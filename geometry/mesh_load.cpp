// load_obj() (geometry/mesh.h): a mesh as read (mesh.cpp), repaired where its inside is still clear
// (faces turned to agree with their neighbours, holes closed: geometry/hole_fill.h) and checked.
// Apart from mesh.cpp so that the closing, which works on meshes, sits above them.
#include <optional>

#include "core/progress.h"
#include "geometry/hole_fill.h"
#include "geometry/mesh.h"

namespace aquaform::geometry {

Result<LoadedMesh> load_obj(const std::filesystem::path& path) {
    Result<Mesh> read = read_obj(path);
    if (!read) return Error{read.error()};
    LoadedMesh loaded;
    loaded.mesh = std::move(read).value();
    // Repair rather than refuse: which side is inside is clear once neighbours agree (see orient_consistently),
    // and once the holes are closed (see close_holes).
    std::optional<ProgressBar> checking;  // about a second per million faces
    if (loaded.mesh.faces.size() > (size_t(1) << 19)) checking.emplace("checking " + path.filename().string(), 3);
    const size_t turned = orient_consistently(loaded.mesh);
    if (checking) checking->update(1, "orientation done, checking edges");
    loaded.report = check_mesh(loaded.mesh);
    if (checking) checking->update(2, "edges checked, closing holes");
    const auto refused = [&](const MeshReport& report) -> std::optional<Error> {
        const std::string reason = unusable_reason(report);
        return reason.empty() ? std::nullopt : std::optional<Error>(Error{"mesh '" + path.string() + "': " + reason});
    };
    if (loaded.report.boundary_edge_count > 0) {
        if (auto error = refused(loaded.report)) return *error;  // a sheet: its caps would be the sheet itself
        const HoleClosing closing = close_holes(loaded.mesh);
        if (!closing.holes.empty()) loaded.report = check_mesh(loaded.mesh), record_closing(closing, loaded.report);
    }
    if (checking) checking->update(3), checking->finish();
    loaded.report.reoriented_face_count = turned;
    if (auto error = refused(loaded.report)) return *error;
    return loaded;
}

}  // namespace aquaform::geometry
