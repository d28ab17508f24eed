// A study run's share of the cells while it measures (`aquaform study --shard K/N`): which cells
// and solver maps it owns, its manifest.json, and the folder rule (one shard a folder). An
// unsharded run owns every cell and writes no manifest.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>

#include "core/result.h"
#include "study/study_rows.h"
#include "study/study_shards.h"
#include "study/study_spec.h"

namespace aquaform::study {

/// `--shard K/N` (or an unsharded run, `shard` empty) refused in a folder holding another shard's
/// (or the whole spec's) manifest, unless `fresh` starts over there.
Result<bool> check_shard_folder(const std::filesystem::path& out_dir, const std::optional<StudyShard>& shard,
                                bool fresh);

class ShardRun {
public:
    /// `spec_path` and `particles`: what the manifest records of the spec's identity. A resumed
    /// shard's wall time goes on from its manifest's (unless `fresh`).
    ShardRun(const StudySpec& spec, const std::filesystem::path& spec_path, std::optional<uint64_t> particles,
             std::optional<StudyShard> shard, const std::filesystem::path& out_dir, bool fresh);

    bool sharded() const { return shard_.has_value(); }
    bool owns_cell(const std::string& cell) const { return !shard_ || cells_.count(cell) > 0; }
    bool owns_map(size_t index) const { return !shard_ || maps_.count(index) > 0; }
    /// "shard K/N: C of T cells (study and solver map)".
    std::string describe() const;
    /// Every cell owned has its row in `files`.
    bool complete(const StudyFiles& files) const;
    /// Writes manifest.json (nothing when unsharded) with the wall time so far.
    Result<bool> write_manifest(const std::string& device, bool complete);

private:
    const StudySpec& spec_;
    std::optional<StudyShard> shard_;
    std::filesystem::path out_dir_;
    std::set<std::string> cells_;  ///< the study cells owned
    std::set<size_t> maps_;        ///< the solver maps owned
    ShardManifest manifest_;
    size_t total_cells_ = 0;
    std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

}  // namespace aquaform::study
