// Videos of a run's frames: H.264 in MP4 through Debian's ffmpeg (a separate program, so that
// aquaform links no codec). The PNG frames stay; the video is made from them at the end.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"

namespace aquaform {

/// ffmpeg on PATH, or an error that says how to install it and how to make the video later.
Result<std::filesystem::path> find_ffmpeg();

/// Checks a --video path before any work: it ends in .mp4 and its folder exists or can be made.
Result<bool> check_video_path(const std::filesystem::path& video);

struct VideoFrames {
    std::filesystem::path dir;               ///< where the frames are
    const char* pattern = "frame_%04d.png";  ///< their names (printf style, numbered from 0)
    uint32_t count = 0;                      ///< frames 0..count-1
    double fps = 60.0;                       ///< frames per second of simulated time
};

/// Frames per second for frames `frame_dt` seconds apart, a whole number when within 0.1 % of
/// one (scene files write 1/60 s as 0.0166667, which should play at 60, not 59.9999).
double video_fps(double frame_dt);

/// The ffmpeg command line that makes `video` from `frames` (also printed for users to rerun).
std::vector<std::string> video_command(const std::filesystem::path& ffmpeg, const VideoFrames& frames,
                                       const std::filesystem::path& video);
/// Whether `video` is a whole MP4: its top-level boxes tile the file and include the header, the
/// index and the frames (a file cut by a full disk fails, naming what is missing).
Result<bool> mp4_is_whole(const std::filesystem::path& video);
/// Runs it and checks the file; the error carries ffmpeg's own message.
Result<bool> encode_video(const std::filesystem::path& ffmpeg, const VideoFrames& frames,
                          const std::filesystem::path& video);

}  // namespace aquaform
