// The row files of a study (study.csv, study_passes.csv, solver_map.csv), written a row at a time
// as each is measured and flushed, so that an interrupted study keeps everything it measured, and
// read back so that a rerun resumes: every row carries the spec's hash and its cell's key
// (columns "spec" and "cell", last), a rerun of the same spec skips the cells present, and a
// folder holding rows of another spec (or another version's columns) is refused, not mixed.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/file_write.h"
#include "core/result.h"
#include "study/study_run.h"
#include "study/study_solver_map.h"

namespace aquaform::study {

/// `rows` in the order of study_cell_keys(spec) (a failed frame's row where its first cell goes).
std::vector<StudyRow> in_spec_order(const StudySpec& spec, std::vector<StudyRow> rows);

/// How a folder's row files are opened: to measure into (a study, a shard), or only to read (a
/// merge reads its shards without touching them: they may be on a read-only mount, and a torn
/// line is a shard's to measure again, not the merge's to drop).
enum class RowAccess { append, read_only };

/// One CSV file of rows keyed by (spec, cell), opened for appending.
class RowFile {
public:
    using Fields = std::vector<std::string>;
    /// Opens `path` for the spec with hash `spec`: a new file gets `header`; an existing one keeps its
    /// complete rows (a line torn by a kill is dropped) that `keep` accepts, and is refused (naming the
    /// file) when its header differs or it holds rows of another spec. read_only: the file is read
    /// as it is (none: no rows) and append() refuses.
    static Result<RowFile> open(const std::filesystem::path& path, const std::string& header, const std::string& spec,
                                const std::function<bool(const Fields&)>& keep = {},
                                RowAccess access = RowAccess::append);
    const std::vector<Fields>& kept() const { return kept_; }
    size_t column(const std::string& name) const;  ///< index in the header (the header names it)
    /// Writes `line` (no line break) and flushes it to the file.
    Result<bool> append(const std::string& line);

private:
    std::filesystem::path path_;
    std::vector<std::string> columns_;
    std::vector<Fields> kept_;
    AppendedFile out_;  // none when read only
};

/// The three files of a study in one folder, for one spec.
class StudyFiles {
public:
    /// `fresh` removes the rows (and study.md, and a shard's manifest.json) of an earlier run first.
    static Result<StudyFiles> open(const std::filesystem::path& dir, const StudySpec& spec, bool fresh,
                                   RowAccess access = RowAccess::append);

    /// Measured already (the cell, or its whole frame when that failed to simulate).
    bool done(const std::string& cell) const;
    size_t cells_done() const;  ///< of study_cell_keys(spec)
    size_t cells_total() const { return cells_.size(); }
    /// Appends the row's passes, then the row (the row last: a row present has its passes).
    Result<bool> add(const StudyRow& row);
    bool map_done(const SolverMapRecord& record) const;
    bool map_done(const std::string& cell) const { return map_done_.count(cell) > 0; }  ///< solver_map_cell_key
    size_t map_cells_kept() const { return map_done_.size(); }
    Result<bool> add(const SolverMapRecord& record);
    /// The solver map rows the folder held when opened (their last field is the cell's key).
    const std::vector<RowFile::Fields>& map_rows() const { return map_->kept(); }
    /// Appends a row of another folder's solver_map.csv of the same spec (merging shards).
    Result<bool> add_map_row(const RowFile::Fields& fields);
    /// Every row of the spec so far, as the files hold them (so a resumed study's report equals
    /// an uninterrupted one's), in the spec's order, with the spec's method configurations.
    std::vector<StudyRow> rows() const;

private:
    StudyRow read_back(const RowFile::Fields& fields,
                       const std::map<std::string, std::map<std::string, double>>& passes) const;

    const StudySpec* spec_ = nullptr;
    std::string hash_;
    std::vector<std::string> cells_;  ///< study_cell_keys(spec)
    std::optional<RowFile> study_, passes_, map_;
    std::vector<StudyRow> rows_;
    std::set<std::string> done_, map_done_;
};

}  // namespace aquaform::study
