#include "render/video.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/output_dir.h"
#include "core/subprocess.h"

namespace aquaform {

namespace fs = std::filesystem;

Result<fs::path> find_ffmpeg() {
    if (auto found = find_on_path("ffmpeg")) return *found;
    return Error{"--video needs ffmpeg, which is not on PATH; install it (Debian: apt-get install ffmpeg, which "
                 "scripts/setup.sh does) or drop --video and make the video later from the PNG frames with: ffmpeg "
                 "-framerate 60 -i OUT/frame_%04d.png -c:v libx264 -pix_fmt yuv420p video.mp4"};
}

Result<bool> check_video_path(const fs::path& video) {
    if (video.extension() != ".mp4")
        return Error{"--video " + video.string() + ": the video is H.264 in an MP4 file; give a name ending in .mp4"};
    if (!video.has_filename() || video.filename() == "." || video.filename() == "..")
        return Error{"--video " + video.string() + ": give a file name ending in .mp4"};
    const fs::path dir = video.has_parent_path() ? video.parent_path() : fs::path(".");
    if (auto ready = prepare_output_dir(dir, "--video"); !ready) return ready;
    std::error_code ec;
    if (fs::is_directory(video, ec)) return Error{"--video " + video.string() + " is a folder; give a file name ending in .mp4"};
    return true;
}

double video_fps(double frame_dt) {
    const double fps = 1.0 / frame_dt;
    return std::abs(fps - std::round(fps)) <= 1e-3 * fps ? std::round(fps) : fps;
}

std::vector<std::string> video_command(const fs::path& ffmpeg, const VideoFrames& frames, const fs::path& video) {
    char fps[32];
    std::snprintf(fps, sizeof fps, "%g", std::clamp(frames.fps, 1.0, 1000.0));
    // yuv420p (what every player decodes) needs even sides: an odd side gets one more row or
    // column of padding. -nostdin: ffmpeg must not read the terminal the user types Ctrl-C in.
    return {ffmpeg.string(), "-hide_banner", "-loglevel", "error", "-nostdin", "-y", "-framerate", fps,
            "-start_number", "0", "-i", (frames.dir / frames.pattern).string(), "-frames:v",
            std::to_string(frames.count), "-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", "20", "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-movflags", "+faststart", video.string()};
}

Result<bool> encode_video(const fs::path& ffmpeg, const VideoFrames& frames, const fs::path& video) {
    if (frames.count == 0) return Error{"no frames were written, so there is no video to make"};
    const ProcessResult run = run_process(video_command(ffmpeg, frames, video));
    if (!run.ok())
        return Error{"ffmpeg could not make " + video.string() + " (exit status " + std::to_string(run.exit_code) +
                     ")" + (run.errors.empty() ? std::string() : ": " + run.errors) + "; the PNG frames are in " +
                     frames.dir.string()};
    return true;
}

}  // namespace aquaform
