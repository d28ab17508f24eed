#include "study/study_rows.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include "core/csv.h"

namespace aquaform::study {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStudyColumns =
    "case,scene,method,width,height,particles,metaball_scale,recursion_depth,bisection_steps,visual,ms_total,fps,"
    "depth_err_mean,depth_err_p95,normal_err_deg_mean,coverage_mismatch,psnr_db,overflow,status,rays,steps_per_ray,"
    "bisection_per_ray,evals_per_ray,mask_leaps_per_ray,list_entries_per_pixel,list_bytes_per_pixel,"
    "particle_visits_per_pixel,memory_bytes_per_pixel,roughness_deg,image,steps_image,spec,cell";
constexpr const char* kPassesColumns = "case,scene,method,width,height,particles,pass,ms,spec,cell";

/// The way out of a folder whose rows this run may not extend.
constexpr const char* kKeepOrStartOver =
    "; to keep those rows, run this spec with another --out; to start over in that folder, pass --fresh";

/// The complete lines of `path`; `torn`: a last line without its line break (cut by a kill).
std::vector<std::string> complete_lines(const fs::path& path, bool* torn) {
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::string> lines;
    size_t start = 0;
    for (size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
        lines.push_back(text.substr(start, end - start));
    *torn = start != text.size();
    return lines;
}

std::optional<double> number(const std::string& field) {
    if (field.empty()) return std::nullopt;
    try {
        return std::stod(field);
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

uint32_t whole(const std::string& field) { return uint32_t(number(field).value_or(0.0)); }

double fps(double ms) { return ms > 0.0 ? 1000.0 / ms : 0.0; }

/// "case/1000" of "case/1000/96x64/method" (study_cell_key), or the frame key itself.
std::string frame_of(const std::string& cell) { return cell.substr(0, cell.find('/', cell.find('/') + 1)); }

/// Columns of the row files that hold text; every other column holds a number or nothing.
bool text_column(const std::string& name) {
    static const std::set<std::string> names{"case",  "scene",       "method", "visual", "status",
                                             "image", "steps_image", "pass",   "spec",   "cell"};
    return names.count(name) > 0;
}

/// Columns that count (sizes, steps, rays): whole numbers from 0 to the largest returned (0:
/// not such a column).
double whole_column_limit(const std::string& name) {
    static const std::set<std::string> counts{"width",           "height",     "particles", "recursion_depth",
                                              "bisection_steps", "iterations", "stable"};
    if (counts.count(name)) return 4294967295.0;
    return name == "rays" ? 9007199254740992.0 : 0.0;  // 2^53: counted in a double exactly
}

/// What is wrong with a row's fields (empty when nothing): every number must be finite, and
/// every count a whole number this program can hold. Every value read from a file is input.
std::string row_problem(const std::vector<std::string>& columns, const std::vector<std::string>& fields) {
    if (fields.size() != columns.size())
        return std::to_string(fields.size()) + " fields where the header has " + std::to_string(columns.size());
    for (size_t c = 0; c < columns.size(); ++c) {
        const std::string& field = fields[c];
        if (field.empty() || text_column(columns[c])) continue;
        double v = 0.0;
        const char* end = field.data() + field.size();
        const auto [stop, ec] = std::from_chars(field.data(), end, v);
        const bool finite = ec == std::errc() && stop == end && std::isfinite(v);
        const double limit = whole_column_limit(columns[c]);
        const bool whole_ok = limit == 0.0 || (v >= 0.0 && v <= limit && v == std::floor(v));
        if (!finite || !whole_ok)
            return "\"" + columns[c] + "\" is \"" + field.substr(0, 40) + "\", not " +
                   (limit > 0.0 ? "a whole number from 0 to " + format_number("%.0f", limit)
                                : std::string("a finite number"));
    }
    return "";
}

}  // namespace

Result<RowFile> RowFile::open(const fs::path& path, const std::string& header, const std::string& spec,
                              const std::function<bool(const Fields&)>& keep, RowAccess access) {
    RowFile file;
    file.path_ = path;
    file.columns_ = split_csv_line(header);
    const size_t spec_column = file.column("spec");
    std::error_code ec;
    const bool existed = fs::exists(path, ec);
    if (existed && !fs::is_regular_file(path, ec))
        return Error{
            path.string() +
            " is not a file; move it away (aquaform study writes it: run it with --fresh to start that folder over)"};
    bool rewrite = !existed;
    if (existed) {
        bool torn = false;
        const std::vector<std::string> lines = complete_lines(path, &torn);
        const size_t pass_column = file.column("pass");
        std::map<std::string, size_t> line_of;  // a row's key -> the line that holds it
        if (lines.empty())
            rewrite = true;  // killed before its header was whole: nothing kept
        else if (lines[0] != header)
            return Error{path.string() + " has other columns than this version of aquaform writes" + kKeepOrStartOver};
        for (size_t i = 1; i < lines.size(); ++i) {
            Fields fields = split_csv_line(lines[i]);
            if (const std::string problem = row_problem(file.columns_, fields); !problem.empty()) {
                // Damaged: a run measures the row again; a merge, which only reads, says where.
                if (access == RowAccess::read_only)
                    return Error{
                        path.string() + " line " + std::to_string(i + 1) + ": " + problem +
                        "; it is written by aquaform study: rerun that folder's study (or shard) with --fresh"};
                rewrite = true;
                continue;
            }
            if (fields[spec_column] != spec)
                return Error{path.string() + " holds rows of another spec (or of its scene files as they were then)" +
                             kKeepOrStartOver};
            if (keep && !keep(fields)) {
                rewrite = true;
                continue;
            }
            // A row is one cell's (one pass of it in study_passes.csv): a second one for the same
            // is dropped by a run, and refused by a merge, as a cell in two shards is.
            const std::string key =
                fields.back() + (pass_column < fields.size() ? ", pass " + fields[pass_column] : "");
            if (const auto [first, added] = line_of.emplace(key, i + 1); !added) {
                if (access == RowAccess::read_only)
                    return Error{path.string() + " lines " + std::to_string(first->second) + " and " +
                                 std::to_string(i + 1) + " both hold the row of " + key +
                                 "; a folder holds each row once: delete one of the two lines, or rerun that "
                                 "folder's study (or shard) with --fresh"};
                rewrite = true;
                continue;
            }
            file.kept_.push_back(std::move(fields));
        }
        rewrite = rewrite || torn;
    }
    if (access == RowAccess::read_only) return file;
    if (rewrite) {  // the header and the rows kept, then appended to
        auto rewritten = write_file_with(path, [&](std::ostream& out) {
            out << header << '\n';
            for (const Fields& fields : file.kept_) out << csv_line(fields) << '\n';
        });
        if (!rewritten) return rewritten.failure();
    }
    auto out = AppendedFile::open(path, AppendedFile::Start::after_existing);
    if (!out) return out.failure();
    file.out_ = std::move(out.value());
    return file;
}

size_t RowFile::column(const std::string& name) const {
    return size_t(std::find(columns_.begin(), columns_.end(), name) - columns_.begin());
}

Result<bool> RowFile::append(const std::string& line) {
    if (!out_.is_open()) return Error{"cannot add a row to " + path_.string() + ": it was opened only to be read"};
    return out_.append(line + '\n');
}

Result<StudyFiles> StudyFiles::open(const fs::path& dir, const StudySpec& spec, bool fresh, RowAccess access) {
    if (fresh)
        for (const char* name : {"study.csv", "study_passes.csv", "solver_map.csv", "study.md", "manifest.json"}) {
            std::error_code ec;
            fs::remove(dir / name, ec);
        }
    StudyFiles files;
    files.spec_ = &spec;
    files.hash_ = spec_hash(spec);
    files.cells_ = study_cell_keys(spec);
    const std::set<std::string> cells(files.cells_.begin(), files.cells_.end());
    std::set<std::string> frames;  // a frame that failed to simulate has a row of its own
    for (const std::string& cell : files.cells_) frames.insert(frame_of(cell));

    auto study = RowFile::open(
        dir / "study.csv", kStudyColumns, files.hash_,
        [&](const RowFile::Fields& f) { return cells.count(f.back()) || frames.count(f.back()); }, access);
    if (!study) return study.failure();
    files.study_ = std::move(study.value());
    for (const RowFile::Fields& f : files.study_->kept()) files.done_.insert(f.back());
    auto passes = RowFile::open(
        dir / "study_passes.csv", kPassesColumns, files.hash_,
        [&](const RowFile::Fields& f) { return files.done_.count(f.back()) > 0; }, access);
    if (!passes) return passes.failure();
    files.passes_ = std::move(passes.value());
    auto map = RowFile::open(dir / "solver_map.csv", solver_map_csv_header(), files.hash_, {}, access);
    if (!map) return map.failure();
    files.map_ = std::move(map.value());
    for (const RowFile::Fields& f : files.map_->kept()) files.map_done_.insert(f.back());

    std::map<std::string, std::map<std::string, double>> by_cell;
    const size_t pass = files.passes_->column("pass"), ms = files.passes_->column("ms");
    for (const RowFile::Fields& f : files.passes_->kept()) by_cell[f.back()][f[pass]] = number(f[ms]).value_or(0.0);
    for (const RowFile::Fields& f : files.study_->kept()) files.rows_.push_back(files.read_back(f, by_cell));
    return files;
}

bool StudyFiles::done(const std::string& cell) const { return done_.count(cell) || done_.count(frame_of(cell)); }

size_t StudyFiles::cells_done() const {
    return size_t(std::count_if(cells_.begin(), cells_.end(), [&](const std::string& c) { return done(c); }));
}

Result<bool> StudyFiles::add(const StudyRow& r) {
    const std::string id = csv_field(r.case_name) + ',' + csv_field(r.scene) + ',' + csv_field(r.method) + ',' +
                           std::to_string(r.width) + ',' + std::to_string(r.height) + ',' + std::to_string(r.particles);
    const std::string key = ',' + hash_ + ',' + csv_field(r.cell);
    std::map<std::string, std::map<std::string, double>> by_cell;
    for (const auto& [pass, ms] : r.ms_per_pass) {
        const std::string ms_text = csv_number(ms);
        if (auto ok = passes_->append(id + ',' + csv_field(pass) + ',' + ms_text + key); !ok) return ok;
        by_cell[r.cell][pass] = number(ms_text).value_or(0.0);
    }
    const bool metaball = r.config.family == StudyFamily::metaball;
    std::ostringstream line;
    line << id << ',' << (metaball ? csv_number(r.config.size) : "") << ','
         << (metaball ? std::to_string(r.config.recursion) : "") << ','
         << (metaball ? std::to_string(r.config.bisection) : "") << ',' << (metaball ? r.config.visual : "") << ','
         << csv_number(r.ms_total) << ',' << csv_number(fps(r.ms_total)) << ',' << csv_number(r.depth_err_mean) << ','
         << csv_number(r.depth_err_p95) << ',' << csv_number(r.normal_err_deg_mean) << ','
         << csv_number(r.coverage_mismatch) << ',' << csv_number(r.psnr_db) << ',' << csv_number(r.overflow_mib) << ','
         << csv_field(r.status) << ',' << r.rays << ',' << csv_number(r.steps_per_ray) << ','
         << csv_number(r.bisection_per_ray) << ',' << csv_number(r.evals_per_ray) << ',' << csv_number(r.leaps_per_ray)
         << ',' << csv_number(r.list_entries_per_pixel) << ',' << csv_number(r.list_bytes_per_pixel) << ','
         << csv_number(r.particle_visits_per_pixel) << ',' << csv_number(r.memory_bytes_per_pixel) << ','
         << csv_number(r.roughness_deg) << ',' << csv_field(r.image) << ',' << csv_field(r.steps_image) << key;
    if (auto ok = study_->append(line.str()); !ok) return ok;
    done_.insert(r.cell);
    rows_.push_back(read_back(split_csv_line(line.str()), by_cell));
    return true;
}

StudyRow StudyFiles::read_back(const RowFile::Fields& f,
                               const std::map<std::string, std::map<std::string, double>>& passes) const {
    auto at = [&](const char* name) -> const std::string& { return f[study_->column(name)]; };
    StudyRow r;
    r.case_name = at("case");
    r.scene = at("scene");
    r.method = at("method");
    r.cell = at("cell");
    r.width = whole(at("width"));
    r.height = whole(at("height"));
    r.particles = whole(at("particles"));
    for (const StudyCase& c : spec_->cases)  // the configuration, from the spec the row was measured for
        if (c.name == r.case_name)
            for (const StudyMethod& m : c.methods)
                if (m.label() == r.method) r.config = m;
    r.ms_total = number(at("ms_total")).value_or(0.0);
    if (auto it = passes.find(r.cell); it != passes.end()) r.ms_per_pass = it->second;
    r.depth_err_mean = number(at("depth_err_mean"));
    r.depth_err_p95 = number(at("depth_err_p95"));
    r.normal_err_deg_mean = number(at("normal_err_deg_mean"));
    r.coverage_mismatch = number(at("coverage_mismatch"));
    r.psnr_db = number(at("psnr_db"));
    r.roughness_deg = number(at("roughness_deg"));
    r.overflow_mib = number(at("overflow")).value_or(0.0);
    r.status = at("status");
    r.image = at("image");
    r.steps_image = at("steps_image");
    r.rays = uint64_t(number(at("rays")).value_or(0.0));
    r.steps_per_ray = number(at("steps_per_ray"));
    r.bisection_per_ray = number(at("bisection_per_ray"));
    r.evals_per_ray = number(at("evals_per_ray")).value_or(0.0);
    r.leaps_per_ray = number(at("mask_leaps_per_ray"));
    r.list_entries_per_pixel = number(at("list_entries_per_pixel"));
    r.list_bytes_per_pixel = number(at("list_bytes_per_pixel"));
    r.particle_visits_per_pixel = number(at("particle_visits_per_pixel"));
    r.memory_bytes_per_pixel = number(at("memory_bytes_per_pixel")).value_or(0.0);
    return r;
}

std::vector<StudyRow> in_spec_order(const StudySpec& spec, std::vector<StudyRow> rows) {
    const std::vector<std::string> cells = study_cell_keys(spec);
    std::map<std::string, size_t> order;
    for (size_t i = 0; i < cells.size(); ++i) {
        order.emplace(cells[i], i);
        order.emplace(frame_of(cells[i]), i);  // a failed frame's row: where its first cell goes
    }
    std::stable_sort(rows.begin(), rows.end(),
                     [&](const StudyRow& a, const StudyRow& b) { return order[a.cell] < order[b.cell]; });
    return rows;
}

std::vector<StudyRow> StudyFiles::rows() const { return in_spec_order(*spec_, rows_); }

Result<bool> StudyFiles::add_map_row(const RowFile::Fields& fields) {
    if (auto ok = map_->append(csv_line(fields)); !ok) return ok;
    map_done_.insert(fields.back());
    return true;
}

bool StudyFiles::map_done(const SolverMapRecord& record) const {
    return map_done_.count(solver_map_cell_key(record)) > 0;
}

Result<bool> StudyFiles::add(const SolverMapRecord& record) {
    if (auto ok = map_->append(solver_map_csv_line(record, hash_)); !ok) return ok;
    map_done_.insert(solver_map_cell_key(record));
    return true;
}

}  // namespace aquaform::study
