// A full disk (issue 28, class 6): `run` with every export and a video, `render` and `study`,
// each into a small RAM disk that fills at several points of its work. Whatever the command
// leaves must be whole (a PNG that decodes, a .vtu that ends, an OBJ whose faces have their
// vertices, a PLY as long as its header says, a VDB OpenVDB reads, CSV rows with every column),
// and it must end with exit 1 naming the full disk.
//
// The disk is a tmpfs mounted in a private mount namespace (`unshare -rm`, which needs no root):
// it disappears with the command, so its files are copied out before.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>
#include <nlohmann/json.hpp>

#include "core/file_write.h"
#include "pictures/image_io.h"
#include "pictures/video.h"
#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;

struct SmallDiskRun {
    int exit_code = -1;
    std::string output;
    fs::path copy;  ///< what the command left on the disk
};

/// Runs `aquaform ARGS --out DISK/out` with DISK a tmpfs of `kib` KiB, then copies DISK/out to
/// `work`/copy. `args` may name the disk as @DISK@ (a --video path on it).
SmallDiskRun run_on_small_disk(const fs::path& work, uint64_t kib, std::string args) {
    const fs::path disk = work / "disk", copy = work / "copy", log = work / "log.txt", code = work / "code.txt";
    fs::remove_all(copy);
    fs::create_directories(disk);
    for (size_t at; (at = args.find("@DISK@")) != std::string::npos;) args.replace(at, 6, disk.string());
    const fs::path script = test_cli::write_file(
        work / "on_small_disk.sh", "mount -t tmpfs -o size=" + std::to_string(kib) + "k tmpfs '" + disk.string() +
                                       "' || exit 99\n" + AQUAFORM_BINARY + " " + args + " --out '" +
                                       (disk / "out").string() + "' >'" + log.string() + "' 2>&1\necho $? >'" +
                                       code.string() + "'\ncp -a '" + (disk / "out").string() + "' '" + copy.string() +
                                       "'\n");
    const std::string command = "unshare -rm sh '" + script.string() + "'";
    const int status = std::system(command.c_str());
    EXPECT_EQ(status, 0) << "could not make the small disk: " << command;
    SmallDiskRun run;
    run.output = test_cli::read_file(log);
    run.exit_code = std::atoi(test_cli::read_file(code).c_str());
    run.copy = copy;
    return run;
}

uint64_t folder_bytes(const fs::path& dir) {
    uint64_t bytes = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) bytes += e.file_size();
    return bytes;
}

bool ends_with(const std::string& text, const std::string& tail) {
    return text.size() >= tail.size() && text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

/// Why a binary PLY is not whole: its length is not what the header's elements make.
std::string ply_problem(const std::string& bytes) {
    const size_t header_end = bytes.find("end_header\n");
    if (header_end == std::string::npos) return "no end_header";
    std::istringstream header(bytes.substr(0, header_end));
    struct Element {
        uint64_t count = 0;
        uint64_t fixed = 0;           // bytes of its scalar properties
        std::vector<int> list_sizes;  // (count type size, item size) pairs, flattened
    };
    const std::map<std::string, int> size_of{{"char", 1}, {"uchar", 1}, {"short", 2}, {"ushort", 2},
                                             {"int", 4},  {"uint", 4},  {"float", 4}, {"double", 8}};
    std::vector<Element> elements;
    for (std::string line; std::getline(header, line);) {
        std::istringstream words(line);
        std::string word, type;
        words >> word;
        if (word == "format" && line.find("binary_little_endian") == std::string::npos) return "not binary: " + line;
        if (word == "element") elements.emplace_back(), words >> type >> elements.back().count;
        if (word == "property" && !elements.empty()) {
            words >> type;
            if (type == "list") {
                std::string count_type, item_type;
                words >> count_type >> item_type;
                elements.back().list_sizes.push_back(size_of.at(count_type));
                elements.back().list_sizes.push_back(size_of.at(item_type));
            } else {
                elements.back().fixed += size_of.at(type);
            }
        }
    }
    size_t at = header_end + 11;
    for (const Element& e : elements)
        for (uint64_t i = 0; i < e.count; ++i) {
            at += e.fixed;
            for (size_t l = 0; l < e.list_sizes.size(); l += 2) {
                if (at >= bytes.size()) return "cut in element " + std::to_string(i);
                const uint8_t n = uint8_t(bytes[at]);  // the exporters count lists with a uchar
                at += e.list_sizes[l] + uint64_t(n) * e.list_sizes[l + 1];
            }
        }
    if (at != bytes.size()) return std::to_string(bytes.size()) + " bytes where the header makes " + std::to_string(at);
    return "";
}

std::string obj_problem(const std::string& text) {
    if (!ends_with(text, "\n")) return "the last line is cut";
    std::istringstream lines(text);
    uint64_t vertices = 0, faces = 0;
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("v ", 0) == 0) ++vertices;
        if (line.rfind("f ", 0) == 0) {
            ++faces;
            std::istringstream words(line.substr(2));
            for (uint64_t index; words >> index;)
                if (index == 0 || index > vertices) return "a face names vertex " + std::to_string(index);
        }
    }
    return faces > 0 ? "" : "no faces";
}

std::string csv_problem(const std::string& text) {
    if (text.empty()) return "";  // a file the first row never reached
    if (!ends_with(text, "\n")) return "the last row is cut";
    std::istringstream lines(text);
    std::string header;
    std::getline(lines, header);
    const auto columns = std::count(header.begin(), header.end(), ',');
    int row = 1;
    for (std::string line; std::getline(lines, line); ++row) {
        // Quoted fields (a study's labels) may hold commas: count outside the quotes.
        long commas = 0;
        bool quoted = false;
        for (char c : line) quoted ^= c == '"', commas += c == ',' && !quoted;
        if (commas != columns) return "row " + std::to_string(row) + " has " + std::to_string(commas + 1) + " fields";
    }
    return "";
}

/// Why `path`, which a command left, is not whole ("" when it is).
std::string file_problem(const fs::path& path) {
    const std::string ext = path.extension().string();
    const std::string bytes = test_cli::read_file(path);
    if (ext == ".png") {
        auto image = read_png(path);
        return image ? "" : image.error();
    }
    if (ext == ".vtu" || ext == ".pvd") return ends_with(bytes, "</VTKFile>\n") ? "" : "does not end in </VTKFile>";
    if (ext == ".svg") return ends_with(bytes, "</svg>\n") ? "" : "does not end in </svg>";
    if (ext == ".obj") return obj_problem(bytes);
    if (ext == ".ply") return ply_problem(bytes);
    if (ext == ".csv") return csv_problem(bytes);
    if (ext == ".json") return nlohmann::json::accept(bytes) ? "" : "not JSON";
    if (ext == ".md") return ends_with(bytes, "\n") ? "" : "the last line is cut";
    if (ext == ".mp4") {
        auto whole = mp4_is_whole(path);
        return whole ? "" : whole.error();
    }
    if (ext == ".vdb") {
        try {
            openvdb::initialize();
            openvdb::io::File file(path.string());
            file.open();
            file.readGrid("density");
            file.close();
            return "";
        } catch (const std::exception& e) {
            return std::string("OpenVDB cannot read it: ") + e.what();
        }
    }
    if (path.filename() == ".aquaform.lock") return "";
    return "a file the test does not know how to check";
}

/// Checks every file a command left; returns how many there were.
size_t expect_every_file_whole(const fs::path& dir, const std::string& context) {
    size_t files = 0;
    if (!fs::exists(dir)) return 0;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (!e.is_regular_file()) continue;
        ++files;
        const std::string problem = file_problem(e.path());
        EXPECT_EQ(problem, "") << context << ": " << e.path().lexically_relative(dir) << " is not whole";
    }
    return files;
}

/// The command filled the disk: it said so and ended with exit 1.
void expect_full_disk_reported(const SmallDiskRun& run, const std::string& context) {
    EXPECT_EQ(run.exit_code, 1) << context << ":\n" << run.output;
    EXPECT_NE(run.output.find("no space left on the disk"), std::string::npos) << context << ":\n" << run.output;
}

/// While it lives, no file this process writes may grow past `bytes` (RLIMIT_FSIZE): the write
/// that crosses it is cut there and the next one fails, as on a disk that fills.
class FileSizeLimit {
public:
    explicit FileSizeLimit(rlim_t bytes) {
        getrlimit(RLIMIT_FSIZE, &saved_);
        old_handler_ = signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG instead
        rlimit limit = saved_;
        limit.rlim_cur = bytes;
        setrlimit(RLIMIT_FSIZE, &limit);
    }
    ~FileSizeLimit() {
        setrlimit(RLIMIT_FSIZE, &saved_);
        signal(SIGXFSZ, old_handler_);
    }

private:
    rlimit saved_{};
    sighandler_t old_handler_ = nullptr;
};

TEST(FileWrite, AnAppendCutShortIsTakenBackToTheLastWholeRecord) {
    const fs::path dir = test_cli::temp_dir("appended_file");
    auto file = AppendedFile::open(dir / "rows.csv");
    ASSERT_TRUE(file) << file.error();
    const std::string record = std::string(299, 'x') + "\n";
    int whole = 0;
    Result<bool> appended = true;
    {
        const FileSizeLimit limit(1000);  // three records and a third of the fourth
        while (whole < 10 && (appended = file.value().append(record))) ++whole;
    }
    EXPECT_EQ(whole, 3);
    ASSERT_FALSE(appended);
    EXPECT_NE(appended.error().find("rows.csv"), std::string::npos) << appended.error();
    EXPECT_EQ(fs::file_size(dir / "rows.csv"), 3 * record.size()) << "the cut record is taken back";
    EXPECT_TRUE(file.value().append(record)) << "with room again, the file grows on from its last whole record";
    EXPECT_EQ(fs::file_size(dir / "rows.csv"), 4 * record.size());
    fs::remove_all(dir);
}

TEST(FileWrite, AFileCutShortIsRemovedAndTheEarlierOneKept) {
    const fs::path dir = test_cli::temp_dir("file_write_cut");
    const auto fill = [](std::ostream& out) { out << std::string(5000, 'y'); };
    ASSERT_TRUE(write_file_with(dir / "kept.txt", [](std::ostream& out) { out << "earlier\n"; }));
    Result<bool> fresh = true, replacing = true;
    {
        const FileSizeLimit limit(1000);
        fresh = write_file_with(dir / "cut.txt", fill);
        replacing = write_file_with(dir / "kept.txt", fill);
    }
    ASSERT_FALSE(fresh);
    EXPECT_NE(fresh.error().find("cut.txt"), std::string::npos) << fresh.error();
    EXPECT_FALSE(fs::exists(dir / "cut.txt")) << "a file cut short is not left";
    ASSERT_FALSE(replacing);
    EXPECT_EQ(test_cli::read_file(dir / "kept.txt"), "earlier\n")
        << "the earlier file stays until the new one is whole";
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1) << "no staged file is left";
    fs::remove_all(dir);
}

TEST(FileWrite, ADeviceIsWrittenWhereItIsNotReplaced) {
    ASSERT_TRUE(write_file_with("/dev/null", [](std::ostream& out) { out << "discarded\n"; }));
    EXPECT_TRUE(fs::is_character_file("/dev/null")) << "a rename must never replace a device node";
}

/// Fractions of the full output at which the disk is made to fill.
const std::vector<double> kFillPoints = {0.03, 0.15, 0.35, 0.6, 0.85};

TEST(FullDisk, RunLeavesOnlyWholeFilesAndItsStatsListTheFramesWritten) {
    const fs::path work = test_cli::temp_dir("full_disk_run");
    const std::string scene = std::string(AQUAFORM_SOURCE_DIR) + "/assets/scenes/dam_break.json";
    const std::string exports =
        " --particles 1000 --frames 6 --resolution 160x90 --vtk-every 1 --ply-every 1 "
        "--vdb-every 2 --mesh-every 1 --video '@DISK@/out/frames.mp4'";
    // The whole output, on a disk with room, sets the sizes that cut it (for both mesh writers).
    uint64_t total[2] = {0, 0};
    for (int ply = 0; ply < 2; ++ply) {
        const SmallDiskRun roomy =
            run_on_small_disk(work, 1 << 20, "run " + scene + exports + (ply ? " --mesh-format ply" : ""));
        ASSERT_EQ(roomy.exit_code, 0) << roomy.output;
        total[ply] = folder_bytes(roomy.copy);
        ASSERT_GT(expect_every_file_whole(roomy.copy, "roomy"), 20u);
    }
    for (size_t i = 0; i < kFillPoints.size(); ++i) {
        const int ply = int(i % 2);
        const uint64_t kib = std::max<uint64_t>(8, uint64_t(kFillPoints[i] * double(total[ply])) / 1024);
        const std::string format = ply ? " --mesh-format ply" : "";
        const std::string context = "run on a " + std::to_string(kib) + " KiB disk" + format;
        const SmallDiskRun run = run_on_small_disk(work, kib, "run " + scene + exports + format);
        expect_full_disk_reported(run, context);
        expect_every_file_whole(run.copy, context);
        // stats.csv lists the frames whose files are all written, and the video (when made) has them.
        const std::string stats = test_cli::read_file(run.copy / "stats.csv");
        const auto rows = std::max<long>(0, long(std::count(stats.begin(), stats.end(), '\n')) - 1);
        for (long f = 0; f < rows; ++f) {
            char name[32];
            std::snprintf(name, sizeof name, "frame_%04ld.png", f);
            EXPECT_TRUE(fs::exists(run.copy / name)) << context << ": stats.csv has frame " << f << " but not " << name;
        }
        EXPECT_NE(run.output.find(std::to_string(rows) + " frames ("), std::string::npos)
            << context << ": the summary should count the " << rows << " frames stats.csv lists:\n"
            << run.output;
    }
    fs::remove_all(work);
}

TEST(FullDisk, RenderAndStudyLeaveOnlyWholeFiles) {
    const fs::path work = test_cli::temp_dir("full_disk_study");
    const std::string scene = std::string(AQUAFORM_SOURCE_DIR) + "/assets/scenes/dam_break.json";
    const fs::path spec = test_cli::write_file(
        work / "spec.json",
        "{\"name\": \"full_disk\", \"repeats\": 1, \"cases\": [{\"name\": \"c\", \"scene\": \"" + scene +
            "\", \"particles\": [1000], \"time\": 0.05, \"resolutions\": [\"96x64\"], \"methods\": [{\"method\": "
            "\"reference\"}, {\"method\": \"uniform\"}, {\"method\": \"adaptive\"}, {\"method\": \"bilateral\"}]}]}");
    const std::vector<std::string> commands = {
        "render " + scene + " --particles 1000 --frame 2 --resolution 320x200 --method uniform",
        "study '" + spec.string() + "' --no-charts",  // the charts come from matplotlib: not this test's concern
    };
    for (const std::string& command : commands) {
        const SmallDiskRun roomy = run_on_small_disk(work, 1 << 20, command);
        ASSERT_EQ(roomy.exit_code, 0) << roomy.output;
        const uint64_t total = folder_bytes(roomy.copy);
        ASSERT_GT(expect_every_file_whole(roomy.copy, command), 1u);
        for (double at : kFillPoints) {
            const uint64_t kib = std::max<uint64_t>(4, uint64_t(at * double(total)) / 1024);
            if (kib * 1024 >= total) continue;
            const std::string context = command + " on a " + std::to_string(kib) + " KiB disk";
            const SmallDiskRun run = run_on_small_disk(work, kib, command);
            expect_full_disk_reported(run, context);
            expect_every_file_whole(run.copy, context);
        }
    }
    fs::remove_all(work);
}

}  // namespace
}  // namespace aquaform
