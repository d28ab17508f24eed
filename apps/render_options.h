// Render flags shared by every command that draws ray-marched frames (run, render, bench render):
// the method, its switches and parameters, and the resolution.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "apps/cli.h"
#include "render/surface_settings.h"

namespace aquaform::cli {

/// Flags with a value and switches that render_settings_from() reads.
const std::vector<std::string>& render_value_flags();
const std::vector<std::string>& render_switches();
/// Usage lines describing them.
const char* render_flags_usage();

/// Settings from the flags; nullopt with `error` naming the flag and the accepted values.
std::optional<SurfaceSettings> render_settings_from(const Args& args, std::string* error);

/// "640x360" (16..8192 per side).
bool parse_resolution(const std::string& text, uint32_t* width, uint32_t* height);

/// FlagSpec of a command: its own flags plus the render flags.
FlagSpec with_render_flags(FlagSpec spec);

}  // namespace aquaform::cli
