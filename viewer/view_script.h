// Scripted viewer sessions (`aquaform view SCENE --script FILE`): UI actions at given viewer
// frames, for tests and recordings. A script is JSON:
//   {"actions": [{"frame": 0, "do": "play"},
//                {"frame": 5, "do": "method", "value": "sbuffer"},
//                {"frame": 6, "do": "screenshot", "file": "sbuffer.png"},
//                {"frame": 9, "do": "quit"}]}
// Actions: play, pause, step (one simulation frame), reset, method (any method of the method
// menu), view (the SPH renderer's debug view: image, steps, classification, tiles, depth_all,
// depth_agg), iterations / substeps (integer value; the solver restarts from the current state),
// screenshot (the last frame drawn, before this frame's actions, as PNG; relative paths go to
// --record DIR or the working directory), attach (an OBJ "file", relative to the script, becomes
// the shape the fluid fills), union (adds a mesh to the shapes), morph (the shapes hand over to a
// mesh in one second), release (the shapes let go), obstacle (an OBJ "file" dropped into the
// flow as a still solid on the floor at the tank's centre; the fluid inside it is taken out),
// remove_obstacles (those dropped go again), resize (the window to "value": "640x480"), whitewater
// ("value": "on" or "off": the scene's whitewater drawn or not; it is made either way), nozzle
// (one of the scene's emitters, "name": moved to "position", aimed along "direction", or shut and
// opened with "open": false / true; from the next step on), quit.
// Frames count from 0 at the first
// frame drawn; actions of one frame run in the order written.
// Everything an action needs is checked before the first frame: names and values when the script
// is read, meshes loaded and checked as their action uses them (load_view_script; with the scene,
// check_script_actions: the obstacle's own checks, the solver's solids), screenshot folders
// (check_script_outputs). An action that still fails at its frame makes the command exit 1.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "sim/scene.h"

namespace aquaform::viewer {

struct ViewAction {
    uint32_t frame = 0;
    std::string
        what;  ///< play, pause, step, reset, method, iterations, substeps, screenshot, attach, union, morph, release, obstacle, remove_obstacles, resize, whitewater, quit
    std::string value;  ///< method name, integer, file, or a nozzle's name
    /// nozzle: what it changes (at least one).
    std::optional<glm::vec3> position, direction;
    std::optional<bool> open;
    uint32_t line = 0;   ///< where the script writes it (1-based; 0: not from a file)
    std::string origin;  ///< the script's file (empty: not from a script)

    /// "s.json: line 4: the obstacle at frame 3", for messages about this action.
    std::string where() const;
};

/// Reads a script; errors name the file, the action's index and the fix. Actions come sorted by
/// frame. The meshes of attach, union, morph and obstacle (relative to the script) are loaded and
/// checked as the mesh loader does for every use (a file, an OBJ, a closed solid with a volume).
Result<std::vector<ViewAction>> load_view_script(const std::filesystem::path& path);
Result<std::vector<ViewAction>> parse_view_script(const std::string& text, const std::string& origin);

/// Checks, before the viewer starts, that every screenshot of a script can be written: a
/// relative file goes under `screenshot_dir`; its folder must exist and take a file, or the first
/// of its missing folders must be one that can be made and take a file (both tried, and removed
/// again), with names the system allows; the file must be neither a folder nor a symbolic link.
/// The error names `origin` (the script), the action's line and the fix.
Result<bool> check_script_outputs(const std::vector<ViewAction>& actions, const std::filesystem::path& screenshot_dir,
                                  const std::string& origin);

/// Checks, before the viewer starts, what the script's mesh actions do to `scene` (the session's,
/// whose control meshes are `shapes`): each obstacle as the viewer drops it (obstacle_box, the
/// obstacle reader's checks) and within the solver's solids (remove_obstacles frees those
/// dropped), each shape placed as attach, union or morph place it, over the shapes the actions
/// before it leave, each nozzle action on an emitter of the scene and where the scene's emitters
/// may stand. The error names the action's line and the fix.
Result<bool> check_script_actions(const std::vector<ViewAction>& actions, const Scene& scene,
                                  const std::vector<std::filesystem::path>& shapes);

}  // namespace aquaform::viewer
