// `run --video`: an H.264 MP4 made by ffmpeg from the run's PNG frames, checked by ffprobe; the
// refusals before any work (no ffmpeg, a name that is not .mp4, --no-png); `--camera`.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "pictures/video.h"
#include "tests/cli_helpers.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using test_cli::run_aquaform;
using test_cli::temp_dir;
using test_cli::write_file;

const char* kTinyTank = R"({
  "name": "tiny tank",
  "domain": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.08]},
  "particle_spacing": 0.02,
  "fluid_blocks": [{"min": [0, 0, 0], "max": [0.1, 0.2, 0.08]}],
  "frames": 3
})";

/// What ffprobe says of the video's stream: "codec,width,height,frames".
std::string probe(const fs::path& video) {
    const test_cli::Outcome o = [&] {
        const std::string cmd =
            "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
            "stream=codec_name,width,height,nb_read_frames -of csv=p=0 '" +
            video.string() + "' 2>&1";
        test_cli::Outcome out;
        FILE* pipe = popen(cmd.c_str(), "r");
        char buf[256];
        while (pipe && fgets(buf, sizeof buf, pipe)) out.output += buf;
        out.exit_code = pipe ? pclose(pipe) : -1;
        return out;
    }();
    std::string text = o.output;
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    return text;
}

TEST(Video, ARunEndsWithAnH264VideoOfItsFrames) {
    const fs::path dir = temp_dir("video_run");
    const fs::path scene = write_file(dir / "tank.json", kTinyTank);
    // An odd height: the encoder needs even sides, so the video is padded by one row.
    const auto o = run_aquaform("run " + scene.string() + " --frames 3 --resolution 64x47 --out " +
                                (dir / "out").string() + " --video " + (dir / "movies" / "tank.mp4").string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    EXPECT_NE(o.output.find("video: " + (dir / "movies" / "tank.mp4").string() + " (3 frames at 60 frames/s"),
              std::string::npos)
        << o.output;
    EXPECT_EQ(probe(dir / "movies" / "tank.mp4"), "h264,64,48,3");
    EXPECT_TRUE(fs::exists(dir / "out" / "frame_0002.png")) << "the frames stay beside the video";
}

TEST(Video, IsRefusedBeforeAnyWorkWhenItCannotBeMade) {
    const fs::path dir = temp_dir("video_refused");
    const fs::path scene = write_file(dir / "tank.json", kTinyTank);
    const std::string run = "run " + scene.string() + " --frames 2 --resolution 32x32 --out " + (dir / "out").string();

    // No ffmpeg on PATH: the message says how to get it and how to make the video later.
    fs::create_directories(dir / "empty_path");
    const auto missing =
        run_aquaform(run + " --video " + (dir / "a.mp4").string(), "PATH=" + (dir / "empty_path").string());
    EXPECT_EQ(missing.exit_code, 2) << missing.output;
    EXPECT_NE(missing.output.find("apt-get install ffmpeg"), std::string::npos) << missing.output;
    EXPECT_NE(missing.output.find("frame_%04d.png"), std::string::npos) << missing.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "stats.csv")) << "nothing is simulated";

    const auto avi = run_aquaform(run + " --video " + (dir / "a.avi").string());
    EXPECT_EQ(avi.exit_code, 2);
    EXPECT_NE(avi.output.find(".mp4"), std::string::npos) << avi.output;

    const auto no_png = run_aquaform(run + " --no-png --video " + (dir / "a.mp4").string());
    EXPECT_EQ(no_png.exit_code, 2);
    EXPECT_NE(no_png.output.find("drop --no-png"), std::string::npos) << no_png.output;

    write_file(dir / "file", "x");
    const auto blocked = run_aquaform(run + " --video " + (dir / "file" / "a.mp4").string());
    EXPECT_EQ(blocked.exit_code, 2);
    EXPECT_NE(blocked.output.find("--video"), std::string::npos) << blocked.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "stats.csv"));
}

TEST(Video, PlaysAtTheScenesFrameRateRoundedWhereItIsAWholeNumber) {
    EXPECT_EQ(video_fps(0.0166667), 60.0);  // how scene files write 1/60 s
    EXPECT_EQ(video_fps(0.04), 25.0);
    EXPECT_NEAR(video_fps(1.0 / 29.97), 29.97, 1e-9);  // NTSC's rate is not rounded to 30
    const auto command = video_command("/usr/bin/ffmpeg", {"/out", "frame_%04d.png", 7, 60.0}, "v.mp4");
    const auto after = [&](const std::string& flag) {
        for (size_t i = 0; i + 1 < command.size(); ++i)
            if (command[i] == flag) return command[i + 1];
        return std::string("(missing)");
    };
    EXPECT_EQ(after("-framerate"), "60");
    EXPECT_EQ(after("-i"), "/out/frame_%04d.png");
    EXPECT_EQ(after("-frames:v"), "7") << "frames left from an earlier, longer run into the folder stay out";
    EXPECT_EQ(after("-c:v"), "libx264");
    EXPECT_EQ(command.back(), "v.mp4");
}

TEST(Video, OddNamesReachFfmpegAsFilesAndABrokenVideoIsNotReportedMade) {
    // A '%' in the folder is literal, not a pattern; a name starting with '-' is not an option.
    const auto command = video_command("/usr/bin/ffmpeg", {"runs/100%", "frame_%04d.png", 3, 60.0}, "-y.mp4");
    EXPECT_EQ(command[std::find(command.begin(), command.end(), "-i") - command.begin() + 1],
              "runs/100%%/frame_%04d.png");
    EXPECT_EQ(command.back(), "./-y.mp4");
    EXPECT_EQ(video_command("/usr/bin/ffmpeg", {"/abs", "frame_%04d.png", 3, 60.0}, "/abs/-v.mp4").back(),
              "/abs/-v.mp4");

    // A real video through both, then the same file cut short (a disk that filled up before
    // ffmpeg's trailer): the whole one passes, every cut one is refused.
    const fs::path dir = temp_dir("video_odd") / "100% -x";
    fs::create_directories(dir);
    write_file(dir / "tank.json", kTinyTank);
    const fs::path was = fs::current_path();
    fs::current_path(dir);
    const auto o = run_aquaform("run tank.json --out 'out%d' --resolution 64x48 --video -y.mp4");
    ASSERT_EQ(o.exit_code, 0) << o.output;
    EXPECT_EQ(probe(dir / "-y.mp4"), "h264,64,48,3");
    ASSERT_TRUE(mp4_is_whole(dir / "-y.mp4").ok()) << mp4_is_whole(dir / "-y.mp4").error();
    const std::string bytes = test_cli::read_file(dir / "-y.mp4");
    for (size_t cut : {bytes.size() - 1, bytes.size() / 2, size_t(40), size_t(4)}) {
        const fs::path part = write_file(dir / "cut.mp4", bytes.substr(0, cut));
        EXPECT_FALSE(mp4_is_whole(part).ok()) << "cut at " << cut << " of " << bytes.size();
    }
    fs::current_path(was);
    fs::remove_all(dir.parent_path());
}

TEST(Video, CameraFlagTakesAutoOrScene) {
    const fs::path dir = temp_dir("camera_flag");
    const fs::path scene = write_file(dir / "tank.json", kTinyTank);
    const auto bad = run_aquaform("render " + scene.string() + " --camera orbit --out " + (dir / "out").string());
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.output.find("--camera takes auto or scene, got \"orbit\""), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace aquaform
