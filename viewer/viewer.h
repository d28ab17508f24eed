// The interactive viewer: a GLFW window (viewer/view_window.h) presents the fluid's pictures
// straight from the GPU, while the simulation and the renderers run on a worker thread
// (viewer/view_worker.h), so the window keeps drawing its panels while a frame of the fluid is
// made. Dear ImGui panels play, pause, step and reset the simulation, switch the surface method
// and change solver settings, and chart the GPU time per pass; an OBJ dropped on the window
// becomes the shape the fluid fills (Release lets it go), and the active shapes are drawn as
// wireframes. Dragging with the left button pushes the fluid; the right button orbits, the
// middle pans and the wheel zooms the camera; F switches to a fly camera (right button looks
// around, W/A/S/D/Q/E move). Keys: space play/pause, N one step, R reset, P screenshot, Esc quit.
// A script (viewer/view_script.h) plays UI actions at given frames; a record directory gets every
// frame drawn; both step the window with the fluid (one picture per window frame) so that frame
// numbers mean the same every run. `aquaform view` (apps/cmd_view.cpp) reads the flags.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "render/surface_settings.h"
#include "session/simulation_session.h"
#include "viewer/view_script.h"
#include "viewer/view_worker.h"

namespace aquaform::gpu {
class Context;
}  // namespace aquaform::gpu

namespace aquaform::viewer {

class ViewWindow;

struct ViewerOptions {
    SurfaceSettings surface;  ///< the panel edits the SPH surface methods' settings
    std::string method = "adaptive";
    std::filesystem::path watch_shaders;  ///< a shader tree to reload edited shaders from, or empty
    /// Every window frame waits for a picture of the fluid made after that frame's actions
    /// (scripts, recordings); otherwise the window never waits for the worker.
    bool lockstep = false;
    std::vector<ViewAction> script;
    std::filesystem::path record_dir;            ///< every frame drawn as PNG there; empty: none
    std::filesystem::path screenshot_dir = ".";  ///< where P and relative script screenshots go
    float picture_scale = 1.0f;                  ///< the picture's size against the window's
    uint32_t max_frames = 0;                     ///< window frames until it closes; 0: until closed
};

/// How a viewing session went, for the command to print.
struct ViewSummary {
    uint32_t window_frames = 0;
    double seconds = 0.0;
    double longest_frame_ms = 0.0;   ///< the slowest window frame: what the user waits for at worst
    ViewReport report;               ///< the worker's last report (pictures, particles, a fatal error)
    uint32_t width = 0, height = 0;  ///< the last picture's size
    std::string method;
    std::vector<std::string> errors;  ///< script actions refused, screenshots not written
};

/// Runs the viewer in `window` (attached to `ctx`) until it closes, the script quits, or
/// max_frames window frames are drawn.
ViewSummary run_viewer(gpu::Context& ctx, ViewWindow& window, session::SessionPlan plan, const ViewerOptions& options);

/// run_viewer with its lines printed: what is viewed on which device before, the window's and
/// the fluid's frame rates after, and every error, fatal error and blow-up (to stderr). True
/// when the session ran clean.
bool run_viewer_printed(gpu::Context& ctx, ViewWindow& window, session::SessionPlan plan, const ViewerOptions& options,
                        const std::string& scene_name);

}  // namespace aquaform::viewer
