#include "pictures/video.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "core/file_write.h"
#include "core/output_dir.h"
#include "core/subprocess.h"

namespace aquaform {

namespace fs = std::filesystem;

Result<fs::path> find_ffmpeg() {
    if (auto found = find_on_path("ffmpeg")) return *found;
    return Error{
        "--video needs ffmpeg, which is not on PATH; install it (Debian: apt-get install ffmpeg, which "
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
    if (fs::is_directory(video, ec))
        return Error{"--video " + video.string() + " is a folder; give a file name ending in .mp4"};
    if (fs::is_symlink(fs::symlink_status(video, ec))) return link_refused(video);
    return true;
}

double video_fps(double frame_dt) {
    const double fps = 1.0 / frame_dt;
    return std::abs(fps - std::round(fps)) <= 1e-3 * fps ? std::round(fps) : fps;
}

namespace {

/// A path as an argument ffmpeg reads as a file: a relative one that starts with '-' would be
/// read as an option ("--video -y.mp4"), so it goes as ./-y.mp4.
std::string file_argument(const fs::path& path) {
    const std::string text = path.string();
    return !path.is_absolute() && !text.empty() && text[0] == '-' ? "./" + text : text;
}

/// The image2 demuxer reads printf-style patterns in the whole path: a '%' of the folder
/// ("--out runs/100%") is written as "%%".
std::string literal_pattern_part(const std::string& text) {
    std::string out;
    for (char c : text) out += c == '%' ? std::string("%%") : std::string(1, c);
    return out;
}

}  // namespace

std::vector<std::string> video_command(const fs::path& ffmpeg, const VideoFrames& frames, const fs::path& video) {
    char fps[32];
    std::snprintf(fps, sizeof fps, "%g", std::clamp(frames.fps, 1.0, 1000.0));
    const std::string input = literal_pattern_part(file_argument(frames.dir)) + "/" + frames.pattern;
    // yuv420p (what every player decodes) needs even sides: an odd side gets one more row or
    // column of padding. -nostdin: ffmpeg must not read the terminal the user types Ctrl-C in.
    return {ffmpeg.string(),
            "-hide_banner",
            "-loglevel",
            "error",
            "-nostdin",
            "-y",
            "-framerate",
            fps,
            "-start_number",
            "0",
            "-i",
            input,
            "-frames:v",
            std::to_string(frames.count),
            "-c:v",
            "libx264",
            "-pix_fmt",
            "yuv420p",
            "-crf",
            "20",
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
            "-movflags",
            "+faststart",
            file_argument(video)};
}

Result<bool> mp4_is_whole(const fs::path& video) {
    std::ifstream in(video, std::ios::binary);
    if (!in) return Error{video.string() + " was not written"};
    in.seekg(0, std::ios::end);
    const uint64_t size = uint64_t(std::max<std::streamoff>(in.tellg(), 0));
    // The top-level boxes must tile the file exactly, and hold the header (ftyp), the index
    // (moov, written last: a disk that fills up loses it) and the frames (mdat).
    bool ftyp = false, moov = false, mdat = false;
    for (uint64_t at = 0; at < size;) {
        unsigned char head[16];
        in.seekg(std::streamoff(at));
        if (size - at < 8 || !in.read(reinterpret_cast<char*>(head), 8))
            return Error{video.string() + " ends inside a box header at byte " + std::to_string(at)};
        uint64_t box = (uint64_t(head[0]) << 24) | (uint64_t(head[1]) << 16) | (uint64_t(head[2]) << 8) | head[3];
        const std::string type(reinterpret_cast<const char*>(head + 4), 4);
        if (box == 1) {  // a 64-bit size follows
            if (size - at < 16 || !in.read(reinterpret_cast<char*>(head + 8), 8))
                return Error{video.string() + " ends inside a box header at byte " + std::to_string(at)};
            box = 0;
            for (int k = 8; k < 16; ++k) box = (box << 8) | head[k];
        } else if (box == 0) {
            box = size - at;  // to the end of the file
        }
        if (box < 8 || box > size - at)
            return Error{video.string() + ": its \"" + type + "\" box at byte " + std::to_string(at) +
                         " runs past the end"};
        ftyp = ftyp || type == "ftyp";
        moov = moov || type == "moov";
        mdat = mdat || type == "mdat";
        at += box;
    }
    if (!ftyp || !moov || !mdat)
        return Error{video.string() + " lacks its " +
                     std::string(!ftyp   ? "header (ftyp)"
                                 : !moov ? "index (moov)"
                                         : "frames (mdat)")};
    return true;
}

Result<bool> encode_video(const fs::path& ffmpeg, const VideoFrames& frames, const fs::path& video) {
    if (frames.count == 0) return Error{"no frames were written, so there is no video to make"};
    // Made beside the video and renamed over it once checked: a failed encode neither leaves a
    // cut file nor removes an earlier video of that name.
    const fs::path staged =
        video.parent_path() / ("." + video.stem().string() + ".partial" + std::to_string(getpid()) + ".mp4");
    std::error_code ec;
    fs::remove(staged, ec);  // ffmpeg -y would write through a link left there
    const ProcessResult run = run_process(video_command(ffmpeg, frames, staged));
    if (!run.ok()) {
        fs::remove(staged, ec);
        return Error{"ffmpeg could not make " + video.string() + " (exit status " + std::to_string(run.exit_code) +
                     ")" + (run.errors.empty() ? std::string() : ": " + run.errors) + "; the PNG frames are in " +
                     frames.dir.string()};
    }
    // ffmpeg exits 0 when it cannot write its trailer (a full disk): the file is checked, and a
    // broken one removed rather than reported made.
    if (auto whole = mp4_is_whole(staged); !whole) {
        fs::remove(staged, ec);
        return Error{"ffmpeg exited 0 but the video " + video.string() + " is not whole (" + whole.error() +
                     "; is the disk full?), so it was removed; the PNG frames are in " + frames.dir.string()};
    }
    fs::rename(staged, video, ec);
    if (ec) {
        fs::remove(staged, ec);
        return Error{"cannot put the video at " + video.string() + ": " + ec.message()};
    }
    return true;
}

}  // namespace aquaform
