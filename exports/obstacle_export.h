// The solids of a run as files beside it, for other tools: each obstacle's mesh as it stands at
// each frame (obstacle_<name>_NNNN.obj for a moving one, numbered by frame; obstacle_<name>.obj
// once for one that stands still) and each static box as obstacle_static_box_<i>.obj, in the
// run's up axis (exports/frame_exports.h). run.json lists them ("obstacles") for
// scripts/blender_scene.py.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "exports/frame_exports.h"
#include "sim/scene.h"

namespace aquaform {

class ObstacleExports {
public:
    ObstacleExports(std::filesystem::path dir, const Scene& scene, UpAxis up);
    /// Writes what frame `frame` (at `time_s`) needs: every solid at frame 0, the moving ones at
    /// every frame. The error names the file and the fix.
    Result<bool> write(uint32_t frame, double time_s);
    /// run.json's "obstacles": [{"name", "file"} or {"name", "files" (a printf pattern of the frame),
    /// "moves": true}].
    static nlohmann::json description(const Scene& scene);

private:
    std::filesystem::path dir_;
    const Scene* scene_;
    UpAxis up_;
};

}  // namespace aquaform
