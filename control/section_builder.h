// A control section built in code: what a scene file's "control" section says (control_section.h),
// for callers that make shapes at run time (the viewer's Shape panel, benchmarks, tests) and
// should not write JSON to parse it again. The JSON loader binds its meshes through the same
// bind_control_mesh(), so both produce the same section (tests/test_session.cpp).
//
//   auto section = SectionBuilder(scene)
//                      .mesh("ball", "assets/meshes/sphere.obj", {.method = PlacementMethod::raster,
//                                                                 .placement = {.fit_into = box}})
//                      .attach("ball", 0.0)
//                      .release(4.0)
//                      .build();
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "control/control_section.h"
#include "core/result.h"
#include "sim/scene.h"

namespace aquaform::control {

/// How one mesh is placed and moves (the keys "method", "placement" and "animation" of a mesh).
struct MeshSpec {
    std::optional<PlacementMethod> method;  ///< default: inside, or raster for a deforming mesh
    geometry::MeshPlacement placement;
    geometry::MeshAnimation animation;
};

/// A ControlMesh named `name` from its rest mesh (`file` as loaded, or none for an OBJ sequence)
/// and spec: checks the method against the animation and binds the animation. `path` names the
/// mesh in messages ("control.meshes.ball"). Throws json_fields::Invalid.
ControlMesh bind_control_mesh(std::string name, std::filesystem::path file, const geometry::Mesh* rest,
                              const geometry::MeshReport& report, MeshSpec spec, const std::string& path);

class SectionBuilder {
public:
    /// Spacing and damping start at the loader's defaults for `scene`.
    explicit SectionBuilder(const Scene& scene);

    SectionBuilder& spacing(float metres);
    SectionBuilder& pressure(float pascal);
    SectionBuilder& support_radius(float metres);
    SectionBuilder& fixed_substeps(bool fixed = true);
    SectionBuilder& damping(float per_second);

    /// A mesh loaded from an OBJ file (`file` used as given: make it absolute or relative to the
    /// working directory).
    SectionBuilder& mesh(const std::string& name, const std::filesystem::path& file, MeshSpec spec = {});
    /// A mesh made in code (primitives.h), in the coordinates its placement starts from.
    SectionBuilder& mesh(const std::string& name, const geometry::Mesh& rest, MeshSpec spec = {});

    /// Timeline events, in time order; `tags` as a mask of fluid tags (bit i: fluid block i).
    SectionBuilder& attach(const std::string& mesh, double t = 0.0, uint32_t tags = ~0u);
    SectionBuilder& union_with(const std::string& mesh, double t = 0.0, uint32_t tags = ~0u);
    /// `duration` 0: replace at once; else cross-fade over `duration` seconds.
    SectionBuilder& morph(const std::string& mesh, double t, double duration, uint32_t tags = ~0u);
    SectionBuilder& hold(double t);
    /// Releases `mesh`, or every mesh when it is empty.
    SectionBuilder& release(double t, const std::string& mesh = "");

    /// The section, or the first problem (a mesh that does not load, a name used twice, an event
    /// naming no mesh of the section, events out of time order, a value out of range).
    Result<ControlSection> build() const;

private:
    SectionBuilder& event(TimelineAction action, const std::string& mesh, double t, uint32_t tags, double duration);
    void fail(std::string message);

    float particle_spacing_ = 0.0f, kernel_radius_ = 0.0f;
    ControlSection section_;
    std::vector<TimelineEvent> events_;
    std::string error_;
};

}  // namespace aquaform::control
