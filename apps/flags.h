// The flags of the `aquaform` commands: parsing `--flag value` / `--switch` and the checks of the
// values every command shares (counts, frame numbers, lists, --particles, --resolution).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "render/picture_size.h"

namespace aquaform {
struct Scene;
}

namespace aquaform::cli {

/// Parsed `--flag value` / `--switch` options and positional arguments of one subcommand.
struct Args {
    std::vector<std::string> positional;
    std::map<std::string, std::string> values;  ///< flags that take a value
    std::map<std::string, bool> switches;       ///< flags without a value

    bool has(const std::string& flag) const { return values.count(flag) || switches.count(flag); }
    std::string value(const std::string& flag, const std::string& fallback = "") const;
};

/// What a subcommand accepts; anything else is an error naming the flag.
struct FlagSpec {
    std::vector<std::string> with_value;
    std::vector<std::string> switches;
};

/// Parses argv[first..]; on error returns nullopt and fills `error` (naming the flag and the fix).
std::optional<Args> parse_args(const std::vector<std::string>& argv, const FlagSpec& spec, const std::string& command,
                               std::string* error);

/// A whole number from 1 to `max` (the same limit as the scene file's key, where there is one);
/// nullopt with `error` naming the flag, the range and the text otherwise.
std::optional<long> parse_positive(const std::string& flag, const std::string& text, std::string* error, long max);
/// A frame number from 0 to kMaxFrames - 1 (`--frame K`).
std::optional<uint32_t> parse_frame_index(const std::string& flag, const std::string& text, std::string* error);
/// "a,b,c" for a list flag; nullopt with `error` naming the flag and showing `example` when the
/// text or an item is empty.
std::optional<std::vector<std::string>> parse_list(const std::string& flag, const std::string& text,
                                                   const std::string& example, std::string* error);
/// "a,b,c" of positive finite numbers; nullopt with `error` naming the flag, the item and
/// `example` otherwise.
std::optional<std::vector<double>> parse_positive_numbers(const std::string& flag, const std::string& text,
                                                          const std::string& example, std::string* error);
/// `--sizes a,b,c`: particle counts from 1 to kMaxSceneParticles (bench sim, bench frame); empty
/// with `error` naming the flag, the item and the fix otherwise.
std::vector<uint32_t> parse_sizes(const std::string& text, std::string* error);
/// Frames of a run or a scene file's "frames" (sim/scene.cpp), and solver iterations.
constexpr long kMaxFrames = 1000000;
constexpr long kMaxIterations = 100;
/// Repeats and counts of benchmark steps.
constexpr long kMaxRepeats = 1000;

/// `--particles N`, the one flag that sizes a scene on run, render, bench render, study and view:
/// nullopt without the flag (error left empty) or when N is not a count from kMinSceneParticles
/// to kMaxSceneParticles (error set, naming the flag and the range).
std::optional<uint64_t> particles_flag(const Args& args, std::string* error);
/// Re-derives `scene`'s spacing for `--particles N` when given (with_particle_count, sim/scene.h);
/// false with `error` set when N is bad or the scene cannot be sized so.
bool scale_to_particles_flag(const Args& args, Scene& scene, std::string* error);

/// `--whitewater on|off` (run, render, view): spray, foam and bubbles made from the flow
/// (sim/whitewater.h), on with the scene's settings or the defaults, or off whatever the scene
/// says; without the flag the scene's own "whitewater" key decides. False with `error` set for
/// any other value.
bool apply_whitewater_flag(const Args& args, Scene& scene, std::string* error);

/// `--resolution WxH`: the size asked for, or `fallback` (the command's default, named in the
/// usage) without the flag; nullopt with `error` naming the flag, an example and the limits.
std::optional<PictureSize> resolution_flag(const Args& args, PictureSize fallback, std::string* error,
                                           const std::string& flag = "--resolution");

}  // namespace aquaform::cli
