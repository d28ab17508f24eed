// A study split over several processes or machines (`aquaform study SPEC --shard K/N`) and put
// back together (`aquaform study merge DIR... --out DIR`).
//
// The unit of work is a frame: one (case, particle count), whose every resolution and method is
// rendered on the same simulated frame and measured against references made from it, so a cell is
// never measured against another machine's frame or reference. Each solver map is a unit of its
// own. Units go to shards greedily, longest first, each to the shard with the least estimated cost
// so far (ties: the lower shard); units of equal cost in spec order. The estimate: a frame costs
// particles x pixels x methods summed over its resolutions (a scene file at its own count is
// taken as 4096 particles); a solver map costs its solver steps x iterations x 4096 x 100 (one
// step of a 4096-particle scene against rendering 100 pixels). Only a deterministic balance is
// needed: every shard computes the same split from the spec alone.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/result.h"
#include "study/study_run.h"
#include "study/study_spec.h"

namespace aquaform::study {

struct StudyShard {
    uint32_t index = 0, count = 1;
    std::string text() const { return std::to_string(index) + "/" + std::to_string(count); }
    bool operator==(const StudyShard&) const = default;
};

/// "K/N" with 0 <= K < N; the error (one line) names the flag and the form wanted.
Result<StudyShard> parse_shard(const std::string& text);

struct StudyUnit {
    std::string key;                   ///< the frame's key (study_frame_key), or "solver_map[i]"
    std::vector<std::string> cells;    ///< study cell keys, or solver map cell keys
    std::optional<size_t> solver_map;  ///< index in spec.solver_maps for a map's unit
    double cost = 0.0;                 ///< the estimate the split balances
};

/// Every unit of the spec, in spec order (frames, then solver maps).
std::vector<StudyUnit> study_units(const StudySpec& spec);
/// The units `shard` owns, in spec order.
std::vector<StudyUnit> shard_units(const StudySpec& spec, StudyShard shard);
/// The keys (solver_map_cell_key) of a map's cells, in the order run_solver_map runs them.
std::vector<std::string> solver_map_cell_keys(const SolverMapSpec& map);

/// manifest.json of a shard's folder: what it belongs to and whether it finished.
struct ShardManifest {
    std::string spec_hash, spec_name, spec_path;  ///< spec_path: absolute, for merge to read the spec
    std::optional<uint64_t> particles;            ///< the run's --particles (part of the spec's identity)
    std::string version, device;
    StudyShard shard;
    std::vector<std::string> cells;  ///< the study and solver map cells the shard owns
    double wall_s = 0.0;             ///< the shard's wall time, summed over resumed runs
    bool complete = false;           ///< every cell owned has its row
};

constexpr const char* kManifestName = "manifest.json";
Result<bool> write_manifest(const std::filesystem::path& dir, const ShardManifest& manifest);
/// Empty when `dir` has no manifest.json; an error when it has one that cannot be read.
Result<std::optional<ShardManifest>> read_manifest(const std::filesystem::path& dir);

/// One shard folder given to merge.
struct ShardInput {
    std::filesystem::path dir;
    ShardManifest manifest;
};

/// Reads every folder's manifest and checks them as a set: the same spec, the same N, every
/// shard 0..N-1 once and complete. Errors name the folders and the command that mends them.
Result<std::vector<ShardInput>> read_shard_set(const std::vector<std::filesystem::path>& dirs);

/// The spec the shards ran (their manifest's path and --particles), checked to have their hash.
/// `path`: the spec's file where the merge runs, when it is not at the manifest's path (another
/// machine, another mount); its hash must still match.
Result<StudySpec> load_shard_spec(const ShardInput& shard, const std::filesystem::path& path = {});

struct MergedStudy {
    std::vector<StudyRow> rows;  ///< as an unsharded run's files hold them, in its order
    /// The device of most cells, and, when shards ran on others, which (study.md's header);
    /// rows from another device carry theirs in StudyRow::device.
    std::string device;
};

/// Writes study.csv, study_passes.csv and solver_map.csv of `shards` into `out_dir` (in an
/// unsharded run's order) and copies their images, after checking that every cell of `spec` is in
/// exactly one shard (the error names the missing or doubled cells and their folders).
Result<MergedStudy> merge_shards(const StudySpec& spec, const std::vector<ShardInput>& shards,
                                 const std::filesystem::path& out_dir);

}  // namespace aquaform::study
