// One solid obstacle of a scene as loaded (sim/obstacles.h reads them): its mesh, bound to its
// placement and motion, and what loading found out about it.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

namespace aquaform {

namespace geometry {
class MeshAnimation;
}

/// Where an obstacle stands at t = 0, as a robust inside test (what fluid starts inside it).
class StartSolid;

struct ObstacleSpec {
    std::string name;
    std::filesystem::path file;  ///< its OBJ (empty for a sequence: the animation names the files)
    /// The mesh bound to its placement and motion; shared, so copies of a scene stay cheap.
    std::shared_ptr<const geometry::MeshAnimation> shape;
    std::shared_ptr<const StartSolid> start;
    bool moves = false;    ///< rigid or deforming motion
    bool deforms = false;  ///< an OBJ sequence or a skeleton: its shape changes, not only its pose
    /// What the mesh check found and tolerates (holes, flipped faces turned back, several parts),
    /// one problem per line; empty for a clean mesh.
    std::string mesh_notes;
    double max_speed = 0.0;  ///< the fastest any point of it moves [m/s] (sampled over its motion)
};

}  // namespace aquaform
