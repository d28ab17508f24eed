// Charts of a study: runs scripts/study_charts.py (matplotlib) over the CSV files a study wrote.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"

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

}  // namespace aquaform::study
