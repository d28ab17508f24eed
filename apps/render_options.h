// Render flags shared by every command that draws frames (run, render, view, bench render): the
// method (any of render/registry.h), its switches and parameters, and the resolution.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "apps/flags.h"
#include "render/registry.h"
#include "render/renderer.h"
#include "render/surface_settings.h"
#include "sim/scene.h"

namespace aquaform::cli {

/// Flags with a value and switches that render_settings_from() reads.
const std::vector<std::string>& render_value_flags();
const std::vector<std::string>& render_switches();
/// Usage lines describing them.
const char* render_flags_usage();

/// The method of --method (default adaptive; any registered method, render/registry.h) with its
/// settings from the flags; nullopt with `error` naming the flag and the accepted values.
std::optional<MethodSettings> render_method_from(const Args& args, std::string* error);

/// The commands that make pictures to be looked at (run, view) draw spray as white water unless
/// --spray says otherwise (SurfaceSettings::spray_whiteness: off where renders are measured).
void draw_spray_unless_told(const Args& args, MethodSettings& settings);
/// Likewise for commands that draw with the SPH surface renderer only (adaptive, uniform, reference).
std::optional<SurfaceSettings> render_settings_from(const Args& args, std::string* error);

/// --camera auto|scene of run and render: `auto` drops the scene's own camera, so that the view
/// frames the tank and the fluid (framed_region in sim/scene.h); `scene` (the default) keeps it.
/// False with `error` naming the flag and its values.
bool apply_camera_flag(const Args& args, Scene& scene, std::string* error);

/// The picture each command draws without --resolution (the usage quotes them):
/// - to be looked at (run's frames, view's window, control place's points): 16:9 like a video or
///   a screen, and small enough that the software device draws one in about a second;
/// - to be measured (render, bench render): square, at the benchmark's size, so that render.json
///   compares with bench_render.json;
/// - bench frame: the display its targets are set for (study::kTargetDisplay, 1920x1080).
inline constexpr PictureSize kViewingPicture{640, 360};
inline constexpr PictureSize kMeasuredPicture{512, 512};

/// FlagSpec of a command: its own flags plus the render flags.
FlagSpec with_render_flags(FlagSpec spec);

}  // namespace aquaform::cli
