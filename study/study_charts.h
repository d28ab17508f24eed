// A study's report: study.md, and the charts that scripts/study_charts.py (matplotlib) draws from
// the CSV files a study wrote.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"
#include "study/study_run.h"

namespace aquaform::study {

/// The chart script, found in this order: $AQUAFORM_SCRIPTS_DIR (an explicit choice wins), then
/// beside a given executable `exe` (its ../share/aquaform/scripts, ../scripts, scripts), then
/// aquaform's data folders for the running one (core/data_dir.h: installed, build tree, source
/// tree). The error lists every place tried.
Result<std::filesystem::path> find_study_charts_script(const std::filesystem::path& exe = {});

/// The first of `candidates` (default: python3 on PATH, then /usr/bin/python3, Debian's, which
/// python3-matplotlib serves) that can import matplotlib; the error names every interpreter tried
/// and how to get matplotlib.
Result<std::string> find_chart_python(const std::vector<std::string>& candidates = {});

struct StudyCharts {
    std::vector<std::string> written;  ///< the chart files
    std::string drawn_by;              ///< "PYTHON SCRIPT": which interpreter ran which script
    /// Why none were drawn when the script or a Python with matplotlib is missing (what was tried,
    /// what to install): the study's CSV files and tables are whole without them, so not an error.
    std::string skipped;
};

/// Draws the charts of study.csv, study_passes.csv and solver_map.csv (those present) in
/// `out_dir` into out_dir/charts/ as PNG and SVG, with find_chart_python's interpreter. The error
/// is the script's failure (what it refused: a missing file or column).
Result<StudyCharts> draw_study_charts(const std::filesystem::path& out_dir);

/// study.md and the charts from the rows as the files hold them (StudyFiles::rows: a run, a
/// resumed run and a merge of shards report alike), printing the count of measurements, the
/// failed ones and the targets; false (the error printed) when one could not be written.
bool write_study_report(const std::filesystem::path& out_dir, const StudySpec& spec, const std::vector<StudyRow>& rows,
                        const std::string& device, bool charts);

}  // namespace aquaform::study
