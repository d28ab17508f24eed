// The screen-space filters in the registry: bilateral (Green 2010), curvature flow (van der
// Laan et al. 2009) and the narrow-range filter (Truong & Yuksel 2018).
#include "render/registry.h"
#include "render/screen_space.h"

namespace aquaform {

namespace {

class ScreenSpaceMethodRenderer final : public FamilyRenderer<ScreenSpaceRenderer, ScreenSpaceSettings> {
public:
    using FamilyRenderer::FamilyRenderer;
    RenderStats stats() override { return {}; }  // no rays, no lists
};

using S = ScreenSpaceSettings;
constexpr SettingType kNumber = SettingType::number, kInteger = SettingType::integer;

std::vector<SettingSpec> common_settings() {
    return {
        setting<S>("sprite_radius", "--sprite-radius", "sprite_radius", kNumber, &S::sprite_radius, 0.25, 4,
                   "0.25..4 particle radii", "sphere sprite radius"),
        setting<S>("max_filter_px", "--max-filter-px", "max_filter_px", kInteger, &S::max_filter_px, 1, 64, "1..64 px",
                   "largest filter half-width"),
    };
}

std::vector<SettingSpec> filter_settings(ScreenSpaceFilter filter) {
    std::vector<SettingSpec> s = common_settings();
    switch (filter) {
        case ScreenSpaceFilter::bilateral:
            s.push_back(setting<S>("bilateral_sigma", "--sigma", "sigma", kNumber, &S::bilateral_sigma_radii, 0, 16,
                                   "(0, 16] particle radii", "spatial sigma"));
            s.push_back(setting<S>("bilateral_depth_sigma", "--depth-sigma", "depth_sigma", kNumber,
                                   &S::bilateral_depth_sigma_radii, 0, 64, "(0, 64] particle radii", "range sigma"));
            break;
        case ScreenSpaceFilter::narrow_range:
            s.push_back(setting<S>("narrow_sigma", "--sigma", "sigma", kNumber, &S::narrow_sigma_radii, 0, 16,
                                   "(0, 16] particle radii", "spatial sigma"));
            s.push_back(setting<S>("narrow_range", "--range", "range", kNumber, &S::narrow_range_radii, 0, 64,
                                   "(0, 64] particle radii", "range half-width delta"));
            s.push_back(setting<S>("narrow_clamp", "--clamp", "clamp", kNumber, &S::narrow_clamp_radii, 0, 64,
                                   "0..narrow_range particle radii", "clamp mu"));
            break;
        case ScreenSpaceFilter::curvature_flow:
            s.push_back(setting<S>("flow_iterations", "--flow-iterations", "iterations", kInteger, &S::flow_iterations,
                                   1, 1000, "1..1000", "iterations of the flow"));
            s.push_back(setting<S>("flow_step", "--flow-step", "flow_step", kNumber, &S::flow_step, 0, 0.25,
                                   "(0, 0.25] px^2 (the explicit scheme's stability bound)", "step kappa"));
            s.push_back(setting<S>("flow_jump", "--flow-jump", "flow_jump", kNumber, &S::flow_jump_radii, 0, 64,
                                   "(0, 64] particle radii", "depth step that counts as a discontinuity"));
            break;
    }
    return s;
}

void add(Registry& registry, ScreenSpaceFilter filter, const char* description) {
    ScreenSpaceSettings defaults;
    defaults.filter = filter;
    registry.add(family_entry<ScreenSpaceMethodRenderer>(filter_name(filter), "screen_space", description, true,
                                                         defaults, filter_settings(filter)));
}

}  // namespace

void register_screen_space_methods(Registry& registry) {
    add(registry, ScreenSpaceFilter::bilateral, "screen-space sprites, bilateral Gaussian filter (Green 2010)");
    add(registry, ScreenSpaceFilter::curvature_flow, "screen-space sprites, curvature flow (van der Laan et al. 2009)");
    add(registry, ScreenSpaceFilter::narrow_range, "screen-space sprites, narrow-range filter (Truong & Yuksel 2018)");
}

}  // namespace aquaform
