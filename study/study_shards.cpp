#include "study/study_shards.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>

#include "core/file_write.h"
#include "core/text_escape.h"
#include "sim/scene.h"
#include "study/study_rows.h"

namespace aquaform::study {

namespace fs = std::filesystem;

namespace {

constexpr double kUnknownParticles = 4096.0;  ///< a scene file at its own count, for the estimate
constexpr double kMapStepCost = 4096.0 * 100.0;

std::optional<uint32_t> whole_number(const std::string& text) {
    uint32_t v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || text.empty()) return std::nullopt;
    return v;
}

std::string rerun(const ShardManifest& m, uint32_t index, const fs::path& dir) {
    return "rerun aquaform study " + (m.spec_path.empty() ? std::string("SPEC") : m.spec_path) +
           (m.particles ? " --particles " + std::to_string(*m.particles) : std::string()) + " --shard " +
           std::to_string(index) + "/" + std::to_string(m.shard.count) + " --out " + dir.string();
}

/// The files of `from` (a shard's images/) into `to`, each written as the project writes a file:
/// never through a link that is in `to` already.
Result<bool> copy_images(const fs::path& from, const fs::path& to) {
    std::error_code ec;
    if (!fs::is_directory(from, ec)) return true;
    for (auto it = fs::recursive_directory_iterator(from, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec)) {
        const fs::path target = to / fs::relative(it->path(), from, ec);
        if (it->is_directory(ec))
            fs::create_directories(target, ec);
        else if (it->is_regular_file(ec)) {
            fs::create_directories(target.parent_path(), ec);
            std::ifstream in(it->path(), std::ios::binary);
            if (!in) return Error{"cannot read " + it->path().string() + "; check that it is readable"};
            auto written = write_file_with(target, [&](std::ostream& out) {
                if (in.peek() != std::ifstream::traits_type::eof()) out << in.rdbuf();  // an empty file: nothing
            });
            if (!written) return written.failure();
        }
        if (ec) break;
    }
    if (ec) return Error{"cannot copy " + from.string() + " to " + to.string() + ": " + ec.message()};
    return true;
}

}  // namespace

Result<StudyShard> parse_shard(const std::string& text) {
    const size_t slash = text.find('/');
    const auto k = slash == std::string::npos ? std::nullopt : whole_number(text.substr(0, slash));
    const auto n = slash == std::string::npos ? std::nullopt : whole_number(text.substr(slash + 1));
    if (!k || !n || *n == 0 || *k >= *n)
        return Error{"--shard " + text + ": give K/N with N >= 1 shards and K from 0 to N-1, e.g. --shard 0/4"};
    return StudyShard{*k, *n};
}

std::vector<std::string> solver_map_cell_keys(const SolverMapSpec& map) {
    std::vector<std::optional<float>> pressures(map.control_pressures.begin(), map.control_pressures.end());
    if (pressures.empty()) pressures.push_back(std::nullopt);
    std::vector<std::string> keys;
    for (const std::optional<float>& pressure : pressures)
        for (uint32_t iterations : map.iterations)
            for (float dt : map.frame_dts) {
                SolverMapRecord id;
                id.scene = map.scene.stem().string();
                id.dt = dt;
                id.iterations = iterations;
                id.control_pressure = pressure;
                keys.push_back(solver_map_cell_key(id));
            }
    return keys;
}

std::vector<StudyUnit> study_units(const StudySpec& spec) {
    std::vector<StudyUnit> units;
    for (const StudyCase& c : spec.cases)
        for (const std::optional<uint32_t>& n : study_frame_counts(c)) {
            StudyUnit unit;
            unit.key = study_frame_key(c, n);
            for (const auto& [w, h] : c.resolutions) {
                for (const StudyMethod& m : c.methods) unit.cells.push_back(study_cell_key(unit.key, w, h, m.label()));
                unit.cost += (n ? double(*n) : kUnknownParticles) * double(w) * h * double(c.methods.size());
            }
            units.push_back(std::move(unit));
        }
    for (size_t i = 0; i < spec.solver_maps.size(); ++i) {
        const SolverMapSpec& map = spec.solver_maps[i];
        StudyUnit unit;
        unit.key = "solver_map[" + std::to_string(i) + "]";
        unit.solver_map = i;
        unit.cells = solver_map_cell_keys(map);
        for (float dt : map.frame_dts)
            for (uint32_t it : map.iterations)
                unit.cost += std::ceil(map.sim_time_s / std::max(dt, 1e-6f)) * it * kMapStepCost *
                             double(std::max<size_t>(1, map.control_pressures.size()));
        units.push_back(std::move(unit));
    }
    return units;
}

std::vector<StudyUnit> shard_units(const StudySpec& spec, StudyShard shard) {
    const std::vector<StudyUnit> units = study_units(spec);
    std::vector<size_t> order(units.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return units[a].cost > units[b].cost; });
    std::vector<double> load(shard.count, 0.0);
    std::vector<bool> mine(units.size(), false);
    for (size_t i : order) {
        const size_t least = size_t(std::min_element(load.begin(), load.end()) - load.begin());  // first of equals
        load[least] += units[i].cost;
        mine[i] = least == shard.index;
    }
    std::vector<StudyUnit> owned;
    for (size_t i = 0; i < units.size(); ++i)
        if (mine[i]) owned.push_back(units[i]);
    return owned;
}

Result<bool> write_manifest(const fs::path& dir, const ShardManifest& m) {
    nlohmann::json j = {{"spec_hash", m.spec_hash}, {"spec_name", m.spec_name}, {"spec_path", m.spec_path},
                        {"version", m.version},     {"device", m.device},       {"shard", m.shard.index},
                        {"shards", m.shard.count},  {"cells", m.cells},         {"wall_s", m.wall_s},
                        {"complete", m.complete}};
    j["particles"] = m.particles ? nlohmann::json(*m.particles) : nlohmann::json(nullptr);
    return write_file_with(dir / kManifestName, [&](std::ostream& out) { out << json_text(j, 2) << '\n'; });
}

Result<std::optional<ShardManifest>> read_manifest(const fs::path& dir) {
    const fs::path path = dir / kManifestName;
    std::error_code ec;
    if (!fs::exists(path, ec)) return std::optional<ShardManifest>();
    const std::string fix = "; it is written by aquaform study --shard: rerun that shard into a fresh folder";
    if (!fs::is_regular_file(path, ec)) return Error{path.string() + " is not a file" + fix};
    nlohmann::json j;
    try {
        std::ifstream in(path);
        j = nlohmann::json::parse(in);
    } catch (const std::exception& e) {
        return Error{path.string() + " is not JSON (" + e.what() + ")" + fix};
    }
    // Every value is input: checked for its type and range before anything indexes by it.
    std::string problem;
    auto key = [&](const char* name) -> const nlohmann::json* {
        if (!problem.empty()) return nullptr;
        if (!j.is_object() || !j.contains(name)) {
            problem = std::string("\"") + name + "\" is missing";
            return nullptr;
        }
        return &j.at(name);
    };
    auto text = [&](const char* name) {
        const nlohmann::json* v = key(name);
        if (v && !v->is_string()) problem = std::string("\"") + name + "\" must be a string";
        return v && v->is_string() ? v->get<std::string>() : std::string();
    };
    auto whole = [&](const char* name, uint64_t least, uint64_t most) -> uint64_t {
        const nlohmann::json* v = key(name);
        if (!v) return 0;
        if (!v->is_number_unsigned() || v->get<uint64_t>() < least || v->get<uint64_t>() > most) {
            problem = std::string("\"") + name + "\" is " + v->dump().substr(0, 40) + ", not a whole number from " +
                      std::to_string(least) + " to " + std::to_string(most);
            return 0;
        }
        return v->get<uint64_t>();
    };
    ShardManifest m;
    m.spec_hash = text("spec_hash");
    m.spec_name = text("spec_name");
    m.spec_path = text("spec_path");
    if (const nlohmann::json* v = key("particles"); v && !v->is_null())
        m.particles = whole("particles", kMinSceneParticles, kMaxSceneParticles);
    m.version = text("version");
    m.device = text("device");
    m.shard.count = uint32_t(whole("shards", 1, UINT32_MAX));
    if (problem.empty()) m.shard.index = uint32_t(whole("shard", 0, m.shard.count - 1));
    if (const nlohmann::json* v = key("cells")) {
        const bool strings =
            v->is_array() && std::all_of(v->begin(), v->end(), [](const auto& c) { return c.is_string(); });
        if (strings)
            m.cells = v->get<std::vector<std::string>>();
        else
            problem = "\"cells\" must be a list of cell names";
    }
    if (const nlohmann::json* v = key("wall_s")) {
        if (v->is_number() && std::isfinite(v->get<double>()) && v->get<double>() >= 0.0)
            m.wall_s = v->get<double>();
        else
            problem = "\"wall_s\" is " + v->dump().substr(0, 40) + ", not a time in seconds (0 or more)";
    }
    if (const nlohmann::json* v = key("complete")) {
        if (v->is_boolean())
            m.complete = v->get<bool>();
        else
            problem = "\"complete\" must be true or false";
    }
    if (!problem.empty()) return Error{path.string() + ": " + problem + fix};
    return std::optional<ShardManifest>(std::move(m));
}

Result<std::vector<ShardInput>> read_shard_set(const std::vector<fs::path>& dirs) {
    std::vector<ShardInput> shards;
    for (const fs::path& dir : dirs) {
        auto read = read_manifest(dir);
        if (!read) return read.failure();
        if (!read.value())
            return Error{dir.string() + " has no " + kManifestName +
                         ": give the folders that aquaform study SPEC --shard K/N --out DIR wrote"};
        shards.push_back({dir, *read.value()});
    }
    if (shards.empty())
        return Error{"give the shard folders to merge, e.g. aquaform study merge out/s0 out/s1 --out out/study"};
    const ShardInput& first = shards.front();
    for (const ShardInput& s : shards) {
        if (s.manifest.spec_hash != first.manifest.spec_hash)
            return Error{s.dir.string() + " holds shard " + s.manifest.shard.text() + " of spec " +
                         s.manifest.spec_name + " (" + s.manifest.spec_hash + ") but " + first.dir.string() +
                         " one of spec " + first.manifest.spec_name + " (" + first.manifest.spec_hash +
                         "): merge the shards of one spec (and one --particles)"};
        if (s.manifest.shard.count != first.manifest.shard.count)
            return Error{s.dir.string() + " holds shard " + s.manifest.shard.text() + " but " + first.dir.string() +
                         " shard " + first.manifest.shard.text() + ": merge shards of one split (one N)"};
    }
    const uint32_t n = first.manifest.shard.count;
    std::vector<const ShardInput*> by_index(n, nullptr);
    for (const ShardInput& s : shards) {
        const ShardInput*& slot = by_index[s.manifest.shard.index];
        if (slot)
            return Error{"shard " + s.manifest.shard.text() + " is given twice: " + slot->dir.string() + " and " +
                         s.dir.string() + "; give each shard once"};
        slot = &s;
    }
    for (uint32_t k = 0; k < n; ++k)
        if (!by_index[k])
            return Error{"shard " + std::to_string(k) + "/" + std::to_string(n) + " is missing; " +
                         rerun(first.manifest, k, "DIR") + " and add DIR to the merge"};
    for (const ShardInput& s : shards)
        if (!s.manifest.complete)
            return Error{"shard " + s.manifest.shard.text() + " in " + s.dir.string() +
                         " is incomplete (stopped before its last cell); " +
                         rerun(s.manifest, s.manifest.shard.index, s.dir) + " to resume it, then merge again"};
    return shards;
}

Result<StudySpec> load_shard_spec(const ShardInput& shard, const fs::path& path) {
    const ShardManifest& m = shard.manifest;
    const std::string spec_path = path.empty() ? m.spec_path : path.string();
    auto spec = load_study_spec(spec_path);
    if (!spec)
        return Error{"the spec of " + shard.dir.string() + ": " + spec.error() +
                     (path.empty() ? "; where it is elsewhere on this machine, give it with --spec PATH" : "")};
    if (m.particles)
        if (auto scaled = set_particle_count(spec.value(), *m.particles); !scaled)
            return Error{"the spec of " + shard.dir.string() + ": --particles: " + scaled.error()};
    if (spec_hash(spec.value()) != m.spec_hash)
        return Error{spec_path + " (or one of its scene files) changed since shard " + m.shard.text() + " in " +
                     shard.dir.string() + " ran (hash " + spec_hash(spec.value()) + ", not " + m.spec_hash +
                     "): restore it, or rerun every shard with --fresh"};
    return spec;
}

Result<MergedStudy> merge_shards(const StudySpec& spec, const std::vector<ShardInput>& shards,
                                 const fs::path& out_dir) {
    std::error_code ec;
    for (const ShardInput& s : shards)
        if (fs::equivalent(s.dir, out_dir, ec))
            return Error{"--out " + out_dir.string() + " is shard " + s.manifest.shard.text() +
                         "'s folder; merge into another folder"};
    // Every shard's rows, read as a resumed run reads them, and left as they are.
    std::vector<StudyFiles> files;
    for (const ShardInput& s : shards) {
        auto opened = StudyFiles::open(s.dir, spec, false, RowAccess::read_only);
        if (!opened) return opened.failure();
        files.push_back(std::move(opened.value()));
    }
    // Each cell in exactly one shard.
    std::vector<std::string> missing, doubled;
    auto check = [&](const std::string& cell, const std::function<bool(const StudyFiles&)>& has) {
        std::vector<std::string> where;
        for (size_t i = 0; i < shards.size(); ++i)
            if (has(files[i])) where.push_back(shards[i].dir.string());
        if (where.empty()) missing.push_back(cell);
        if (where.size() > 1) {
            std::string text = cell + " (in";
            for (const auto& w : where) text += " " + w;
            doubled.push_back(text + ")");
        }
    };
    for (const std::string& cell : study_cell_keys(spec))
        check(cell, [&](const StudyFiles& f) { return f.done(cell); });
    std::vector<std::string> map_cells;
    for (const SolverMapSpec& map : spec.solver_maps)
        for (const std::string& cell : solver_map_cell_keys(map)) map_cells.push_back(cell);
    for (const std::string& cell : map_cells)
        check(cell, [&](const StudyFiles& f) {
            return std::any_of(f.map_rows().begin(), f.map_rows().end(),
                               [&](const RowFile::Fields& r) { return r.back() == cell; });
        });
    auto list = [](const std::vector<std::string>& cells) {
        std::string text;
        for (size_t i = 0; i < cells.size() && i < 8; ++i) text += (i ? ", " : "") + cells[i];
        if (cells.size() > 8) text += ", and " + std::to_string(cells.size() - 8) + " more";
        return text;
    };
    if (!missing.empty())
        return Error{std::to_string(missing.size()) + " cells of " + spec.name + " are in no shard: " + list(missing) +
                     "; rerun the shard that owns them (aquaform study SPEC --shard K/N --out DIR) and merge again"};
    if (!doubled.empty())
        return Error{std::to_string(doubled.size()) + " cells of " + spec.name + " are in more than one shard: " +
                     list(doubled) + "; give each shard's folder once, each written by its own --shard K/N"};

    // The rows in an unsharded run's order, written through the same files.
    fs::create_directories(out_dir, ec);
    if (ec) return Error{"cannot create " + out_dir.string() + ": " + ec.message()};
    auto out = StudyFiles::open(out_dir, spec, true);
    if (!out) return out.failure();
    std::map<std::string, size_t> shard_of;  // cell -> shard
    std::vector<StudyRow> rows;
    for (size_t i = 0; i < files.size(); ++i)
        for (StudyRow& r : files[i].rows()) {
            shard_of[r.cell] = i;
            rows.push_back(std::move(r));
        }
    for (const StudyRow& row : in_spec_order(spec, std::move(rows)))
        if (auto added = out.value().add(row); !added) return added.failure();
    for (const std::string& cell : map_cells)
        for (const StudyFiles& f : files)
            for (const RowFile::Fields& r : f.map_rows())
                if (r.back() == cell)
                    if (auto added = out.value().add_map_row(r); !added) return added.failure();
    for (const ShardInput& s : shards)
        if (auto copied = copy_images(s.dir / "images", out_dir / "images"); !copied) return copied.failure();

    // The device of most cells names the times; rows from another carry theirs.
    std::map<std::string, size_t> cells_on;
    for (const ShardInput& s : shards) cells_on[s.manifest.device] += s.manifest.cells.size();
    const auto majority = std::max_element(cells_on.begin(), cells_on.end(),
                                           [](const auto& a, const auto& b) { return a.second < b.second; });
    MergedStudy merged;
    merged.device = majority == cells_on.end() ? std::string() : majority->first;
    if (cells_on.size() > 1) {
        merged.device += " (the rows marked \"on\" another device were measured there:";
        for (const ShardInput& s : shards)
            merged.device += " shard " + s.manifest.shard.text() + " on " + s.manifest.device + ";";
        merged.device += " their times compare only with rows of the same device)";
    }
    merged.rows = out.value().rows();
    for (StudyRow& r : merged.rows)
        if (auto it = shard_of.find(r.cell);
            it != shard_of.end() && cells_on.size() > 1 && shards[it->second].manifest.device != majority->first)
            r.device = shards[it->second].manifest.device;
    return merged;
}

}  // namespace aquaform::study
