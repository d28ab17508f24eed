#include "study/shard_run.h"

#include <algorithm>

#include "core/version.h"

namespace aquaform::study {

Result<bool> check_shard_folder(const std::filesystem::path& out_dir, const std::optional<StudyShard>& shard,
                                bool fresh) {
    auto held = read_manifest(out_dir);
    if (!held) return Error{held.error()};
    if (!held.value() || fresh) return true;
    const StudyShard theirs = held.value()->shard;
    if (shard && *shard == theirs) return true;
    return Error{out_dir.string() + " holds shard " + theirs.text() + " of " + held.value()->spec_name + " (" +
                 kManifestName + "), not " + (shard ? "shard " + shard->text() : std::string("an unsharded run")) +
                 ": give each shard its own --out, or pass --fresh to start over there"};
}

ShardRun::ShardRun(const StudySpec& spec, const std::filesystem::path& spec_path, std::optional<uint64_t> particles,
                   std::optional<StudyShard> shard, const std::filesystem::path& out_dir, bool fresh)
    : spec_(spec), shard_(shard), out_dir_(out_dir) {
    for (const StudyUnit& unit : study_units(spec)) total_cells_ += unit.cells.size();
    if (!shard_) return;
    // A shard measures the cells of its units only (study/study_shards.h) and says so in its manifest.
    for (const StudyUnit& unit : shard_units(spec, *shard_)) {
        manifest_.cells.insert(manifest_.cells.end(), unit.cells.begin(), unit.cells.end());
        if (unit.solver_map)
            maps_.insert(*unit.solver_map);
        else
            cells_.insert(unit.cells.begin(), unit.cells.end());
    }
    if (auto before = read_manifest(out_dir); before && before.value() && !fresh)
        manifest_.wall_s = before.value()->wall_s;  // a resumed shard's time goes on
    manifest_.spec_hash = spec_hash(spec);
    manifest_.spec_name = spec.name;
    manifest_.spec_path = std::filesystem::absolute(spec_path).lexically_normal().string();
    manifest_.particles = particles;
    manifest_.version = aquaform_version();
    manifest_.shard = *shard_;
}

std::string ShardRun::describe() const {
    return "shard " + shard_->text() + ": " + std::to_string(manifest_.cells.size()) + " of " +
           std::to_string(total_cells_) + " cells (study and solver map)";
}

bool ShardRun::complete(const StudyFiles& files) const {
    return std::all_of(manifest_.cells.begin(), manifest_.cells.end(), [&](const std::string& cell) {
        return cells_.count(cell) ? files.done(cell) : files.map_done(cell);
    });
}

Result<bool> ShardRun::write_manifest(const std::string& device, bool complete) {
    if (!shard_) return true;
    ShardManifest written = manifest_;
    written.device = device;
    written.complete = complete;
    written.wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    return study::write_manifest(out_dir_, written);
}

}  // namespace aquaform::study
