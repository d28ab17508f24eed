// The SPH surface renderer's methods in the registry: adaptive (Wu et al.), uniform (Xiao et
// al.) and the exhaustive reference. One SurfaceRenderer draws all three, so a renderer made for
// one may be configured with another (a study's reference on the same buffers).
#include "render/registry.h"
#include "render/surface_renderer.h"

namespace aquaform {

namespace {

class SurfaceMethodRenderer final : public FamilyRenderer<SurfaceRenderer, SurfaceSettings> {
public:
    using FamilyRenderer::FamilyRenderer;
    RenderStats stats() override {
        RenderStats s;
        s.rays = impl_.rays_cast();
        for (const RayCounts& c : impl_.ray_counts()) {
            s.march_steps += c.march;
            s.bisection_evaluations += c.bisection;
            s.mask_leaps += c.leaps;
        }
        s.evaluations = s.march_steps + s.bisection_evaluations;
        s.cut = impl_.cut_rays();
        const SpriteCounts sprites = impl_.sprite_counts();
        s.sprites = sprites.sprites;
        s.sprite_pixels = sprites.pixels;
        s.sprite_covered = sprites.covered;
        s.sprite_depth_atomics = sprites.depth_atomics;
        s.sprite_thickness_atomics = sprites.thickness_atomics;
        s.sprite_longest_walk = sprites.longest_walk;
        s.sprite_largest_footprint = sprites.largest_footprint;
        s.resolution_note = impl_.resolution_note();
        s.march_lanes = impl_.march_lanes();
        return s;
    }
};

using S = SurfaceSettings;
constexpr SettingType kNumber = SettingType::number, kInteger = SettingType::integer, kOff = SettingType::off_switch;

std::vector<SettingSpec> surface_settings() {
    return {
        setting<S>("step", "--step", "step", kNumber, &S::step_radii, 0.01, 4, "0.01..4 particle radii",
                   "marching step in particle radii"),
        setting<S>("max_steps", "--max-steps", "max_steps", kInteger, &S::max_steps, 1, 100000, "1..100000",
                   "density evaluations per ray before it gives up"),
        setting<S>("max_skip_evals", "--max-skip", "max_skip", kInteger, &S::max_skip_evals, 0, 1e9, "0 or more",
                   "maxSkipCounts: evaluations before Wu et al.'s jump to D_agg (--wu-skip)"),
        setting<S>("refine_steps", "--refine", "refine", kInteger, &S::refine_steps, 0, 32, "0..32",
                   "bisection steps at the hit"),
        setting<S>("mask_a", "--mask-a", "mask_a", kNumber, &S::mask_a, 0, 1, "0 < a <= 1",
                   "centre weight of Wu et al.'s mask convolution (--wu-mask)"),
        setting<S>("mask_b", "--mask-b", "mask_b", kNumber, &S::mask_b, 0, 1, "0 < b <= a",
                   "outer weight of Wu et al.'s mask convolution (--wu-mask)"),
        setting<S>("tile_eps1", "--eps1", "eps1", kNumber, &S::tile_eps1, 0, 1e9, "a value >= 0",
                   "tile depth variance for half resolution, radii^2"),
        setting<S>("tile_eps2", "--eps2", "eps2", kNumber, &S::tile_eps2, 0, 1e9, "a value above tile_eps1",
                   "tile depth variance for quarter resolution, radii^2"),
        setting<S>("blend_a", "--blend-a", "blend_a", kNumber, &S::blend_a, 0, 1e9, "A >= 0",
                   "normal blending A per particle radius"),
        setting<S>("blend_b", "--blend-b", "blend_b", kNumber, &S::blend_b, -1e9, 1e9, "a finite B",
                   "normal blending B per pixel"),
        setting<S>("lone_radius", "--lone-radius", "lone_radius", kNumber, &S::lone_radius, 0.05, 3.9,
                   "0.05..3.9 particle radii (below the kernel support)", "iso-sphere radius of a lone particle"),
        setting<S>("radius_spacings", "--radius", "radius", kNumber, &S::radius_spacings, 0, 4,
                   "0 (the solver's h) or 1..4 spacings", "kernel support in spacings"),
        setting<S>("use_mask", "--no-mask", "mask", kOff, &S::use_mask, 0, 1, "", "adaptive: no binary density mask"),
        setting<S>("use_skip", "--no-skip", "skip", kOff, &S::use_skip, 0, 1, "", "adaptive: no skip to D_agg"),
        setting<S>("tight_mask", "--wu-mask", "tight_mask", kOff, &S::tight_mask, 0, 1, "",
                   "adaptive: Wu et al.'s mask (cell counts x W(0), convolved with a, b) instead of the tight bound"),
        setting<S>("exact_skip", "--wu-skip", "exact_skip", kOff, &S::exact_skip, 0, 1, "",
                   "adaptive: Wu et al.'s skip after max_skip evaluations (can jump over splashes)"),
        setting<S>("adaptive_resolution", "--no-adaptive-res", "adaptive_resolution", kOff, &S::adaptive_resolution, 0,
                   1, "", "adaptive: every tile at full resolution"),
        setting<S>("blend_normals", "--no-blend", "blend_normals", kOff, &S::blend_normals, 0, 1, "",
                   "adaptive: screen-space normals only"),
        setting<S>("anisotropic", "--isotropic", "anisotropic", kOff, &S::anisotropic, 0, 1, "",
                   "isotropic kernels for the classification"),
        choice<S>("surface", "--surface", "surface", &S::surface, {"isotropic", "anisotropic"},
                  "the surface's kernels: a sphere per particle, or Yu & Turk's stretched kernels"),
        setting<S>("spray_whiteness", "--spray", "spray", kNumber, &S::spray_whiteness, 0, 1, "0 (off) .. 1",
                   "appearance: splash particles drawn as white water (run, demo, viewer: on)"),
        setting<S>("normal_smoothing_deg", "--normal-smoothing", "normal_smoothing", kNumber, &S::normal_smoothing_deg,
                   0, 90, "0 (off) .. 90 degrees",
                   "adaptive: normals averaged across the surface where they differ by about this angle or less"),
        setting<S>("centre_smoothing", "--centre-smoothing", "centre_smoothing", kNumber, &S::centre_smoothing, 0, 1,
                   "0..1", "anisotropic surface: Laplacian smoothing of the kernel centres (Yu & Turk's lambda)"),
    };
}

void add(Registry& registry, SurfaceMethod method, const char* description) {
    SurfaceSettings defaults;
    defaults.method = method;
    registry.add(family_entry<SurfaceMethodRenderer>(method_name(method), "surface", description,
                                                     method != SurfaceMethod::reference, defaults, surface_settings()));
}

}  // namespace

void register_surface_methods(Registry& registry) {
    add(registry, SurfaceMethod::adaptive,
        "Wu et al.: adaptive ray marching (mask, skip, adaptive resolution, blended normals)");
    add(registry, SurfaceMethod::uniform, "Xiao et al. 2018: uniform ray casting from D_all, PCA normals");
    add(registry, SurfaceMethod::reference, "exhaustive SPH reference: fine steps from the grid's bounds (slow)");
}

}  // namespace aquaform
