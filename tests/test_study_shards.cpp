// `aquaform study SPEC --shard K/N` and `aquaform study merge`: the split keeps each frame (with its
// references) and each solver map whole, is the same in every process, and the tiny spec run as 3
// shards and merged gives the unsharded run's cells, errors and tables; merge refuses a missing,
// doubled, incomplete or foreign shard and missing or doubled cells, naming the folder and the fix;
// a shard stopped midway keeps its rows and resumes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/csv.h"
#include "study/study_rows.h"
#include "study/study_shards.h"
#include "study/study_spec.h"
#include "tests/cli_helpers.h"
#include "tests/json_mutations.h"

namespace aquaform::study {
namespace {

namespace fs = std::filesystem;

const std::string kAssetTiny = AQUAFORM_ASSETS_DIR "/studies/tiny.json";

/// The tiny spec at frame 0 of every case, in the temporary folder: a dam break simulated on for
/// 0.15 s amplifies the order of the device's float atomics, which differs between any two runs,
/// into errors a few percent apart; at frame 0 two runs (sharded or not) measure the same frames.
std::string frozen_tiny(const fs::path& dir) {
    std::string text = test_cli::read_file(AQUAFORM_ASSETS_DIR "/studies/tiny.json");
    const auto replace = [&](const std::string& from, const std::string& to) {
        for (size_t at; (at = text.find(from)) != std::string::npos;) text.replace(at, from.size(), to);
    };
    replace("\"time\": 0.15", "\"time\": 0.0");
    replace("\"../scenes/", "\"" AQUAFORM_ASSETS_DIR "/scenes/");
    return test_cli::write_file(dir / "tiny.json", text).string();
}

const fs::path& tiny_runs();
/// The spec every test here runs: frozen_tiny's.
std::string tiny() { return (tiny_runs() / "tiny.json").string(); }

std::vector<std::vector<std::string>> read_csv(const fs::path& path) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(test_cli::read_file(path));
    for (std::string line; std::getline(in, line);) rows.push_back(split_csv_line(line));
    return rows;
}

/// The main table rows of study.md without the times: method, particles, resolution, status.
std::vector<std::string> table_rows(const fs::path& md) {
    std::vector<std::string> rows;
    std::istringstream in(test_cli::read_file(md));
    bool in_table = false;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("| method | particles | resolution | ms |", 0) == 0)
            in_table = true;
        else if (line.empty() || line[0] != '|')
            in_table = false;
        else if (in_table && line.rfind("|---", 0) != 0) {
            std::vector<std::string> cells;
            std::istringstream fields(line.substr(1));
            for (std::string f; std::getline(fields, f, '|');) cells.push_back(f);
            rows.push_back(cells[0] + "|" + cells[1] + "|" + cells[2] + "|" + cells[11]);
        }
    }
    return rows;
}

test_cli::Outcome aquaform(const std::string& args) { return test_cli::run_aquaform(args, "AQUAFORM_VALIDATION=1"); }

/// The tiny spec run whole and as 3 shards, once for every test here.
const fs::path& tiny_runs() {
    static const fs::path dir = [] {
        const fs::path d = test_cli::temp_dir("study_shards");
        const std::string kTiny = frozen_tiny(d);
        auto whole = aquaform("study " + kTiny + " --out " + (d / "whole").string() + " --no-charts");
        EXPECT_EQ(whole.exit_code, 0) << whole.output;
        for (int k = 0; k < 3; ++k) {
            auto shard = aquaform("study " + kTiny + " --shard " + std::to_string(k) + "/3 --out " +
                                  (d / ("s" + std::to_string(k))).string());
            EXPECT_EQ(shard.exit_code, 0) << shard.output;
            EXPECT_EQ(shard.output.find("chart"), std::string::npos) << "a shard draws no charts: " << shard.output;
        }
        return d;
    }();
    static const struct Removed {  // at exit, after every test here has used the runs
        ~Removed() { fs::remove_all(dir); }
    } removed;
    return dir;
}

std::string merge(const std::vector<fs::path>& dirs, const fs::path& out, int expect, const std::string& more = "") {
    std::string args = "study merge";
    for (const fs::path& d : dirs) args += " " + d.string();
    auto o = aquaform(args + " --out " + out.string() + " --no-charts" + more);
    EXPECT_EQ(o.exit_code, expect) << args << ": " << o.output;
    return o.output;
}

void expect_says(const std::string& output, const std::vector<std::string>& parts) {
    for (const std::string& p : parts) EXPECT_NE(output.find(p), std::string::npos) << p << " in: " << output;
}

TEST(StudyShardTest, BadShardValuesAreRefusedNamingTheFlag) {
    for (const char* bad : {"3/3", "x/2", "0/0", "-1/2", "1", "1/2/3", ""}) {
        EXPECT_FALSE(parse_shard(bad).ok()) << bad;
        auto o =
            test_cli::run_aquaform("study " + kAssetTiny + " --shard '" + bad + "' --out /tmp/aquaform_never_written");
        EXPECT_EQ(o.exit_code, 2) << bad << ": " << o.output;
        EXPECT_NE(o.output.find("--shard"), std::string::npos) << o.output;
        EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << "one line: " << o.output;
    }
    EXPECT_FALSE(fs::exists("/tmp/aquaform_never_written"));
    auto ok = parse_shard("2/5");
    ASSERT_TRUE(ok.ok());
    EXPECT_EQ(ok.value(), (StudyShard{2, 5}));
    // The merge's flags are in its help.
    const std::string help = test_cli::run_aquaform("study merge --help").output;
    for (const char* flag : {"study merge DIR...", "--out DIR", "--no-charts", "--shard K/N"})
        EXPECT_NE(help.find(flag), std::string::npos) << flag;
}

TEST(StudyShardTest, TheSplitKeepsFramesWholeCoversEveryCellOnceAndIsBalanced) {
    auto spec = load_study_spec(kAssetTiny);
    ASSERT_TRUE(spec.ok()) << spec.error();
    const std::vector<StudyUnit> units = study_units(spec.value());
    ASSERT_EQ(units.size(), 5u)
        << "4 frames (methods/1000, methods/2000, curtain/1500, large_metaballs/1000) and the map";
    for (uint32_t n : {1u, 2u, 3u, 7u}) {
        std::multiset<std::string> cells;
        std::vector<double> load;
        for (uint32_t k = 0; k < n; ++k) {
            double cost = 0.0;
            for (const StudyUnit& u : shard_units(spec.value(), {k, n})) {
                cells.insert(u.cells.begin(), u.cells.end());
                cost += u.cost;
                if (!u.solver_map) {  // a frame's every cell: its references are made with it
                    for (const std::string& c : u.cells) EXPECT_EQ(c.rfind(u.key + "/", 0), 0u) << c;
                }
            }
            load.push_back(cost);
            std::vector<std::string> again;  // the same split every time: every process computes it alone
            for (const StudyUnit& u : shard_units(spec.value(), {k, n})) again.push_back(u.key);
            std::vector<std::string> first;
            for (const StudyUnit& u : shard_units(spec.value(), {k, n})) first.push_back(u.key);
            EXPECT_EQ(first, again);
        }
        std::multiset<std::string> expected;
        for (const StudyUnit& u : units) expected.insert(u.cells.begin(), u.cells.end());
        EXPECT_EQ(cells, expected) << n << " shards";
        if (n == 7) {
            EXPECT_TRUE(shard_units(spec.value(), {6, 7}).empty()) << "more shards than units: some are empty";
        }
        if (n == 3) {  // longest first: the largest frame alone on shard 0
            ASSERT_EQ(shard_units(spec.value(), {0, 3}).size(), 1u);
            EXPECT_EQ(shard_units(spec.value(), {0, 3})[0].key, "methods/2000");
        }
    }
}

TEST(StudyShardCliTest, ThreeShardsMergeToTheUnshardedRowsAndTables) {
    const fs::path& d = tiny_runs();
    for (int k = 0; k < 3; ++k) {
        auto manifest = read_manifest(d / ("s" + std::to_string(k)));
        ASSERT_TRUE(manifest.ok() && manifest.value()) << k;
        const ShardManifest& m = *manifest.value();
        EXPECT_TRUE(m.complete);
        EXPECT_EQ(m.shard, (StudyShard{uint32_t(k), 3}));
        EXPECT_EQ(m.spec_name, "tiny");
        EXPECT_FALSE(m.device.empty());
        EXPECT_FALSE(m.version.empty());
        EXPECT_GT(m.wall_s, 0.0);
        EXPECT_FALSE(m.cells.empty());
    }
    const std::string said = merge({d / "s0", d / "s1", d / "s2"}, d / "merged", 0);
    const auto whole = read_csv(d / "whole" / "study.csv"), merged = read_csv(d / "merged" / "study.csv");
    ASSERT_EQ(merged.size(), whole.size()) << said;
    ASSERT_EQ(merged[0], whole[0]);
    const std::vector<std::string>& header = whole[0];
    const std::set<std::string> timed = {"ms_total", "fps"};
    const size_t status = size_t(std::find(header.begin(), header.end(), "status") - header.begin());
    for (size_t i = 1; i < whole.size(); ++i) {
        ASSERT_EQ(merged[i].back(), whole[i].back()) << "the same cell in the same place";
        ASSERT_EQ(merged[i][status], whole[i][status]) << whole[i].back();
        // Lists that overflow keep the entries whose threads came first: which ones, and so the
        // errors, differ from run to run (sharded or not).
        const bool overflow = whole[i][status] == "overflow";
        for (size_t c = 0; c < header.size(); ++c) {
            if (timed.count(header[c]) || (overflow && header[c] != "status" && header[c] != "cell")) continue;
            const std::string &a = whole[i][c], &b = merged[i][c];
            char* end_a = nullptr;
            char* end_b = nullptr;
            const double x = std::strtod(a.c_str(), &end_a), y = std::strtod(b.c_str(), &end_b);
            // The spec column is a hex hash: one of digits and an 'e' reads as a number, even as inf.
            const bool number = header[c] != "spec" && !a.empty() && *end_a == '\0' && !b.empty() && *end_b == '\0';
            if (number)  // the device's float sums vary a little
                EXPECT_NEAR(x, y, 0.02 * std::max(std::abs(x), std::abs(y)) + 1e-3)
                    << whole[i].back() << " " << header[c];
            else
                EXPECT_EQ(a, b) << whole[i].back() << " " << header[c];
        }
    }
    EXPECT_EQ(read_csv(d / "merged" / "solver_map.csv").size(), read_csv(d / "whole" / "solver_map.csv").size());
    EXPECT_EQ(read_csv(d / "merged" / "study_passes.csv").size(), read_csv(d / "whole" / "study_passes.csv").size());
    const auto rows = table_rows(d / "merged" / "study.md");
    EXPECT_EQ(rows.size(), whole.size() - 1);
    EXPECT_EQ(rows, table_rows(d / "whole" / "study.md"));
    for (size_t i = 1; i < merged.size(); ++i) {
        const std::string image = merged[i][std::find(header.begin(), header.end(), "image") - header.begin()];
        if (!image.empty()) {
            EXPECT_TRUE(fs::exists(d / "merged" / image)) << image;
        }
    }

    // More shards than units: a shard with nothing to do is complete and empty.
    auto empty = aquaform("study " + tiny() + " --shard 6/7 --out " + (d / "empty").string());
    ASSERT_EQ(empty.exit_code, 0) << empty.output;
    auto manifest = read_manifest(d / "empty");
    ASSERT_TRUE(manifest.ok() && manifest.value());
    EXPECT_TRUE(manifest.value()->complete);
    EXPECT_TRUE(manifest.value()->cells.empty());

    // Rows from another device are marked in study.md.
    fs::copy(d / "s2", d / "s2_other", fs::copy_options::recursive);
    std::string text = test_cli::read_file(d / "s2_other" / kManifestName);
    const size_t at = text.find("\"device\": \"") + 11;
    text.replace(at, text.find('"', at) - at, "Other GPU");
    test_cli::write_file(d / "s2_other" / kManifestName, text);
    merge({d / "s0", d / "s1", d / "s2_other"}, d / "merged_devices", 0);
    const std::string md = test_cli::read_file(d / "merged_devices" / "study.md");
    expect_says(md, {"(on Other GPU)", "shard 2/3 on Other GPU"});
}

TEST(StudyShardCliTest, MergeOnlyReadsItsShards) {
    const fs::path& d = tiny_runs();
    // A torn last line (a write cut short) in a complete shard: a run into that folder would drop
    // it and rewrite the file; the merge reads past it and leaves the file as it is.
    const fs::path s1 = d / "s1_torn";
    fs::remove_all(s1);
    fs::copy(d / "s1", s1, fs::copy_options::recursive);
    std::ofstream(s1 / "study.csv", std::ios::app) << "methods,torn";
    const std::string before = test_cli::read_file(s1 / "study.csv");
    merge({d / "s0", s1, d / "s2"}, d / "merged_from_torn", 0);
    EXPECT_EQ(test_cli::read_file(s1 / "study.csv"), before) << "the merge rewrote a shard's rows";
    EXPECT_EQ(read_csv(d / "merged_from_torn" / "study.csv").size(), read_csv(d / "whole" / "study.csv").size());
}

TEST(StudyShardCliTest, MergeTakesTheSpecFromSpecWhereItIsElsewhere) {
    const fs::path& d = tiny_runs();
    const std::vector<fs::path> shards{d / "s0", d / "s1", d / "s2"};
    // The same spec by another path: merged.
    merge(shards, d / "merged_spec_path", 0, " --spec " + (d / "." / "tiny.json").string());
    EXPECT_EQ(read_csv(d / "merged_spec_path" / "study.csv").size(), read_csv(d / "whole" / "study.csv").size());
    // Not there, or another spec: refused, naming it.
    expect_says(merge(shards, d / "merged_nowhere", 2, " --spec " + (d / "nowhere.json").string()),
                {(d / "nowhere.json").string()});
    const std::string shipped = std::string(AQUAFORM_SOURCE_DIR) + "/assets/studies/tiny.json";
    expect_says(merge(shards, d / "merged_other", 2, " --spec " + shipped), {shipped, "changed since shard"});
}

TEST(StudyShardCliTest, MergeRefusesMissingDoubledIncompleteAndForeignShards) {
    const fs::path& d = tiny_runs();
    const fs::path s0 = d / "s0", s1 = d / "s1", s2 = d / "s2", out = d / "refused";
    expect_says(merge({s0, s1}, out, 2), {"shard 2/3 is missing", "--shard 2/3", "rerun aquaform study"});
    expect_says(merge({s0, s1, s1, s2}, out, 2), {"shard 1/3 is given twice", s1.string()});
    EXPECT_FALSE(fs::exists(out / "study.csv")) << "nothing written when refused";

    // Another spec's shard (empty: the other spec has one unit).
    const fs::path other_spec =
        test_cli::write_file(d / "other.json", R"({"name": "other", "repeats": 1, "cases": [{"name": "c",
        "scene": "dam_break", "particles": [1000], "time": 0.05, "resolutions": ["64x64"], "methods": [{"method": "bilateral"}]}]})");
    auto other = aquaform("study " + other_spec.string() + " --shard 2/3 --out " + (d / "other2").string());
    ASSERT_EQ(other.exit_code, 0) << other.output;
    expect_says(merge({s0, s1, d / "other2"}, out, 2),
                {(d / "other2").string(), s0.string(), "other", "tiny", "one spec"});

    // Another shard into a shard's folder is refused, naming both.
    auto into = test_cli::run_aquaform("study " + tiny() + " --shard 0/3 --out " + s1.string());
    EXPECT_EQ(into.exit_code, 2) << into.output;
    expect_says(into.output, {"shard 1/3", "shard 0/3", "its own --out", "--fresh"});
    fs::copy(s1, d / "s1_fresh", fs::copy_options::recursive);  // --fresh starts that folder over
    auto fresh = aquaform("study " + tiny() + " --shard 6/7 --fresh --out " + (d / "s1_fresh").string());
    ASSERT_EQ(fresh.exit_code, 0) << fresh.output;
    auto replaced = read_manifest(d / "s1_fresh");
    ASSERT_TRUE(replaced.ok() && replaced.value());
    EXPECT_EQ(replaced.value()->shard, (StudyShard{6, 7}));
    EXPECT_EQ(read_csv(d / "s1_fresh" / "study.csv").size(), 1u) << "shard 1/3's rows are gone";

    // A cell doubled (rows of shard 0 also in a copy of shard 1) or missing (a row taken out).
    fs::copy(s1, d / "s1_doubled", fs::copy_options::recursive);
    const auto s0_rows = read_csv(s0 / "study.csv");
    {
        std::ofstream csv(d / "s1_doubled" / "study.csv", std::ios::app);
        csv << csv_line(s0_rows[1]) << "\n";
    }
    expect_says(merge({s0, d / "s1_doubled", s2}, out, 2),
                {"in more than one shard", s0_rows[1].back(), s0.string(), (d / "s1_doubled").string()});
    fs::copy(s2, d / "s2_missing", fs::copy_options::recursive);
    auto s2_rows = read_csv(s2 / "study.csv");
    {
        std::ofstream csv(d / "s2_missing" / "study.csv", std::ios::trunc);
        for (size_t i = 0; i + 1 < s2_rows.size(); ++i) csv << csv_line(s2_rows[i]) << "\n";
    }
    expect_says(merge({s0, s1, d / "s2_missing"}, out, 2), {"in no shard", s2_rows.back().back(), "--shard K/N"});
}

/// A row twice in one shard's file was merged twice (a cell counted double in study.md). It is
/// refused as a cell in two shards is, naming the file, the lines, the row and the fix.
TEST(StudyShardCliTest, ARowTwiceInOneShardIsRefusedAsACellInTwoShardsIs) {
    const fs::path& d = tiny_runs();
    for (const char* name : {"study.csv", "solver_map.csv"}) {
        const fs::path twice = d / "s_twice";
        fs::remove_all(twice);
        // The shard that holds rows of this file.
        fs::path shard;
        for (const char* s : {"s0", "s1", "s2"})
            if (shard.empty() && read_csv(d / s / name).size() > 1) shard = d / s;
        ASSERT_FALSE(shard.empty()) << "no shard has rows in " << name;
        fs::copy(shard, twice, fs::copy_options::recursive);
        const auto rows = read_csv(twice / name);
        {
            std::ofstream csv(twice / name, std::ios::app);
            csv << csv_line(rows[1]) << "\n";
        }
        std::vector<fs::path> dirs;
        for (const char* s : {"s0", "s1", "s2"}) dirs.push_back(d / s == shard ? twice : d / s);
        const fs::path out = d / "merged_twice";
        expect_says(merge(dirs, out, 2), {(twice / name).string() + " lines 2 and " + std::to_string(rows.size() + 1),
                                          rows[1].back(), "delete one of the two lines", "--fresh"});
        EXPECT_FALSE(fs::exists(out / "study.csv")) << "nothing merged";
    }
    fs::remove_all(d / "s_twice");
}

/// Every number in a shard's files is input. A copy of shard 1 with its manifest or one row
/// changed: what the merge reads is refused in one line naming the file and the key (or the
/// line and the column), or merged when the change is harmless; never a crash.
TEST(StudyShardCliTest, MutatedManifestsAndRowsAreRefusedNamingTheFileAndTheKey) {
    const fs::path& d = tiny_runs();
    const fs::path mutant = d / "s1_mutant";
    auto load = [&](const fs::path& dir) -> Result<MergedStudy> {
        auto shards = read_shard_set({d / "s0", dir, d / "s2"});
        if (!shards) return Error{shards.error()};
        auto spec = load_shard_spec(shards.value().front(), {});
        if (!spec) return Error{spec.error()};
        fs::remove_all(d / "merged_mutant");
        return merge_shards(spec.value(), shards.value(), d / "merged_mutant");
    };
    auto fresh_copy = [&] {
        fs::remove_all(mutant);
        fs::copy(d / "s1", mutant, fs::copy_options::recursive);
    };

    // The manifest: each key mutated (types, extremes, deletion, text that is not JSON).
    using namespace json_mutations;
    const json manifest = json::parse(test_cli::read_file(d / "s1" / kManifestName));
    std::vector<json::json_pointer> paths;
    collect_paths(manifest, json::json_pointer(), paths);
    std::mt19937 random(28);
    int mutations = 0, refused = 0;
    for (const json::json_pointer& path : paths)
        for (int k = 0; k < 4; ++k) {
            fresh_copy();
            const Mutation m = mutate(manifest, path, random);
            test_cli::write_file(mutant / kManifestName, m.text);
            ++mutations;
            Result<MergedStudy> merged = Error{};
            ASSERT_NO_THROW(merged = load(mutant)) << path.to_string();
            if (merged) continue;
            ++refused;
            const std::string& e = merged.error();
            EXPECT_EQ(e.find('\n'), std::string::npos) << e;
            EXPECT_NE(e.find(mutant.string()), std::string::npos) << "names the folder or file: " << e;
        }
    EXPECT_GT(refused, mutations / 3) << refused << " of " << mutations;
    std::printf("manifest fuzz: %d mutations, %d refused\n", mutations, refused);

    // The shard numbers that crashed the merge, through the binary: exit 2 naming the key.
    for (const auto& [key, value] : std::vector<std::pair<std::string, json>>{{"shard", 5},
                                                                              {"shard", -1},
                                                                              {"shards", 0},
                                                                              {"shard", 3},
                                                                              {"shards", 4294967296.0},
                                                                              {"particles", 1e300}}) {
        fresh_copy();
        json changed = manifest;
        changed[key] = value;
        test_cli::write_file(mutant / kManifestName, changed.dump(2));
        const std::string out = merge({d / "s0", mutant, d / "s2"}, d / "merged_mutant", 2);
        expect_says(out, {(mutant / kManifestName).string(), "\"" + key + "\""});
    }

    // A row: each number column given a value no run writes.
    const auto rows = read_csv(d / "s1" / "study.csv");
    ASSERT_GE(rows.size(), 2u);
    const std::vector<std::string>& header = rows[0];
    int columns = 0;
    for (size_t c = 0; c < header.size(); ++c) {
        // The spec column is a hex hash (the run's identity), which may happen to be all digits and an 'e'.
        if (header[c] == "spec" || rows[1][c].empty() ||
            rows[1][c].find_first_not_of("0123456789.e+-") != std::string::npos)
            continue;
        for (const char* bad : {"-1", "nan", "1e400", "x", "4294967296e9"}) {
            if (std::string(bad) == "-1" && header[c] != "width" && header[c] != "rays" && header[c] != "particles")
                continue;
            fresh_copy();
            std::vector<std::vector<std::string>> changed = rows;
            changed[1][c] = bad;
            std::ofstream csv(mutant / "study.csv", std::ios::trunc);
            for (const auto& r : changed) csv << csv_line(r) << "\n";
            csv.close();
            Result<MergedStudy> merged = Error{};
            ASSERT_NO_THROW(merged = load(mutant)) << header[c];
            if (std::string(bad) == "4294967296e9" && header[c] != "width" && header[c] != "height" &&
                header[c] != "particles" && header[c] != "rays")
                continue;  // a large finite measurement is a measurement
            ASSERT_FALSE(merged.ok()) << header[c] << " = " << bad;
            expect_says(merged.error(), {(mutant / "study.csv").string() + " line 2", "\"" + header[c] + "\""});
        }
        ++columns;
    }
    EXPECT_GT(columns, 10) << "number columns mutated";

    // A file that is a folder.
    for (const char* name : {kManifestName, "study.csv"}) {
        fresh_copy();
        fs::remove(mutant / name);
        fs::create_directory(mutant / name);
        Result<MergedStudy> merged = Error{};
        ASSERT_NO_THROW(merged = load(mutant)) << name;
        ASSERT_FALSE(merged.ok()) << name;
        expect_says(merged.error(), {(mutant / name).string() + " is not a file"});
    }
    fs::remove_all(mutant);
}

TEST(StudyShardCliTest, AShardStoppedMidwayIsIncompleteUntilItsRerunResumes) {
    const fs::path& d = tiny_runs();
    const fs::path k1 = d / "k1";
    const int stopped = test_cli::interrupt_aquaform({"study", tiny(), "--shard", "1/3", "--out", k1.string()},
                                                     d / "k1.log", ": reference: ");
    const std::string log = test_cli::read_file(d / "k1.log");
    ASSERT_EQ(stopped, 130) << log;
    const size_t kept = read_csv(k1 / "study.csv").size() - 1;
    ASSERT_GE(kept, 1u) << log;
    auto manifest = read_manifest(k1);
    ASSERT_TRUE(manifest.ok() && manifest.value());
    EXPECT_FALSE(manifest.value()->complete);
    expect_says(merge({d / "s0", k1, d / "s2"}, d / "refused_incomplete", 2),
                {"shard 1/3", k1.string(), "incomplete", "rerun aquaform study", "--shard 1/3 --out " + k1.string()});

    auto resumed = aquaform("study " + tiny() + " --shard 1/3 --out " + k1.string());
    ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
    EXPECT_NE(resumed.output.find("resuming: " + std::to_string(kept) + " of"), std::string::npos) << resumed.output;
    EXPECT_EQ(resumed.output.find(": reference: "), std::string::npos) << "the kept cells are not measured again";
    manifest = read_manifest(k1);
    ASSERT_TRUE(manifest.ok() && manifest.value());
    EXPECT_TRUE(manifest.value()->complete);
    merge({d / "s0", k1, d / "s2"}, d / "merged_resumed", 0);
    EXPECT_EQ(table_rows(d / "merged_resumed" / "study.md"), table_rows(d / "whole" / "study.md"));
}

}  // namespace
}  // namespace aquaform::study
