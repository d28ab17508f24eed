// Charts of a study: runs scripts/study_charts.py (matplotlib) over the CSV files a study wrote.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"

namespace aquaform::study {

/// The chart script, found in this order: $AQUAFORM_SCRIPTS_DIR (an explicit choice wins),
/// then beside the running executable (/proc/self/exe): <exe dir>/../scripts, <exe dir>/scripts,
/// <exe dir>/../../scripts (the test binary one level down in the build tree). The error lists
/// every place tried.
Result<std::filesystem::path> find_study_charts_script();

/// Draws the charts of study.csv, study_passes.csv and solver_map.csv (those present) in
/// `out_dir` into out_dir/charts/ as PNG and SVG, with /usr/bin/python3 when it exists (Debian's,
/// which python3-matplotlib serves), else python3 on PATH. Returns the files written; the error
/// names what to install or what the script refused (a missing file or column).
Result<std::vector<std::string>> draw_study_charts(const std::filesystem::path& out_dir);

}  // namespace aquaform::study
