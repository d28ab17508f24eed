// `aquaform study`: the spec is read strictly (errors name the key and the fix; names that
// become paths stay inside the output folder) and checked whole before any GPU work; the tiny
// spec runs end to end on the software device, writing its CSV, tables and charts, with the
// overflowing case reported as such; rows are written as measured, so Ctrl-C keeps them and a
// rerun resumes; an unwritable --out is refused precisely; the chart script and a Python with
// matplotlib are found from any build folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench/bench_scenes.h"
#include "core/output_dir.h"
#include "render/metaball_renderer.h"
#include "render/surface_settings.h"
#include "study/study_charts.h"
#include "study/study_rows.h"
#include "study/study_run.h"
#include "study/study_spec.h"
#include "tests/cli_helpers.h"

namespace aquaform::cli {
namespace {

namespace fs = std::filesystem;

Result<study::StudySpec> parse(const std::string& text) {
    return study::parse_study_spec(text, "spec.json", AQUAFORM_ASSETS_DIR "/studies");
}

TEST(StudySpecTest, ArrayParametersExpandIntoConfigurations) {
    auto spec = parse(R"({"cases": [{"name": "a", "resolutions": ["64x32", "32x32"], "particles": [1000, 2000],
        "list_bytes_per_pixel": 64, "methods": [{"method": "sbuffer", "visual": ["gradient", "real"], "size": [1, 2], "recursion": [1, 4]},
                    {"method": "adaptive", "resolution": ["full", "half"]}]}]})");
    ASSERT_TRUE(spec.ok()) << spec.error();
    const study::StudyCase& c = spec.value().cases[0];
    EXPECT_EQ(c.resolutions.size(), 2u);
    EXPECT_EQ(c.resolutions[0], std::make_pair(64u, 32u));
    EXPECT_EQ(c.particles, (std::vector<uint32_t>{1000, 2000}));
    // gradient x {1, 2} (recursion applies to real only) + real x {1, 2} x {1, 4} + adaptive x 2.
    ASSERT_EQ(c.methods.size(), 2u + 4u + 2u);
    EXPECT_EQ(c.methods[0].label(), "sbuffer gradient x1 b3");
    EXPECT_EQ(c.methods.back().label(), "adaptive half");
    // Each configuration carries the registry's settings the study draws it with.
    const MetaballSettings* real = c.methods[2].settings.get<MetaballSettings>();
    ASSERT_NE(real, nullptr) << c.methods[2].label();
    EXPECT_EQ(c.methods[2].settings.method(), "sbuffer");
    EXPECT_EQ(real->visual, MetaballVisual::real);
    EXPECT_EQ(real->size, 1.0f);
    EXPECT_EQ(real->recursion_depth, 1u);
    EXPECT_EQ(real->list_bytes_per_pixel, 64u) << "the case's list memory";
    const SurfaceSettings* half = c.methods.back().settings.get<SurfaceSettings>();
    ASSERT_NE(half, nullptr);
    EXPECT_FALSE(half->adaptive_resolution) << "a fixed resolution turns adaptive resolution off";
    EXPECT_EQ(c.methods.back().resolution_divisor(), 2u);
    EXPECT_FALSE(c.methods[c.methods.size() - 2].settings.as<SurfaceSettings>().adaptive_resolution) << "full, too";
}

TEST(StudySpecTest, ShippedSpecsLoadWithTheirScenes) {
    for (const char* name : {"default.json", "tiny.json"}) {
        auto spec = study::load_study_spec(fs::path(AQUAFORM_ASSETS_DIR) / "studies" / name);
        ASSERT_TRUE(spec.ok()) << name << ": " << spec.error();
        EXPECT_GE(spec.value().cases.size(), 2u) << name;
    }
    // The default study measures on splashy frames and the curtain, with Wu et al. Fig. 5's stepping.
    const auto spec = study::load_study_spec(fs::path(AQUAFORM_ASSETS_DIR) / "studies" / "default.json").value();
    for (const char* name : {"calm", "curtain", "double_collision", "violent_wall", "crown"}) {
        auto c = std::find_if(spec.cases.begin(), spec.cases.end(),
                              [&](const study::StudyCase& x) { return x.name == name; });
        ASSERT_NE(c, spec.cases.end()) << name;
        bool mask_skip = false;
        for (const auto& m : c->methods) mask_skip |= m.label() == "adaptive mask+skip";
        EXPECT_TRUE(mask_skip) << name;
    }
}

TEST(StudySpecTest, SteppingConfigurationsAreWuFigureFivesMechanisms) {
    auto spec = parse(R"({"cases": [{"name": "a", "resolutions": ["64x64"],
        "methods": [{"method": "adaptive", "stepping": ["all", "mask", "mask_skip"]}]}]})");
    ASSERT_TRUE(spec.ok()) << spec.error();
    const auto& m = spec.value().cases[0].methods;
    ASSERT_EQ(m.size(), 3u);
    EXPECT_EQ(m[0].label(), "adaptive");
    EXPECT_EQ(m[1].label(), "adaptive mask");
    EXPECT_EQ(m[2].label(), "adaptive mask+skip");
    const SurfaceSettings& all = m[0].settings.as<SurfaceSettings>();
    EXPECT_TRUE(all.use_mask && all.use_skip && all.adaptive_resolution);
    const SurfaceSettings& mask = m[1].settings.as<SurfaceSettings>();
    EXPECT_TRUE(mask.use_mask);
    EXPECT_FALSE(mask.use_skip);
    EXPECT_FALSE(mask.adaptive_resolution) << "a ray per pixel, so that every pixel has its step count";
    const SurfaceSettings& mask_skip = m[2].settings.as<SurfaceSettings>();
    EXPECT_TRUE(mask_skip.use_mask && mask_skip.use_skip);
    EXPECT_FALSE(mask_skip.adaptive_resolution);
}

TEST(StudySpecTest, ErrorsNameTheKeyAndTheFix) {
    auto expect_error = [](const std::string& text, const std::vector<std::string>& parts) {
        auto spec = parse(text);
        ASSERT_FALSE(spec.ok()) << text;
        for (const auto& part : parts) EXPECT_NE(spec.error().find(part), std::string::npos) << spec.error();
    };
    expect_error(R"({"cases": [{"name": "a", "resolutions": ["64x64"], "methods": [{"method": "octree"}]}]})",
                 {"cases[0].methods[0].method", "octree", "sbuffer"});
    expect_error(R"({"cases": [{"name": "a", "resolution": ["64x64"], "methods": [{"method": "brute"}]}]})",
                 {"resolution", "resolutions"});
    expect_error(R"({"cases": [{"name": "a", "resolutions": ["64 by 64"], "methods": [{"method": "brute"}]}]})",
                 {"cases[0].resolutions", "512x512"});
    expect_error(
        R"({"cases": [{"name": "a", "resolutions": ["64x64"], "methods": [{"method": "adaptive", "size": 2}]}]})",
        {"size", "metaball"});
    expect_error(
        R"({"cases": [{"name": "a", "resolutions": ["64x64"], "methods": [{"method": "brute", "recursion": 9}]}]})",
        {"recursion"});
    expect_error(
        R"({"cases": [{"name": "a", "scene": "nowhere.json", "resolutions": ["64x64"], "methods": [{"method": "brute"}]}]})",
        {"nowhere.json", "relative to the spec"});
    expect_error(R"({"cases": []})", {"cases"});
    expect_error(R"({"cases": [{"name": "a", "resolutions": ["64x64"], "methods": [{"method": "brute"}]},
                               {"name": "a", "resolutions": ["64x64"], "methods": [{"method": "brute"}]}]})",
                 {"used twice"});
    expect_error("{\"cases\": [", {"spec.json"});
    expect_error(
        R"({"cases": [{"name": "a", "resolutions": ["64x64"], "methods": [{"method": "uniform", "stepping": "mask"}]}]})",
        {"stepping", "adaptive method only"});
    expect_error(
        R"({"cases": [{"name": "a", "resolutions": ["64x64"], "methods": [{"method": "adaptive", "stepping": "skip"}]}]})",
        {"stepping", "mask_skip"});
    expect_error(R"({"cases": [{"name": "a", "resolutions": ["64x64"],
                                "methods": [{"method": "adaptive", "stepping": "mask", "resolution": "half"}]}]})",
                 {"stepping", "full resolution"});
}

study::StudyRow row(const std::string& case_name, const std::string& method, uint32_t particles, double ms,
                    double depth) {
    study::StudyRow r;
    r.case_name = case_name;
    r.method = method;
    r.particles = particles;
    r.width = r.height = 512;
    r.ms_total = ms;
    r.depth_err_mean = depth;
    return r;
}

TEST(StudyTargetsTest, ComparisonsStayWithinACaseAndTheCrossoverIsInterpolated) {
    const std::string s = "sbuffer gradient x1 b3", s2 = "sbuffer gradient x2 b3", b = "brute gradient x1 b3";
    std::vector<study::StudyRow> rows{
        // A case with brute force only, and one with both: the ratio comes from the second.
        row("other", b, 4096, 1000.0, 0.1), row("k", b, 4096, 900.0, 0.1), row("k", s, 4096, 100.0, 0.1),
        // A case of one count far from 100k: the comparison takes the case that comes nearer.
        row("small", "adaptive", 2000, 100.0, 0.01), row("small", s2, 2000, 900.0, 0.05),
        // The S-buffer x2 is 2x faster at 10k, the adaptive method 2x faster at 1M: equal at 100k.
        row("scaling", "adaptive", 10000, 200.0, 0.01), row("scaling", s2, 10000, 100.0, 0.05),
        row("scaling", "adaptive", 1000000, 200.0, 0.01), row("scaling", s2, 1000000, 400.0, 0.05)};
    // March steps: 40 % of uniform's at the same depth error in one case, 60 % in another.
    for (const auto& [c, steps] : {std::pair{"curtain", 4.0}, std::pair{"calm", 6.0}}) {
        rows.push_back(row(c, "uniform", 1000, 10.0, 0.02));
        rows.back().steps_per_ray = 10.0;
        rows.push_back(row(c, "adaptive mask+skip", 1000, 10.0, 0.02));
        rows.back().steps_per_ray = steps;
    }
    // Adaptive resolution: march + upsample at half the full-resolution march.
    rows.push_back(row("calm", "adaptive", 1000, 10.0, 0.02));
    rows.back().ms_per_pass = {{"render_march", 4.0}, {"render_upsample", 1.0}};
    rows.push_back(row("calm", "adaptive full", 1000, 10.0, 0.02));
    rows.back().ms_per_pass = {{"render_march", 10.0}};
    const auto lines = study::study_targets(rows);
    ASSERT_EQ(lines.size(), 6u);
    EXPECT_NE(lines[0].find("9.0x at 4096 particles in k"), std::string::npos) << lines[0];
    EXPECT_NE(lines[0].find("MET"), std::string::npos) << lines[0];
    EXPECT_NE(lines[1].find("MISS"), std::string::npos) << lines[1];
    EXPECT_NE(lines[1].find("in scaling"), std::string::npos) << lines[1];
    EXPECT_NE(lines[2].find("about 100000 particles"), std::string::npos) << lines[2];
    EXPECT_NE(lines[3].find("in curtain"), std::string::npos) << lines[3];
    EXPECT_NE(lines[3].find("40.0%"), std::string::npos) << lines[3];
    EXPECT_NE(lines[3].find("MET"), std::string::npos) << lines[3];
    EXPECT_NE(lines[4].find("in calm"), std::string::npos) << lines[4];
    EXPECT_NE(lines[4].find("MISS"), std::string::npos) << lines[4];
    EXPECT_NE(lines[5].find("0.50x"), std::string::npos) << lines[5];
    EXPECT_NE(lines[5].find("MET"), std::string::npos) << lines[5];
}

TEST(StudyCameraTest, TheCloseUpBringsParticlesWithinAMetaballRangeOfTheEyePlane) {
    // The close-up case is where billboards are dropped: it must actually put particles that
    // close, in view, with the eye on the fluid's surface rather than inside it.
    const Scene scene = study::bench_scene(4096, 4);
    study::StudyCamera spec;
    spec.preset = "closeup";
    const ViewCamera camera = study::study_camera(spec, scene, 1.0f);
    std::vector<glm::vec4> x;
    std::vector<uint32_t> block;
    scene.generate_particles(x, block);
    const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
    const float range = metaball_radius(MetaballSettings{}, scene.particle_domain());
    const float tan_half = std::tan(glm::radians(camera.fov_y_degrees) * 0.5f);
    size_t near_plane = 0;
    float nearest = INFINITY;
    for (const glm::vec4& p : x) {
        const glm::vec3 rel = glm::vec3(p) - camera.eye;
        const float depth = glm::dot(rel, forward);
        nearest = std::min(nearest, glm::length(rel));
        if (depth > 0.0f && depth < range && glm::length(rel - depth * forward) < depth * tan_half + range)
            ++near_plane;
    }
    EXPECT_GT(near_plane, 0u) << "no particle within R = " << range << " m of the eye plane";
    EXPECT_GE(nearest, 0.45f * scene.particle_spacing) << "the eye is inside the fluid";
}

TEST(StudyCliTest, MissingSpecAndUnknownFlagAreRefused) {
    auto missing = test_cli::run_aquaform("study /nonexistent/spec.json");
    EXPECT_EQ(missing.exit_code, 2) << missing.output;
    EXPECT_NE(missing.output.find("cannot open study spec"), std::string::npos) << missing.output;
    auto flag = test_cli::run_aquaform("study " AQUAFORM_ASSETS_DIR "/studies/tiny.json --fast");
    EXPECT_EQ(flag.exit_code, 2) << flag.output;
    EXPECT_NE(flag.output.find("--fast"), std::string::npos) << flag.output;
}

/// Rows of a CSV file as fields (no quoted commas in what the tiny study writes, but for status).
std::vector<std::vector<std::string>> read_csv(const fs::path& path) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(test_cli::read_file(path));
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> fields;
        std::string field;
        bool quoted = false;
        for (char c : line) {
            if (c == '"')
                quoted = !quoted;
            else if (c == ',' && !quoted)
                fields.push_back(std::move(field)), field.clear();
            else
                field += c;
        }
        fields.push_back(field);
        rows.push_back(fields);
    }
    return rows;
}

TEST(StudySpecTest, NamesThatBecomePathsStayInsideTheOutputFolder) {
    auto error_of = [](const std::string& top_name, const std::string& case_name) {
        auto spec = parse("{\"name\": " + top_name + ", \"cases\": [{\"name\": " + case_name +
                          ", \"resolutions\": [\"64x64\"], \"methods\": [{\"method\": \"brute\"}]}]}");
        return spec.ok() ? std::string("(accepted)") : spec.error();
    };
    for (const char* bad : {R"("../../x")", R"("a/b")", R"("a\\b")", R"(".")", R"("..")", R"("")", R"(".hidden")",
                            R"("tab\there")", R"("a b")", R"("x\u0001")"}) {
        const std::string top = error_of(bad, "\"ok\""), in_case = error_of("\"ok\"", bad);
        EXPECT_NE(top.find("name is"), std::string::npos) << bad << ": " << top;
        EXPECT_NE(top.find("letters, digits"), std::string::npos) << bad << ": " << top;
        EXPECT_NE(in_case.find("cases[0].name"), std::string::npos) << bad << ": " << in_case;
    }
    EXPECT_NE(error_of('"' + std::string(65, 'x') + '"', "\"ok\"").find("1 to 64"), std::string::npos);
    EXPECT_EQ(error_of("\"v1.2-study_A\"", "\"case-1.b\""), "(accepted)");
    // Through the command: refused with exit 2 before anything is made.
    const fs::path dir = test_cli::temp_dir("study_name");
    const fs::path spec = test_cli::write_file(dir / "escape.json", R"({"name": "../../escaped", "cases": [{"name": "a",
        "resolutions": ["64x64"], "methods": [{"method": "brute"}]}]})");
    auto run =
        test_cli::run_aquaform("study " + spec.string(), "cd " + dir.string() + " &&");  // out/study/../../escaped
    EXPECT_EQ(run.exit_code, 2) << run.output;
    EXPECT_NE(run.output.find("name is \"../../escaped\""), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(dir / "escaped"));
    EXPECT_FALSE(fs::exists(dir / "out"));
    fs::remove_all(dir);
}

/// A study of six cells on two frames and a solver map of one cell: seconds on the software device.
/// Three repeats give the rows after the first a few hundred milliseconds, for Ctrl-C to land in.
std::string small_spec(const std::string& extra = "") {
    return R"({"name": "small", "repeats": 3,
 "cases": [{"name": "a", "scene": "dam_break", "particles": [1000], "time": 0.05, "resolutions": ["64x64"],
            "methods": [{"method": "reference"}, {"method": "uniform"}, {"method": "sbuffer"}, {"method": "bilateral"},
                        {"method": "narrow_range"}]},
           {"name": "b", "scene": "dam_break", "particles": [1000], "time": 0.05, "resolutions": ["64x64"],
            "methods": [{"method": "adaptive"}]})" +
           extra +
           R"(],
 "solver_map": {"scene": ")" AQUAFORM_ASSETS_DIR
           R"(/scenes/hydrostatic.json", "dt": [0.004], "iterations": [2], "time": 0.05}})";
}

TEST(StudyCliTest, TheWholeSpecIsCheckedBeforeAnyMeasurement) {
    const fs::path dir = test_cli::temp_dir("study_check");
    auto refused = [&](const std::string& text, const std::vector<std::string>& parts) {
        const fs::path spec = test_cli::write_file(dir / "spec.json", text);
        auto run = test_cli::run_aquaform("study " + spec.string() + " --out " + (dir / "out").string());
        EXPECT_EQ(run.exit_code, 2) << run.output;
        for (const auto& part : parts)
            EXPECT_NE(run.output.find(part), std::string::npos) << part << ": " << run.output;
        EXPECT_EQ(run.output.find("study small on"), std::string::npos) << "measured before the check: " << run.output;
        EXPECT_FALSE(fs::exists(dir / "out" / "study.csv"));
    };
    // The last thing the study would reach: a solver map that cannot run.
    std::string spec = small_spec();
    spec.replace(spec.find("\"time\": 0.05}}"), 14, "\"time\": 0.05, \"control_pressure\": [1000]}}");
    refused(spec, {"solver_map", "no \"control\" section"});
    // A case's scene file that does not load, after a good case.
    test_cli::write_file(dir / "broken.json", "{\"domain\": ");
    refused(
        small_spec(
            R"(, {"name": "c", "scene": "broken.json", "resolutions": ["64x64"], "methods": [{"method": "brute"}]})"),
        {"cases[2] (c)", "broken.json"});
    fs::remove_all(dir);
}

TEST(StudyCliTest, AnUnwritableOutputFolderIsReportedPrecisely) {
    const fs::path dir = test_cli::temp_dir("study_out");
    // Below, the study runs as nobody, who may not read the source tree (a clean clone lies in a
    // private temporary folder): the spec's scene file is copied beside it.
    std::string text = small_spec();
    const std::string assets_scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/hydrostatic.json";
    fs::copy_file(assets_scene, dir / "hydrostatic.json");
    text.replace(text.find(assets_scene), assets_scene.size(), (dir / "hydrostatic.json").string());
    const fs::path spec = test_cli::write_file(dir / "spec.json", text);
    const fs::path file = test_cli::write_file(dir / "a_file", "x");
    auto expect = [&](const fs::path& out, const std::string& part, const std::string& prefix = "") {
        auto run = test_cli::run_aquaform("study " + spec.string() + " --out " + out.string(), prefix);
        EXPECT_EQ(run.exit_code, 2) << run.output;
        EXPECT_NE(run.output.find(part), std::string::npos) << part << ": " << run.output;
        EXPECT_NE(run.output.find("--out"), std::string::npos) << "the fix: " << run.output;
        EXPECT_EQ(run.output.find("does not exist"), std::string::npos) << run.output;
    };
    expect(file, file.string() + " is a file, not a folder");
    expect(file / "sub", file.string() + " is a file, not a folder");
    // Permissions do not bind root: the check runs as nobody there.
    const fs::path read_only = dir / "read_only";
    fs::create_directories(read_only);
    fs::permissions(read_only, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                                   fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
    std::string as_user;
    if (geteuid() == 0) {
        ASSERT_TRUE(fs::exists("/usr/bin/setpriv"))
            << "util-linux's setpriv runs the check as nobody; install util-linux";
        as_user = "exec /usr/bin/setpriv --reuid=65534 --regid=65534 --clear-groups";
    }
    expect(read_only, read_only.string() + " is not writable", as_user);
    expect(read_only / "sub" / "deeper", read_only.string() + " is not writable", as_user);
    // The helper itself: a folder it makes is writable and there.
    ASSERT_TRUE(prepare_output_dir(dir / "new" / "deeper").ok());
    EXPECT_TRUE(fs::is_directory(dir / "new" / "deeper"));
    EXPECT_TRUE(fs::is_empty(dir / "new" / "deeper")) << "the probe file is removed";
    fs::remove_all(dir);
}

TEST(StudyChartsLookupTest, TheScriptIsFoundFromABuildFolderAnywhereAndTheEnvironmentWins) {
    const char* saved = std::getenv("AQUAFORM_SCRIPTS_DIR");
    const std::string restore = saved ? saved : "";
    unsetenv("AQUAFORM_SCRIPTS_DIR");
    // An executable far from the sources: the source tree's scripts/, from the configure step.
    auto found = study::find_study_charts_script("/nonexistent/build/aquaform");
    ASSERT_TRUE(found.ok()) << found.error();
    EXPECT_TRUE(fs::equivalent(found.value(), fs::path(AQUAFORM_SOURCE_DIR) / "scripts" / "study_charts.py"))
        << found.value();
    const fs::path dir = test_cli::temp_dir("study_scripts");
    test_cli::write_file(dir / "study_charts.py", "# a user's own\n");
    setenv("AQUAFORM_SCRIPTS_DIR", dir.c_str(), 1);
    found = study::find_study_charts_script();
    ASSERT_TRUE(found.ok()) << found.error();
    EXPECT_TRUE(fs::equivalent(found.value(), dir / "study_charts.py"));
    if (saved)
        setenv("AQUAFORM_SCRIPTS_DIR", restore.c_str(), 1);
    else
        unsetenv("AQUAFORM_SCRIPTS_DIR");
    fs::remove_all(dir);
}

TEST(StudyChartsLookupTest, APythonWithoutMatplotlibIsPassedOverAndNoneIsANoteNamingThem) {
    auto none = study::find_chart_python({"/nonexistent/python3", "/bin/false"});
    ASSERT_FALSE(none.ok());
    for (const char* part : {"/nonexistent/python3", "/bin/false", "apt-get install python3-matplotlib"})
        EXPECT_NE(none.error().find(part), std::string::npos) << part << ": " << none.error();
    ASSERT_EQ(std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1"), 0)
        << "scripts/setup.sh installs python3-matplotlib for /usr/bin/python3";
    auto found = study::find_chart_python({"/bin/false", "/usr/bin/python3"});
    ASSERT_TRUE(found.ok()) << found.error();
    EXPECT_EQ(found.value(), "/usr/bin/python3");
}

study::StudyRow fake_row(const study::StudySpec& spec, const std::string& cell, size_t i) {
    study::StudyRow r;
    r.case_name = "a";
    r.cell = cell;
    r.method = cell.substr(cell.rfind('/') + 1);
    for (const auto& m : spec.cases[0].methods)
        if (m.label() == r.method) r.config = m;
    r.width = r.height = cell.find("/64x64/") != std::string::npos ? 64 : 32;
    r.particles = 4096;
    // Digits beyond what the files keep: a report from memory would differ from one from the files.
    r.ms_total = 1.234567891 * double(i + 1);
    r.ms_per_pass = {{"render_march", 0.123456789 * double(i + 1)}, {"render_shade", 0.5}};
    r.depth_err_mean = 0.0123456789 * double(i);
    r.rays = 4096;
    r.steps_per_ray = 3.14159265 + double(i);
    r.image = "images/" + std::to_string(i) + ".png";
    r.status = i == 2 ? "overflow, needs \"more\"" : "ok";
    return r;
}

TEST(StudyFilesTest, AResumedStudyReportsExactlyAsOneUninterruptedRun) {
    auto parsed = parse(R"({"name": "u", "cases": [{"name": "a", "resolutions": ["64x64", "32x32"],
        "methods": [{"method": "reference"}, {"method": "sbuffer"}, {"method": "adaptive"}]}]})");
    ASSERT_TRUE(parsed.ok()) << parsed.error();
    const study::StudySpec& spec = parsed.value();
    const std::vector<std::string> cells = study::study_cell_keys(spec);
    ASSERT_EQ(cells.size(), 6u);
    EXPECT_EQ(cells[4], "a/4096/32x32/sbuffer gradient x1 b3");
    const fs::path whole = test_cli::temp_dir("study_files_whole"), resumed = test_cli::temp_dir("study_files_resumed");
    auto report = [&](const fs::path& dir, const study::StudyFiles& files) {
        const auto rows = files.rows();
        EXPECT_TRUE(study::write_study_markdown(dir / "study.md", spec, rows, study::study_targets(rows), "dev").ok());
        return test_cli::read_file(dir / "study.md");
    };
    std::string one_run;
    {
        auto files = study::StudyFiles::open(whole, spec, false);
        ASSERT_TRUE(files.ok()) << files.error();
        for (size_t i = 0; i < cells.size(); ++i) ASSERT_TRUE(files.value().add(fake_row(spec, cells[i], i)).ok());
        one_run = report(whole, files.value());
    }
    {
        auto first = study::StudyFiles::open(resumed, spec, false);
        ASSERT_TRUE(first.ok()) << first.error();
        for (size_t i = 0; i < 3; ++i) ASSERT_TRUE(first.value().add(fake_row(spec, cells[i], i)).ok());
    }
    // A kill in the middle of the fourth row leaves half a line; a pass of it may be there too.
    std::ofstream(resumed / "study.csv", std::ios::app) << "a,,reference,32,32,4096,,,";
    std::ofstream(resumed / "study_passes.csv", std::ios::app)
        << "a,,reference,32,32,4096,render_march,9," << study::spec_hash(spec) << "," << cells[3] << "\n";
    auto again = study::StudyFiles::open(resumed, spec, false);
    ASSERT_TRUE(again.ok()) << again.error();
    EXPECT_EQ(again.value().cells_done(), 3u);
    for (size_t i = 0; i < cells.size(); ++i) {
        EXPECT_EQ(again.value().done(cells[i]), i < 3) << cells[i];
        if (i >= 3) {
            ASSERT_TRUE(again.value().add(fake_row(spec, cells[i], i)).ok());
        }
    }
    EXPECT_EQ(report(resumed, again.value()), one_run);
    EXPECT_NE(one_run.find("overflow, needs \"more\""), std::string::npos) << "a status with a comma and quotes";
    EXPECT_EQ(test_cli::read_file(resumed / "study.csv"), test_cli::read_file(whole / "study.csv"));
    EXPECT_EQ(test_cli::read_file(resumed / "study_passes.csv"), test_cli::read_file(whole / "study_passes.csv"));
    // A file cut before its header was whole holds nothing: a start, not a refusal; an older
    // version's columns are refused, with the way out.
    fs::remove_all(whole);
    fs::create_directories(whole);
    test_cli::write_file(whole / "study.csv", "case,sce");
    auto cut = study::StudyFiles::open(whole, spec, false);
    ASSERT_TRUE(cut.ok()) << cut.error();
    EXPECT_EQ(cut.value().cells_done(), 0u);
    test_cli::write_file(whole / "study.csv", "case,scene,method\na,b,c\n");
    auto older = study::StudyFiles::open(whole, spec, false);
    ASSERT_FALSE(older.ok());
    EXPECT_NE(older.error().find("--fresh"), std::string::npos) << older.error();
    fs::remove_all(whole);
    fs::remove_all(resumed);
}

TEST(StudyCliTest, CtrlCKeepsTheRowsAndTheReportAndARerunResumes) {
    const fs::path dir = test_cli::temp_dir("study_resume");
    const fs::path spec = test_cli::write_file(dir / "spec.json", small_spec()), out = dir / "out";
    const int stopped = test_cli::interrupt_aquaform({"study", spec.string(), "--out", out.string(), "--no-charts"},
                                                     dir / "log", ": reference: ");
    const std::string log = test_cli::read_file(dir / "log");
    ASSERT_EQ(stopped, 130) << log;
    EXPECT_NE(log.find("interrupted"), std::string::npos) << log;
    EXPECT_NE(log.find("run the same command again to resume"), std::string::npos) << log;
    const auto kept = read_csv(out / "study.csv");
    const size_t done = kept.size() - 1;
    ASSERT_GE(done, 1u) << "the reference row was measured before Ctrl-C";
    ASSERT_LT(done, 5u) << "stopped after the current row, not at the end of the frame: " << log;
    EXPECT_NE(test_cli::read_file(out / "study.md").find("| reference |"), std::string::npos)
        << "the report of the rows kept";

    auto resumed = test_cli::run_aquaform("study " + spec.string() + " --out " + out.string() + " --no-charts",
                                          "AQUAFORM_VALIDATION=1");
    ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
    EXPECT_NE(resumed.output.find("resuming: " + std::to_string(done) + " of 6 cells done"), std::string::npos)
        << resumed.output;
    size_t measured = 0;
    for (size_t at = 0; (at = resumed.output.find("study: a, ", at)) != std::string::npos; ++at) ++measured;
    for (size_t at = 0; (at = resumed.output.find("study: b, ", at)) != std::string::npos; ++at) ++measured;
    EXPECT_EQ(measured, 6 - done) << "the cells done were not measured again: " << resumed.output;
    EXPECT_EQ(resumed.output.find(": reference: "), std::string::npos) << resumed.output;
    // The rows a fresh run writes, in its order, the kept ones untouched.
    const auto rows = read_csv(out / "study.csv");
    auto parsed = study::load_study_spec(spec);
    ASSERT_TRUE(parsed.ok()) << parsed.error();
    const auto cells = study::study_cell_keys(parsed.value());
    ASSERT_EQ(rows.size(), cells.size() + 1);
    for (size_t i = 0; i < cells.size(); ++i) {
        EXPECT_EQ(rows[i + 1].back(), cells[i]);
        EXPECT_EQ(rows[i + 1][18], "ok") << cells[i];
        if (i < done) {
            EXPECT_EQ(rows[i + 1], kept[i + 1]);
        }
    }
    EXPECT_EQ(read_csv(out / "solver_map.csv").size(), 2u) << "a header and the map's cell";
    const std::string md = test_cli::read_file(out / "study.md");
    for (const char* row :
         {"| reference |", "| uniform |", "| sbuffer gradient x1 b3 |", "| narrow_range |", "| adaptive |"})
        EXPECT_NE(md.find(row), std::string::npos) << row;

    // Another spec into the same folder is refused, naming the folder and both ways out; --fresh
    // starts over.
    test_cli::write_file(spec, R"({"name": "small", "cases": [{"name": "c", "scene": "dam_break", "particles": [1000],
        "time": 0.05, "resolutions": ["64x64"], "methods": [{"method": "bilateral"}]}]})");
    const std::string again = "study " + spec.string() + " --out " + out.string() + " --no-charts";
    auto refused = test_cli::run_aquaform(again);
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    for (const std::string& part : {(out / "study.csv").string(), std::string("another spec"), std::string("--fresh"),
                                    std::string("another --out")})
        EXPECT_NE(refused.output.find(part), std::string::npos) << part << ": " << refused.output;
    EXPECT_EQ(read_csv(out / "study.csv").size(), 7u) << "the rows stay as they were";
    auto fresh = test_cli::run_aquaform(again + " --fresh", "AQUAFORM_VALIDATION=1");
    ASSERT_EQ(fresh.exit_code, 0) << fresh.output;
    EXPECT_EQ(fresh.output.find("resuming"), std::string::npos) << fresh.output;
    const auto fresh_rows = read_csv(out / "study.csv");
    ASSERT_EQ(fresh_rows.size(), 2u);
    EXPECT_EQ(fresh_rows[1].back(), "c/1000/64x64/bilateral");
    EXPECT_EQ(read_csv(out / "solver_map.csv").size(), 1u) << "the old map's rows are gone too";
    fs::remove_all(dir);
}

TEST(StudyCliTest, TinySpecRunsEndToEndWithCsvTablesAndCharts) {
    const fs::path out = test_cli::temp_dir("study");
    auto run = test_cli::run_aquaform("study " AQUAFORM_ASSETS_DIR "/studies/tiny.json --out " + out.string(),
                                      "AQUAFORM_VALIDATION=1");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const auto rows = read_csv(out / "study.csv");
    ASSERT_GT(rows.size(), 1u);
    const auto& header = rows[0];
    auto column = [&](const std::string& name) {
        const auto it = std::find(header.begin(), header.end(), name);
        EXPECT_NE(it, header.end()) << name;
        return size_t(it - header.begin());
    };
    const size_t method = column("method"), status = column("status"), ms = column("ms_total"),
                 depth = column("depth_err_mean"), overflow = column("overflow"), case_name = column("case"),
                 steps = column("steps_per_ray"), bisect = column("bisection_per_ray"), evals = column("evals_per_ray"),
                 list_entries = column("list_entries_per_pixel"), memory = column("memory_bytes_per_pixel");
    column("roughness_deg");
    size_t sph_rows = 0;
    std::map<std::string, double> curtain_steps;
    std::vector<std::string> methods_seen;
    bool overflow_seen = false;
    for (size_t i = 1; i < rows.size(); ++i) {
        const auto& r = rows[i];
        ASSERT_EQ(r.size(), header.size()) << "row " << i;
        EXPECT_GT(std::stod(r[ms]), 0.0) << r[method];
        if (r[case_name] == "large_metaballs") {
            EXPECT_EQ(r[status], "overflow") << "a 16-byte-per-pixel budget cannot hold x4 metaballs";
            EXPECT_GT(std::stod(r[overflow]), 0.0) << "the memory the lists would need";
            overflow_seen = true;
            continue;
        }
        // The software device ends very long shader loops early; the study says so per row ("cut",
        // or "reference cut" when the reference was), hardware leaves every row "ok".
        const bool cut = r[status].rfind("cut: ", 0) == 0 || r[status].rfind("reference cut: ", 0) == 0;
        EXPECT_TRUE(r[status] == "ok" || cut) << r[method] << ": " << r[status];
        methods_seen.push_back(r[method].substr(0, r[method].find(' ')));
        // Counted costs: steps and bisection add up to the evaluations of the SPH methods; the
        // list methods count their entries; every renderer has memory.
        EXPECT_GT(std::stod(r[memory]), 0.0) << r[method];
        const std::string family = methods_seen.back();
        if (family == "reference" || family == "adaptive" || family == "uniform") {
            ++sph_rows;
            ASSERT_FALSE(r[steps].empty()) << r[method];
            EXPECT_NEAR(std::stod(r[steps]) + std::stod(r[bisect]), std::stod(r[evals]), 1e-3 * std::stod(r[evals]))
                << r[method];
            if (r[case_name] == "curtain") curtain_steps[r[method]] = std::stod(r[steps]);
        } else {
            EXPECT_TRUE(r[steps].empty()) << r[method];
        }
        if (family == "abuffer" || family == "sbuffer") {
            EXPECT_GT(std::stod(r[list_entries]), 0.0) << r[method];
        }
        if (family != "reference") {  // "reference", "reference iso": the references themselves
            ASSERT_FALSE(r[depth].empty()) << r[method] << " has no error against its reference";
            // Each method draws its field's surface to within a few particle radii.
            EXPECT_LT(std::stod(r[depth]), 4.0) << r[method];
        }
    }
    EXPECT_TRUE(overflow_seen);
    for (const char* m : {"reference", "adaptive", "uniform", "brute", "abuffer", "sbuffer", "bilateral",
                          "curvature_flow", "narrow_range"})
        EXPECT_NE(std::find(methods_seen.begin(), methods_seen.end(), m), methods_seen.end()) << m;
    EXPECT_GT(read_csv(out / "study_passes.csv").size(), 10u);
    size_t images = 0;
    for (const auto& entry : fs::directory_iterator(out / "images")) images += entry.path().extension() == ".png";
    EXPECT_EQ(images, rows.size() - 1 + sph_rows) << "a picture of every measurement, and the SPH methods' steps";
    // Wu et al. Fig. 5 on the curtain: the mask saves steps, the skip more.
    ASSERT_EQ(curtain_steps.size(), 4u);
    EXPECT_LT(curtain_steps["adaptive mask"], curtain_steps["uniform"]);
    EXPECT_LT(curtain_steps["adaptive mask+skip"], curtain_steps["adaptive mask"]);
    const auto map = read_csv(out / "solver_map.csv");
    ASSERT_EQ(map.size(), 3u) << "a header and two cells";
    const std::string md = test_cli::read_file(out / "study.md");
    for (const char* part : {"Karpati Table 1", "Wu Table 2", "## Targets", "Wu et al. Fig. 5 layout", "Cost, counted",
                             "Which conclusions depend on the device", "_steps.png", "mask+skip steps/ray in curtain"})
        EXPECT_NE(md.find(part), std::string::npos) << part;
    EXPECT_NE(md.find("overflow (needs"), std::string::npos);
    for (const char* chart : {"pareto", "roughness", "time_vs_particles", "passes", "solver_map"})
        for (const char* ext : {".png", ".svg"}) {
            const fs::path file = out / "charts" / (std::string(chart) + ext);
            ASSERT_TRUE(fs::exists(file)) << file;
            EXPECT_GT(fs::file_size(file), 2000u) << file;
        }
    fs::remove_all(out);
}

TEST(StudyCliTest, ACaseWithNozzlesMeasuresTheWaterAliveAtItsTime) {
    // The tap filling the glass, sized for 3,000 particles over its run: at 0.8 s about a third of
    // them have left the tap, and every method draws those, against the reference of that frame.
    const fs::path out = test_cli::temp_dir("study_tap");
    const fs::path spec = test_cli::write_file(out / "tap.json", R"({"name": "tap", "repeats": 1, "cases": [
        {"name": "tap", "scene": ")" AQUAFORM_ASSETS_DIR R"(/scenes/tap_fills_glass.json", "particles": [3000],
         "time": 0.8, "resolutions": ["96x64"],
         "methods": [{"method": "reference"}, {"method": "adaptive"}, {"method": "sbuffer", "size": [1]},
                     {"method": "bilateral"}]}]})");
    auto run = test_cli::run_aquaform("study " + spec.string() + " --out " + (out / "study").string(),
                                      "AQUAFORM_VALIDATION=1");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const auto rows = read_csv(out / "study" / "study.csv");
    ASSERT_EQ(rows.size(), 5u) << "a header and four methods";
    const auto& header = rows[0];
    const auto column = [&](const std::string& name) {
        return size_t(std::find(header.begin(), header.end(), name) - header.begin());
    };
    const size_t particles = column("particles"), status = column("status"), depth = column("depth_err_mean");
    for (size_t i = 1; i < rows.size(); ++i) {
        EXPECT_EQ(rows[i][status], "ok") << rows[i][column("method")];
        EXPECT_EQ(rows[i][particles], rows[1][particles]) << "every method draws the same frame";
        if (i > 1) {
            EXPECT_LT(std::stod(rows[i][depth]), 4.0) << rows[i][column("method")];
        }
    }
    const int alive = std::stoi(rows[1][particles]);
    EXPECT_GT(alive, 600) << "the water the tap made by 0.8 s";
    EXPECT_LT(alive, 1500) << "the count alive at 0.8 s, not the capacity";
    fs::remove_all(out);
}

}  // namespace
}  // namespace aquaform::cli
