#include "exports/obstacle_export.h"

#include "core/format_text.h"
#include "geometry/animation.h"
#include "geometry/primitives.h"

namespace aquaform {

namespace {

geometry::Mesh in_up_axis(geometry::Mesh mesh, UpAxis up) {
    if (up == UpAxis::z)
        for (glm::vec3& v : mesh.vertices) v = z_up(v);  // as every export is turned
    return mesh;
}

std::string still_file(const std::string& name) { return "obstacle_" + name + ".obj"; }
// run.json records the printf pattern for other tools; the file itself is named by appending the
// number (a name is the user's text, never a format), and the scene's name rule keeps '%' out.
std::string moving_pattern(const std::string& name) { return "obstacle_" + name + "_%04u.obj"; }
std::string moving_file(const std::string& name, uint32_t frame) {
    return numbered_file("obstacle_" + name, frame, ".obj");
}

}  // namespace

ObstacleExports::ObstacleExports(std::filesystem::path dir, const Scene& scene, UpAxis up)
    : dir_(std::move(dir)), scene_(&scene), up_(up) {}

Result<bool> ObstacleExports::write(uint32_t frame, double time_s) {
    if (frame == 0)
        for (size_t b = 0; b < scene_->static_boxes.size(); ++b)
            if (auto w = geometry::write_obj(dir_ / still_file("static_box_" + std::to_string(b)),
                                             in_up_axis(geometry::make_box(scene_->static_boxes[b]), up_));
                !w)
                return w;
    for (const ObstacleSpec& o : scene_->obstacles) {
        if (!o.moves && frame != 0) continue;
        const std::filesystem::path path = dir_ / (o.moves ? moving_file(o.name, frame) : still_file(o.name));
        if (auto w = geometry::write_obj(path, in_up_axis(o.shape->mesh_at(time_s), up_)); !w) return w;
    }
    return true;
}

nlohmann::json ObstacleExports::description(const Scene& scene) {
    nlohmann::json out = nlohmann::json::array();
    for (size_t b = 0; b < scene.static_boxes.size(); ++b) {
        const std::string name = "static_box_" + std::to_string(b);
        out.push_back({{"name", name}, {"file", still_file(name)}});
    }
    for (const ObstacleSpec& o : scene.obstacles) {
        if (o.moves)
            out.push_back({{"name", o.name}, {"files", moving_pattern(o.name)}, {"moves", true}});
        else
            out.push_back({{"name", o.name}, {"file", still_file(o.name)}});
    }
    return out;
}

}  // namespace aquaform
