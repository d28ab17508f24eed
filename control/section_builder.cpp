#include "control/section_builder.h"

#include <algorithm>
#include <cmath>

#include "control/control_force.h"
#include "core/json_fields.h"

namespace aquaform::control {

using json_fields::fmt;

ControlMesh bind_control_mesh(std::string name, std::filesystem::path file, const geometry::Mesh* rest,
                              const geometry::MeshReport& report, MeshSpec spec, const std::string& path) {
    ControlMesh mesh;
    mesh.name = std::move(name);
    mesh.file = std::move(file);
    mesh.report = report;
    mesh.animation = std::move(spec.animation);
    if (spec.method) mesh.method = *spec.method;
    if (mesh.animation.deforms()) {
        if (spec.method && *spec.method != PlacementMethod::raster)
            json_fields::fail(path + ".method is \"" + method_name(*spec.method) +
                              "\" but the mesh deforms, so its points are placed again every frame by \"raster\" (the "
                              "only method fast enough); write \"method\": \"raster\" or leave it out");
        mesh.method = PlacementMethod::raster;
    }
    const bool sequence = std::holds_alternative<geometry::SequenceAnimation>(mesh.animation.kind());
    if (!rest && !sequence)
        json_fields::fail(path + " has no mesh: give a file (\"file\": \"../meshes/sphere.obj\") or an OBJ sequence");
    mesh.animation.bind(rest ? *rest : geometry::Mesh{}, spec.placement);
    return mesh;
}

SectionBuilder::SectionBuilder(const Scene& scene)
    : particle_spacing_(scene.particle_spacing),
      kernel_radius_(scene.solver.kernel_radius_factor * scene.particle_spacing) {
    section_.spacing = scene.particle_spacing;
    section_.damping = kDefaultDamping;
}

void SectionBuilder::fail(std::string message) {
    if (error_.empty()) error_ = std::move(message);
}

SectionBuilder& SectionBuilder::spacing(float metres) {
    if (!(metres >= 0.25f * particle_spacing_ && metres <= 8.0f * particle_spacing_))
        fail("control.spacing is " + fmt(metres) + "; use a length from 1/4 to 8 particle spacings (" +
             fmt(0.25 * particle_spacing_) + " to " + fmt(8.0 * particle_spacing_) + " m)");
    section_.spacing = metres;
    return *this;
}

SectionBuilder& SectionBuilder::pressure(float pascal) {
    if (!(pascal > 0.0f && std::isfinite(pascal)))
        fail("control.pressure is " + fmt(pascal) + "; use a positive number");
    section_.overrides.pressure = pascal;
    return *this;
}

SectionBuilder& SectionBuilder::support_radius(float metres) {
    if (!(metres >= kernel_radius_ && metres <= 8.0f * kernel_radius_))
        fail("control.support_radius is " + fmt(metres) + "; use a length from the kernel radius h to 8 h (" +
             fmt(kernel_radius_) + " to " + fmt(8.0 * kernel_radius_) + " m)");
    section_.overrides.support = metres;
    return *this;
}

SectionBuilder& SectionBuilder::fixed_substeps(bool fixed) {
    section_.overrides.fixed_substeps = fixed;
    return *this;
}

SectionBuilder& SectionBuilder::damping(float per_second) {
    if (!(per_second >= 0.0f && per_second <= 100.0f))
        fail("control.damping is " + fmt(per_second) + "; use a rate from 0 to 100 per second");
    section_.damping = per_second;
    return *this;
}

SectionBuilder& SectionBuilder::mesh(const std::string& name, const std::filesystem::path& file, MeshSpec spec) {
    const std::string path = "control.meshes." + name;
    auto loaded = geometry::load_obj(file);
    if (!loaded) {
        fail(path + ".file: " + loaded.error());
        return *this;
    }
    try {
        section_.meshes.push_back(
            bind_control_mesh(name, file, &loaded.value().mesh, loaded.value().report, std::move(spec), path));
    } catch (const json_fields::Invalid& e) {
        fail(e.message);
    }
    return *this;
}

SectionBuilder& SectionBuilder::mesh(const std::string& name, const geometry::Mesh& rest, MeshSpec spec) {
    const std::string path = "control.meshes." + name;
    try {
        section_.meshes.push_back(
            bind_control_mesh(name, {}, &rest, geometry::check_mesh(rest), std::move(spec), path));
    } catch (const json_fields::Invalid& e) {
        fail(e.message);
    }
    return *this;
}

SectionBuilder& SectionBuilder::event(TimelineAction action, const std::string& mesh, double t, uint32_t tags,
                                      double duration) {
    const std::string where = "control.timeline[" + std::to_string(events_.size()) + "]";
    TimelineEvent ev{t, action, -1, tags, duration};
    if (!(t >= 0.0)) fail(where + ".t is " + fmt(t) + "; use a time in seconds >= 0");
    if (!events_.empty() && t < events_.back().t)
        fail(where + ".t is " + fmt(t) + ", earlier than the event before it (t = " + fmt(events_.back().t) +
             "); list the events in time order");
    if (!(duration >= 0.0)) fail(where + ".duration is " + fmt(duration) + "; use a number of seconds >= 0");
    if (!mesh.empty()) {
        const auto it = std::find_if(section_.meshes.begin(), section_.meshes.end(),
                                     [&](const ControlMesh& m) { return m.name == mesh; });
        if (it == section_.meshes.end()) {
            std::vector<std::string> mesh_names;
            for (const ControlMesh& m : section_.meshes) mesh_names.push_back(m.name);
            const std::string names = json_fields::quoted_list(mesh_names);
            fail(where + ".mesh is \"" + mesh + "\", which is not a mesh of the section (" +
                 (names.empty() ? "none defined" : names) + "); add it with mesh() before the event or fix the name");
        } else {
            ev.mesh = int(it - section_.meshes.begin());
        }
    }
    events_.push_back(ev);
    return *this;
}

SectionBuilder& SectionBuilder::attach(const std::string& mesh, double t, uint32_t tags) {
    return event(TimelineAction::attach, mesh, t, tags, 0.0);
}
SectionBuilder& SectionBuilder::union_with(const std::string& mesh, double t, uint32_t tags) {
    return event(TimelineAction::union_with, mesh, t, tags, 0.0);
}
SectionBuilder& SectionBuilder::morph(const std::string& mesh, double t, double duration, uint32_t tags) {
    return event(TimelineAction::morph, mesh, t, tags, duration);
}
SectionBuilder& SectionBuilder::hold(double t) { return event(TimelineAction::hold, "", t, ~0u, 0.0); }
SectionBuilder& SectionBuilder::release(double t, const std::string& mesh) {
    return event(TimelineAction::release, mesh, t, ~0u, 0.0);
}

Result<ControlSection> SectionBuilder::build() const {
    if (!error_.empty()) return Error{error_};
    if (section_.meshes.empty()) return Error{"control.meshes is empty; add a mesh with mesh(\"ball\", file)"};
    for (size_t i = 0; i < section_.meshes.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (section_.meshes[i].name == section_.meshes[j].name)
                return Error{"control.meshes has two meshes named \"" + section_.meshes[i].name +
                             "\"; give each its own name"};
    ControlSection section = section_;
    section.timeline = Timeline(events_);
    return section;
}

}  // namespace aquaform::control
