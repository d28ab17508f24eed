// Where aquaform writes and what it writes there: never through a symbolic link planted in --out
// (the lock, stats.csv, run.json, exports.csv, any file written whole), with the link's target
// left as it was; user text (a scene's file name that is not UTF-8, a name with control
// characters and XML's special characters) kept well-formed in JSON, CSV and SVG; the host
// memory figure said in units that mean something, naming AQUAFORM_HOST_MEMORY when it set it.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/csv.h"
#include "core/error.h"
#include "core/file_write.h"
#include "core/host_memory.h"
#include "core/output_dir.h"
#include "core/text_escape.h"
#include "geometry/mesh.h"
#include "geometry/primitives.h"
#include "study/study_rows.h"
#include "study/study_spec.h"
#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using test_cli::read_file;
using test_cli::temp_dir;
using test_cli::write_file;

constexpr const char* kPrecious = "precious: not aquaform's to write\n";

/// `dir`/`name` made a symbolic link to a file outside `dir` holding kPrecious; returns the target.
fs::path plant_link(const fs::path& dir, const std::string& name) {
    const fs::path target = dir.parent_path() / (dir.filename().string() + "_outside_" + name);
    write_file(target, kPrecious);
    fs::create_directories(dir);
    fs::create_symlink(target, dir / name);
    return target;
}

void expect_refused_link(const std::string& message, const fs::path& link) {
    EXPECT_NE(message.find(link.string() + " is a symbolic link"), std::string::npos) << message;
    EXPECT_NE(message.find("remove the link"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
}

/// Whether /usr/bin/python3's XML parser accepts `file` (the check that tools reading an SVG make).
bool well_formed_xml(const fs::path& file) {
    const std::string command =
        "/usr/bin/python3 -c 'import sys, xml.dom.minidom; xml.dom.minidom.parse(sys.argv[1])' '" + file.string() +
        "' 2>/dev/null";
    return std::system(command.c_str()) == 0;
}

TEST(OutputSafety, AFileWrittenWholeRefusesALinkAndLeavesItsTarget) {
    const fs::path dir = temp_dir("link_whole") / "out";
    const fs::path target = plant_link(dir, "result.json");
    const Result<bool> written = write_file_with(dir / "result.json", [](std::ostream& out) { out << "{}\n"; });
    ASSERT_FALSE(written.ok());
    expect_refused_link(written.error(), dir / "result.json");
    EXPECT_EQ(read_file(target), kPrecious);
    EXPECT_TRUE(fs::is_symlink(dir / "result.json")) << "the link is the user's: left as it is";
    EXPECT_FALSE(prepare_output_file(dir / "result.json").ok()) << "refused before any work too";
    fs::remove_all(dir.parent_path());
}

TEST(OutputSafety, AnAppendedFileRefusesALinkAndLeavesItsTarget) {
    const fs::path dir = temp_dir("link_appended") / "out";
    const fs::path target = plant_link(dir, "rows.csv");
    for (const AppendedFile::Start start : {AppendedFile::Start::empty, AppendedFile::Start::after_existing}) {
        const Result<AppendedFile> opened = AppendedFile::open(dir / "rows.csv", start);
        ASSERT_FALSE(opened.ok());
        expect_refused_link(opened.error(), dir / "rows.csv");
    }
    EXPECT_EQ(read_file(target), kPrecious);
    fs::remove_all(dir.parent_path());
}

TEST(OutputSafety, TheLockRefusesALinkAFolderAndAnotherHolderNamingTheLockFile) {
    const fs::path root = temp_dir("lock");
    const fs::path linked = root / "linked", folder = root / "folder", held = root / "held";
    const fs::path target = plant_link(linked, kOutputLockName);
    const Result<bool> through_link = hold_output_dir(linked, "test");
    ASSERT_FALSE(through_link.ok());
    expect_refused_link(through_link.error(), linked / kOutputLockName);
    EXPECT_EQ(read_file(target), kPrecious) << "the lock truncated the file its link points to";

    fs::create_directories(folder / kOutputLockName);
    const Result<bool> a_folder = hold_output_dir(folder, "test");
    ASSERT_FALSE(a_folder.ok());
    EXPECT_NE(a_folder.error().find((folder / kOutputLockName).string() + ": it is a folder"), std::string::npos)
        << a_folder.error();

    // Another holder: a second open file description, as another process has.
    fs::create_directories(held);
    const int other = ::open((held / kOutputLockName).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    ASSERT_GE(other, 0);
    ASSERT_EQ(flock(other, LOCK_EX | LOCK_NB), 0);
    const Result<bool> taken = hold_output_dir(held, "test");
    ::close(other);
    ASSERT_FALSE(taken.ok());
    EXPECT_NE(taken.error().find("which holds " + (held / kOutputLockName).string()), std::string::npos)
        << taken.error();
    fs::remove_all(root);
}

TEST(OutputSafety, RunRefusesALinkWhereItWritesBeforeAnyWork) {
    const fs::path root = temp_dir("run_links");
    const fs::path scene =
        write_file(root / "tiny.json", R"({"name": "tiny", "domain": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.08]},
        "particle_spacing": 0.02, "fluid_blocks": [{"min": [0, 0, 0], "max": [0.1, 0.2, 0.08]}], "frames": 2})");
    for (const std::string name : {kOutputLockName, "stats.csv", "run.json", "exports.csv"}) {
        const fs::path out = root / ("out_" + name.substr(name.find_first_not_of('.')));
        const fs::path target = plant_link(out, name);
        const test_cli::Outcome o = test_cli::run_aquaform("run " + scene.string() + " --no-png --out " + out.string());
        EXPECT_EQ(o.exit_code, 2) << name << ": " << o.output;
        EXPECT_NE(o.output.find((out / name).string() + " is a symbolic link"), std::string::npos) << o.output;
        EXPECT_NE(o.output.find("remove the link"), std::string::npos) << o.output;
        EXPECT_EQ(read_file(target), kPrecious) << name << "'s target was written";
        EXPECT_FALSE(fs::exists(out / "stats.csv") && !fs::is_symlink(out / "stats.csv")) << "refused before any work";
    }
    fs::remove_all(root);
}

TEST(OutputSafety, UserTextStaysOneCsvFieldWhateverItHolds) {
    for (const std::string text : {"plain", "a,b", "say \"hi\"", "line\nbreak\r\x01 bell\x07", "bad \xff byte", ""}) {
        const std::string row = "first," + csv_field(text) + ",last";
        EXPECT_EQ(row.find_first_of("\n\r\x01\x07"), std::string::npos) << "a row is one line of text: " << row;
        const std::vector<std::string> fields = split_csv_line(row);
        ASSERT_EQ(fields.size(), 3u) << row;
        EXPECT_EQ(fields[2], "last");
        EXPECT_EQ(valid_utf8(fields[1]), fields[1]) << "UTF-8: " << fields[1];
    }
    EXPECT_EQ(csv_field("ball (1.00)", true), "\"ball (1.00)\"");
}

TEST(OutputSafety, UserTextStaysWellFormedXml) {
    const fs::path dir = temp_dir("xml_text");
    const std::string text = "a\x01<b>&c\nd'e\"f \xff g\xEF\xBF\xBF";
    write_file(dir / "doc.svg", "<svg xmlns=\"http://www.w3.org/2000/svg\"><text class=\"" + xml_text(text) + "\">" +
                                    xml_text(text) + "</text></svg>\n");
    EXPECT_TRUE(well_formed_xml(dir / "doc.svg")) << read_file(dir / "doc.svg");
    write_file(dir / "raw.svg", "<svg><text>" + text + "</text></svg>\n");
    EXPECT_FALSE(well_formed_xml(dir / "raw.svg")) << "the check tells an ill-formed file";
    fs::remove_all(dir);
}

TEST(OutputSafety, JsonTextReplacesBytesThatAreNotUtf8) {
    const nlohmann::json doc = {{"scene", "dam\xff.json"}};
    EXPECT_THROW((void)doc.dump(), nlohmann::json::type_error) << "what a plain dump does";
    const nlohmann::json back = nlohmann::json::parse(json_text(doc, 2));
    EXPECT_EQ(back["scene"], "dam\xEF\xBF\xBD.json");
}

TEST(OutputSafety, ASceneFileNameThatIsNotUtf8RunsAndItsRecordsParse) {
    const fs::path root = temp_dir("utf8_name");
    const fs::path scene =
        write_file(root / "dam\xff\xfe.json", R"({"name": "tiny", "domain": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.08]},
        "particle_spacing": 0.02, "fluid_blocks": [{"min": [0, 0, 0], "max": [0.1, 0.2, 0.08]}], "frames": 2})");
    const fs::path run_out = root / "run", render_out = root / "render";
    const test_cli::Outcome run =
        test_cli::run_aquaform("run '" + scene.string() + "' --no-png --out " + run_out.string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const nlohmann::json described = nlohmann::json::parse(read_file(run_out / "run.json"));
    EXPECT_NE(described["scene"].get<std::string>().find("dam\xEF\xBF\xBD"), std::string::npos) << described.dump();
    std::istringstream stats(read_file(run_out / "stats.csv"));
    int lines = 0;
    for (std::string line; std::getline(stats, line);) ++lines;
    EXPECT_EQ(lines, 3) << "the header and frames 0 and 1";

    const test_cli::Outcome render = test_cli::run_aquaform("render '" + scene.string() +
                                                            "' --frame 0 --resolution 32x32 --method uniform "
                                                            "--no-reference --out " +
                                                            render_out.string());
    ASSERT_EQ(render.exit_code, 0) << render.output;
    const nlohmann::json report = nlohmann::json::parse(read_file(render_out / "render.json"));
    EXPECT_NE(report["scene"].get<std::string>().find("dam\xEF\xBF\xBD"), std::string::npos) << report.dump();
    fs::remove_all(root);
}

TEST(OutputSafety, ASceneNameWithControlAndMarkupCharactersGivesWellFormedFiles) {
    const fs::path root = temp_dir("odd_name");
    const fs::path scene = write_file(root / "odd.json", R"({"name": "a\u0001<b>&c\nd'e\"f,g",
        "domain": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.08]}, "particle_spacing": 0.02,
        "fluid_blocks": [{"min": [0, 0, 0], "max": [0.1, 0.2, 0.08]}], "column_width": 0.1, "frames": 3})");
    const fs::path out = root / "out";
    const test_cli::Outcome o = test_cli::run_aquaform("run " + scene.string() + " --no-png --out " + out.string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    EXPECT_TRUE(well_formed_xml(out / "front.svg")) << read_file(out / "front.svg");
    EXPECT_NE(read_file(out / "front.svg").find("a\xEF\xBF\xBD&lt;b&gt;&amp;c"), std::string::npos)
        << "the name is there, its control character replaced";
    EXPECT_EQ(nlohmann::json::parse(read_file(out / "run.json"))["name"], "a\x01<b>&c\nd'e\"f,g");
    for (const char* csv : {"stats.csv", "front.csv"}) {
        std::istringstream rows(read_file(out / csv));
        std::string header;
        std::getline(rows, header);
        int count = 0;
        for (std::string line; std::getline(rows, line); ++count)
            EXPECT_EQ(split_csv_line(line).size(), split_csv_line(header).size()) << csv << ": " << line;
        EXPECT_EQ(count, 3) << csv;
    }
    fs::remove_all(root);
}

TEST(OutputSafety, NoTextAUserGivesIsAFormat) {
    // Every name and file name a run takes holds printf directives (%s and %n crash a printf that
    // takes them for its format; %d prints another number): the run ends normally and writes
    // each of them as the text it is. The build refuses formats that are not literals
    // (-Werror=format-nonliteral), and an obstacle's name, which names its files, holds letters,
    // digits, '_' and '-' only, so a directive there is refused, not run.
    const fs::path root = temp_dir("format_names");
    const std::string odd = "%s%n%d%04u";
    ASSERT_TRUE(geometry::write_obj(root / ("rock" + odd + ".obj"),
                                    geometry::make_box({{0.3f, 0.0f, 0.0f}, {0.36f, 0.04f, 0.08f}}))
                    .ok());
    const auto scene_text = [&](const std::string& obstacle_name) {
        return R"({"name": ")" + odd +
               R"(", "domain": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.08]}, "particle_spacing": 0.02,
            "fluid_blocks": [{"min": [0, 0, 0], "max": [0.1, 0.2, 0.08]}], "frames": 3, "whitewater": {},
            "obstacles": {")" +
               obstacle_name + R"(": {"file": "rock)" + odd + R"(.obj"}},
            "probes": {"gauges": {"H)" +
               odd + R"(": {"x": 0.2, "z": 0.04}}, "sensors": {"P)" + odd + R"(": {"position": [0.2, 0, 0.04]}}}})";
    };
    const fs::path scene = write_file(root / ("scene" + odd + ".json"), scene_text("rock"));
    const fs::path out = root / ("out" + odd);
    const test_cli::Outcome o = test_cli::run_aquaform("run '" + scene.string() +
                                                       "' --no-png --vtk-every 1 --mesh-every 2 "
                                                       "--whitewater-every 1 --out '" +
                                                       out.string() + "'");
    ASSERT_EQ(o.exit_code, 0) << o.output;
    EXPECT_NE(o.output.find(odd), std::string::npos) << "the scene's name printed as it is: " << o.output;
    EXPECT_EQ(nlohmann::json::parse(read_file(out / "run.json"))["name"], odd);
    const std::string probes = read_file(out / "probes.csv");
    EXPECT_EQ(probes.rfind("time_s,H" + odd + "_m,P" + odd + "_Pa,", 0), 0u) << probes.substr(0, 200);
    EXPECT_NE(read_file(out / "probe_heights.svg").find("H" + odd), std::string::npos);
    EXPECT_TRUE(fs::exists(out / "obstacle_rock.obj"));

    for (const std::string name : {"a%s%s%s%s", "x%n%n", "p%d", "q%04u"}) {
        write_file(scene, scene_text(name));
        const test_cli::Outcome refused =
            test_cli::run_aquaform("run '" + scene.string() + "' --no-png --out '" + out.string() + "'");
        EXPECT_EQ(refused.exit_code, 2) << name << ": " << refused.output;
        EXPECT_NE(refused.output.find("obstacles: the name \"" + name + "\""), std::string::npos) << refused.output;
    }
    fs::remove_all(root);
}

TEST(OutputSafety, AnEarlierRunsFileThatCannotBeRemovedIsReportedBeforeAnyWork) {
    // A rerun as another user into a sticky folder (as /tmp is) that holds a root-owned file of an
    // earlier run: the file cannot be removed, and the run says so at once, naming it, instead of
    // simulating and then failing to write over it.
    const fs::path root = temp_dir("sticky_rerun");
    const fs::path out = root / "out";
    fs::create_directories(out);
    fs::permissions(root, fs::perms::all);
    fs::permissions(out, fs::perms::all | fs::perms::sticky_bit);
    const fs::path scene = root / "dam.json";
    fs::copy_file(std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json", scene);
    fs::permissions(scene, fs::perms::owner_all | fs::perms::group_read | fs::perms::others_read);
    write_file(out / "probe_heights.svg", "<svg/>");
    std::string as_user;
    if (geteuid() == 0) {
        ASSERT_TRUE(fs::exists("/usr/bin/setpriv"))
            << "util-linux's setpriv runs the check as nobody; install util-linux";
        as_user = "exec /usr/bin/setpriv --reuid=65534 --regid=65534 --clear-groups";
    } else {
        GTEST_SKIP() << "needs root to own the earlier file";  // CI runs as root
    }
    const test_cli::Outcome o =
        test_cli::run_aquaform("run " + scene.string() + " --frames 2 --no-png --out " + out.string(), as_user);
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_NE(o.output.find("cannot remove " + (out / "probe_heights.svg").string()), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("another --out"), std::string::npos) << o.output;
    EXPECT_FALSE(fs::exists(out / "stats.csv")) << "no work was done";
    fs::remove_all(root);
}

TEST(HostMemory, ASmallLimitFromTheVariableIsSaidInKibAndNamed) {
    setenv("AQUAFORM_HOST_MEMORY", "1K", 1);
    EXPECT_EQ(available_host_memory().value_or(0), 1024u);
    EXPECT_EQ(available_memory_text(1024), "1 KiB are available (AQUAFORM_HOST_MEMORY=1K; unset it or raise it)");
    EXPECT_EQ(available_memory_text(4096), "4 KiB are available") << "a figure the variable did not set";

    const fs::path dir = temp_dir("host_memory");
    write_file(dir / "quad.obj",
               "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 2 5\nf 2 3 5\n"
               "f 3 4 5\nf 4 1 5\n# padding the file past 1 KiB / 6 " +
                   std::string(200, '#') + "\n");
    const auto loaded = geometry::load_obj(dir / "quad.obj");
    unsetenv("AQUAFORM_HOST_MEMORY");
    ASSERT_FALSE(loaded.ok());
    EXPECT_NE(
        loaded.error().find("KiB of memory but 1 KiB are available (AQUAFORM_HOST_MEMORY=1K; unset it or raise it)"),
        std::string::npos)
        << loaded.error();
    EXPECT_EQ(loaded.error().find("0 MB"), std::string::npos) << loaded.error();
    fs::remove_all(dir);

    EXPECT_EQ(memory_size_text(0), "0 bytes");
    EXPECT_EQ(memory_size_text(1023), "1023 bytes");
    EXPECT_EQ(memory_size_text(5000), "4 KiB");
    EXPECT_EQ(memory_size_text(uint64_t(3) << 20), "3 MB");
}

TEST(HostMemory, AVariableThatIsNotASizeIsRefusedNamingItAndTheFix) {
    for (const std::string bad : {"lots", "1.5G", "8GB", "0", "0K", "-1", " 8G", "K", "99999999999999999G"}) {
        setenv("AQUAFORM_HOST_MEMORY", bad.c_str(), 1);
        try {
            (void)available_host_memory();
            ADD_FAILURE() << bad << " was taken";
        } catch (const Failure& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find("AQUAFORM_HOST_MEMORY is \"" + bad + "\""), std::string::npos) << message;
            EXPECT_NE(message.find("e.g. 8G, 512M"), std::string::npos) << message;
            EXPECT_NE(message.find("or unset it"), std::string::npos) << message;
            EXPECT_EQ(e.kind(), Failure::Kind::input);
        }
    }
    unsetenv("AQUAFORM_HOST_MEMORY");
}

TEST(StudySpecFamily, AnUnknownMethodFamilyIsAnErrorNotTheSurfaceFamily) {
    EXPECT_EQ(study::study_family("metaball").value(), study::StudyFamily::metaball);
    EXPECT_EQ(study::study_family("screen_space").value(), study::StudyFamily::screen_space);
    EXPECT_EQ(study::study_family("surface").value(), study::StudyFamily::surface);
    const Result<study::StudyFamily> unknown = study::study_family("volume");
    ASSERT_FALSE(unknown.ok());
    for (const char* says : {"\"volume\"", "surface", "metaball", "screen_space"})
        EXPECT_NE(unknown.error().find(says), std::string::npos) << says << " in: " << unknown.error();
}

}  // namespace
}  // namespace aquaform
