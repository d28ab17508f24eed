#include "control/control_scene.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "control/control_force.h"
#include "control/section_builder.h"
#include "core/json_fields.h"

namespace aquaform::control {

using namespace json_fields;

namespace {

constexpr std::string_view kSectionKeys[] = {"spacing", "pressure", "support_radius", "fixed_substeps",
                                             "damping", "meshes",   "timeline"};
constexpr std::string_view kMeshKeys[] = {"file", "method", "placement", "animation"};

PlacementMethod read_method(const json& v, const std::string& path) {
    for (auto m : {PlacementMethod::vertices, PlacementMethod::inside, PlacementMethod::raster})
        if (v.is_string() && v.get<std::string>() == method_name(m)) return m;
    fail(path + " is " + written(v) + "; use \"vertices\", \"inside\" or \"raster\"");
}

ControlMesh read_mesh(const json& v, const std::string& name, const std::string& path,
                      const std::filesystem::path& base_dir) {
    if (!v.is_object())
        fail(path + " must be an object such as {\"file\": \"../meshes/sphere.obj\"}, got " + written(v));
    check_keys(v, "in " + path, kMeshKeys);
    MeshSpec spec;
    if (v.contains("animation"))
        spec.animation = geometry::parse_animation(v["animation"], path + ".animation", base_dir);
    const bool sequence = std::holds_alternative<geometry::SequenceAnimation>(spec.animation.kind());
    if (!sequence) require(v, "file", "in " + path, "\"file\": \"../meshes/sphere.obj\"");
    if (v.contains("method")) spec.method = read_method(v["method"], path + ".method");
    if (v.contains("placement")) spec.placement = geometry::parse_placement(v["placement"], path + ".placement");
    std::filesystem::path file;
    std::optional<geometry::LoadedMesh> loaded;
    if (v.contains("file")) {
        if (!v["file"].is_string()) fail(path + ".file must be a path string, got " + written(v["file"]));
        file = base_dir / v["file"].get<std::string>();
        auto result = geometry::load_obj(file);
        if (!result) fail(path + ".file: " + result.error());
        loaded = std::move(result.value());
    }
    return bind_control_mesh(name, file, loaded ? &loaded->mesh : nullptr,
                             loaded ? loaded->report : geometry::MeshReport{}, std::move(spec), path);
}

/// A shape placed outside the domain holds no fluid, and one reaching out of it can never fill:
/// refused at load time rather than found as an IoU of 0 after the run. Checked on the rest pose
/// (animations may move a shape out on purpose, e.g. to lift it away); `slack` is one spacing.
void check_inside_domain(const ControlMesh& mesh, const Box& domain, float slack, const std::string& path) {
    const Box b = mesh.animation.placed_rest().bounds();
    for (int a = 0; a < 3; ++a)
        if (b.min[a] < domain.min[a] - slack || b.max[a] > domain.max[a] + slack)
            fail(path + " is placed at " + fmt(b) + ", which reaches outside the domain " + fmt(domain) + " on " +
                 "xyz"[a] + "; fluid cannot go there, so the shape could never fill: move or scale it inside (" + path +
                 ".placement: fit_into within the domain, or position and scale)");
}

ControlSection read_section(const json& j, const Scene& scene, const std::filesystem::path& base_dir) {
    if (!j.is_object()) fail("control must be an object {\"meshes\": {...}, \"timeline\": [...]}, got " + written(j));
    check_keys(j, "in control", kSectionKeys);
    require(j, "meshes", "in control", "\"meshes\": {\"ball\": {\"file\": \"../meshes/sphere.obj\"}}");
    require(j, "timeline", "in control", "\"timeline\": [{\"t\": 0, \"do\": \"attach\", \"mesh\": \"ball\"}]");
    ControlSection s;
    s.spacing = scene.particle_spacing;
    if (j.contains("spacing"))
        s.spacing = read_number(j["spacing"], "control.spacing",
                                {0.25 * scene.particle_spacing, 8.0 * scene.particle_spacing, false, false,
                                 "a length from 1/4 to 8 particle spacings (control points per fluid particle)"});
    const Range positive{0.0, HUGE_VAL, true, false, "a positive number"};
    if (j.contains("pressure")) s.overrides.pressure = read_number(j["pressure"], "control.pressure", positive);
    const float h = scene.solver.kernel_radius_factor * scene.particle_spacing;
    if (j.contains("support_radius"))
        s.overrides.support = read_number(j["support_radius"], "control.support_radius",
                                          {h, 8.0 * h, false, false, "a length from the kernel radius h to 8 h"});
    if (j.contains("fixed_substeps")) {
        if (!j["fixed_substeps"].is_boolean())
            fail("control.fixed_substeps must be true or false, got " + written(j["fixed_substeps"]));
        s.overrides.fixed_substeps = j["fixed_substeps"].get<bool>();
    }
    s.damping = kDefaultDamping;
    if (j.contains("damping"))
        s.damping =
            read_number(j["damping"], "control.damping", {0.0, 100.0, false, false, "a rate from 0 to 100 per second"});
    const json& meshes = j["meshes"];
    if (!meshes.is_object() || meshes.empty())
        fail(
            "control.meshes must be a non-empty object of named meshes, e.g. {\"ball\": {\"file\": "
            "\"../meshes/sphere.obj\"}}, got " +
            written(meshes));
    std::vector<std::string> names;
    for (const auto& [name, entry] : meshes.items()) {
        names.push_back(name);
        s.meshes.push_back(read_mesh(entry, name, "control.meshes." + name, base_dir));
        check_inside_domain(s.meshes.back(), scene.domain, scene.particle_spacing, "control.meshes." + name);
    }
    FluidTags tags{scene.fluid_blocks.size(), {}};
    for (const EmitterSpec& e : scene.emitters) tags.emitters.push_back(e.name);
    s.timeline = Timeline::parse(j["timeline"], "control.timeline", names, tags);
    return s;
}

}  // namespace

Result<ControlSection> load_control_section(const Scene& scene) {
    const std::string origin = scene.path.empty() ? scene.name : scene.path.string();
    if (!scene.control_json) return Error{origin + ": the scene has no \"control\" section"};
    try {
        return read_section(json::parse(*scene.control_json), scene, scene.path.parent_path());
    } catch (const Invalid& e) {
        return Error{origin + ": " + e.message};
    } catch (const std::exception& e) {
        return Error{origin + ": control: " + std::string(e.what())};
    }
}

}  // namespace aquaform::control
