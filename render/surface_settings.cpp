#include "render/surface_settings.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "shaders/shared/render/anisotropy.h"
#include "shaders/shared/render/render_kernels.h"

namespace aquaform {

namespace {

uint32_t ceil_div(uint32_t a, uint32_t b) { return (a + b - 1) / b; }

glm::vec4 with_w(const glm::vec3& v, float w) { return glm::vec4(v, w); }

template <typename T>
Result<bool> out_of_range(const char* name, T value, const char* range) {
    std::ostringstream text;
    text << "render setting " << name << " = " << value << " is out of range; use " << range;
    return Error{text.str()};
}

}  // namespace

const char* method_name(SurfaceMethod method) {
    switch (method) {
        case SurfaceMethod::uniform:
            return "uniform";
        case SurfaceMethod::adaptive:
            return "adaptive";
        case SurfaceMethod::reference:
            return "reference";
    }
    return "?";
}

Result<SurfaceMethod> parse_method(const std::string& text) {
    for (SurfaceMethod m : {SurfaceMethod::uniform, SurfaceMethod::adaptive, SurfaceMethod::reference})
        if (text == method_name(m)) return m;
    return Error{"unknown render method '" + text + "'; use uniform (Xiao et al.), adaptive (Wu et al.) or reference"};
}

Result<bool> validate(const SurfaceSettings& s) {
    if (!(s.radius_spacings == 0.0f || (s.radius_spacings >= 1.0f && s.radius_spacings <= 4.0f)))
        return out_of_range("radius_spacings", s.radius_spacings, "0 (the solver's h) or 1..4 spacings");
    if (!(s.lone_radius >= 0.05f && s.lone_radius <= 3.9f))  // the range the help gives, both ends in
        return out_of_range("lone_radius", s.lone_radius, "0.05..3.9 particle radii (below the kernel support)");
    if (!(s.step_radii >= 0.01f && s.step_radii <= 4.0f))
        return out_of_range("step", s.step_radii, "0.01..4 particle radii");
    if (s.max_steps < 1 || s.max_steps > 100000) return out_of_range("max_steps", s.max_steps, "1..100000");
    if (s.refine_steps > 32) return out_of_range("refine_steps", s.refine_steps, "0..32");
    if (!(s.mask_a > 0.0f && s.mask_a <= 1.0f)) return out_of_range("mask_a", s.mask_a, "0 < a <= 1");
    if (!(s.mask_b > 0.0f && s.mask_b <= s.mask_a))
        return out_of_range("mask_b", s.mask_b, "0 < b <= a (outer cells weigh less than the centre)");
    if (!(s.tile_eps1 >= 0.0f && s.tile_eps2 > s.tile_eps1))
        return out_of_range("tile_eps2", s.tile_eps2, "a value above tile_eps1 (>= 0)");
    if (!(s.blend_a >= 0.0f) || !std::isfinite(s.blend_b))
        return out_of_range("blend_a", s.blend_a, "A >= 0, finite B");
    if (!(s.smooth_sigma_px > 0.0f) || s.smooth_radius_px > 32)
        return out_of_range("smooth_radius_px", s.smooth_radius_px, "1..32 px with a positive sigma");
    if (!(s.spray_whiteness >= 0.0f && s.spray_whiteness <= 1.0f))
        return out_of_range("spray", s.spray_whiteness, "0 (off) .. 1");
    if (!(s.normal_smoothing_deg >= 0.0f && s.normal_smoothing_deg <= 90.0f))
        return out_of_range("normal_smoothing", s.normal_smoothing_deg, "0 (off) .. 90 degrees");
    if (!(s.centre_smoothing >= 0.0f && s.centre_smoothing <= 1.0f))
        return out_of_range("centre_smoothing", s.centre_smoothing, "0..1");
    if (s.surface == SurfaceKernel::anisotropic && !s.tight_mask)
        return Error{
            "render setting tight_mask = 0 (--wu-mask) needs the isotropic surface: Wu et al.'s count bound "
            "assumes every kernel peaks at W(0); add --surface isotropic, or drop --wu-mask"};
    if (!(s.reference_step_radii > 0.0f))
        return out_of_range("reference_step", s.reference_step_radii, "a step above 0 particle radii");
    return true;
}

float render_radius(const SurfaceSettings& settings, const ParticleDomain& domain) {
    const float factor = settings.radius_spacings > 0.0f ? settings.radius_spacings : domain.kernel_radius_factor;
    return factor * domain.particle_spacing;
}

Result<GridGeometry> render_grid(const SurfaceSettings& settings, const ParticleDomain& domain) {
    return grid_for_domain(domain.bounds.min, domain.bounds.max, render_radius(settings, domain));
}

shader::SurfaceParams make_surface_params(const SurfaceSettings& s, const ParticleDomain& domain,
                                          const GridGeometry& grid, const ViewCamera& camera, uint32_t width,
                                          uint32_t height, uint32_t particle_count) {
    shader::SurfaceParams p = make_field_params(s, domain, grid, particle_count);
    const CameraBlock view = camera_block(camera, width, height);
    const float tan_y = view.right.w;
    p.eye = view.eye;
    p.forward = view.forward;
    p.right = view.right;
    p.up = view.up;
    p.screen = {width, height, ceil_div(width, SURFACE_TILE), ceil_div(height, SURFACE_TILE)};
    p.pixel_scale = float(height) / (2.0f * tan_y);
    return p;
}

shader::SurfaceParams make_field_params(const SurfaceSettings& s, const ParticleDomain& domain,
                                        const GridGeometry& grid, uint32_t particle_count) {
    shader::SurfaceParams p{};
    p.grid_origin_cell = with_w(grid.origin, grid.cell_size);
    p.grid_dims = {grid.dims, grid.cell_count()};
    const glm::uvec3 words{ceil_div(grid.dims.x, MASK_BLOCK_X), ceil_div(grid.dims.y, MASK_BLOCK_Y),
                           ceil_div(grid.dims.z, MASK_BLOCK_Z)};
    p.mask_dims = {words, words.x * words.y * words.z};
    const glm::uvec3 coarse{ceil_div(words.x, MASK_COARSE), ceil_div(words.y, MASK_COARSE),
                            ceil_div(words.z, MASK_COARSE)};
    p.coarse_dims = {coarse, coarse.x * coarse.y * coarse.z};
    p.domain_min = with_w(domain.bounds.min, 0.0f);
    p.domain_max = with_w(domain.bounds.max, 0.0f);

    const float r = grid.cell_size;
    const float spacing = domain.particle_spacing;
    const float particle_radius = 0.5f * spacing;
    p.radius = r;
    p.inv_radius = 1.0f / r;
    p.kernel_coeff = shader::cubic_coefficient(r);
    p.volume = spacing * spacing * spacing;
    p.iso = p.volume * p.kernel_coeff * shader::cubic_shape(std::min(s.lone_radius * particle_radius / r, 1.0f));
    p.particle_radius = particle_radius;
    // Sprites of radius r: the field is zero farther than r from every particle, so the front of
    // the union of these spheres is never behind the iso-surface and the entry never skips it.
    p.sprite_radius = r;
    p.particle_count = particle_count;

    const bool reference = s.method == SurfaceMethod::reference;
    const bool adaptive = s.method == SurfaceMethod::adaptive;
    // The reference never steps coarser than the method it measures (--step 0.01 is finer than
    // its own 1/16 radius, and was refused through this setting, which no flag sets).
    p.step = (reference ? std::min(s.reference_step_radii, s.step_radii) : s.step_radii) * particle_radius;
    // The reference marches from the grid's bounds, so it may need many more evaluations.
    p.max_steps = reference ? 1000000u : s.max_steps;
    p.max_skip_evals = s.max_skip_evals;
    p.refine_steps = reference ? s.reference_refine_steps : s.refine_steps;
    p.method = reference ? SURFACE_METHOD_REFERENCE : adaptive ? SURFACE_METHOD_ADAPTIVE : SURFACE_METHOD_UNIFORM;
    uint32_t flags = 0;
    if (s.anisotropic) flags |= SURFACE_ANISOTROPIC;
    if (s.surface == SurfaceKernel::anisotropic) flags |= SURFACE_ANISOTROPIC_FIELD;
    // The reference skips only what the exact (a = b = 1) mask proves empty.
    if (reference || (adaptive && s.use_mask)) flags |= SURFACE_USE_MASK;
    if (adaptive && s.use_skip) flags |= SURFACE_USE_SKIP;
    if (adaptive && s.use_skip && !s.exact_skip) flags |= SURFACE_WU_SKIP;
    if (adaptive && s.adaptive_resolution) flags |= SURFACE_ADAPTIVE_RES;
    if (adaptive && s.blend_normals) flags |= SURFACE_BLEND_NORMALS;
    if (s.method == SurfaceMethod::uniform) flags |= SURFACE_XIAO_NORMALS;
    p.flags = flags;
    p.mask_count_threshold = p.iso / (p.volume * p.kernel_coeff);
    p.mask_weight_a = reference ? 1.0f : s.mask_a;
    p.mask_weight_b = reference ? 1.0f : s.mask_b;

    const float radius2 = particle_radius * particle_radius;
    p.tile_eps1 = s.tile_eps1 * radius2;
    p.tile_eps2 = s.tile_eps2 * radius2;
    p.blend_a = s.blend_a / particle_radius;
    p.blend_b = s.blend_b;
    p.smooth_sigma_px = s.smooth_sigma_px;
    p.smooth_sigma_depth = s.smooth_sigma_depth_radii * particle_radius;

    p.aniso_kr = shader::kDefaultAnisoKr;
    p.aniso_ks = shader::kDefaultAnisoKs;
    p.aniso_kn = shader::kDefaultAnisoKn;
    p.aniso_neps = shader::kDefaultAnisoNeps;
    p.aggregate_density = shader::kDefaultAggregateDensity;
    p.xiao_d = s.xiao_d;
    p.xiao_k = s.xiao_k;
    p.smooth_radius_px = s.smooth_radius_px;
    p.centre_smoothing = s.centre_smoothing;
    p.shading = s.spray_whiteness > 0.0f ? SHADE_SPRAY : 0u;
    p.spray_whiteness = s.spray_whiteness;
    p.normal_smoothing =
        adaptive && s.normal_smoothing_deg > 0.0f ? 1.0f - std::cos(glm::radians(s.normal_smoothing_deg)) : 0.0f;

    p.light_dir = kLightDirection;
    p.fluid_color = kFluidOptics;
    p.tank = make_tank_params(domain);
    return p;
}

shader::TankParams make_tank_params(const ParticleDomain& domain) {
    if (domain.static_boxes.size() > TANK_MAX_BOXES)
        throw Failure("renderer: " + std::to_string(domain.static_boxes.size()) + " static boxes, at most " +
                          std::to_string(TANK_MAX_BOXES) + " are drawn",
                      Failure::Kind::input);
    shader::TankParams tank{};
    tank.counts = {uint32_t(domain.static_boxes.size()), TANK_GLASS_WALLS, 0u, 0u};
    // The frame is thin beside the tank yet a few pixels wide in a 640-pixel view of it: 1 % of
    // the tank's length (its height is left out: a tall tank is rarely seen whole).
    const glm::vec3 size = domain.bounds.max - domain.bounds.min;
    tank.frame.x = 0.01f * std::max(size.x, size.z);
    for (size_t i = 0; i < domain.static_boxes.size(); ++i) {
        tank.box_min[i] = with_w(domain.static_boxes[i].min, 0.0f);
        tank.box_max[i] = with_w(domain.static_boxes[i].max, 0.0f);
    }
    return tank;
}

CameraBlock camera_block(const ViewCamera& camera, uint32_t width, uint32_t height) {
    const glm::mat3 axes = camera_axes(camera);
    const float tan_y = std::tan(glm::radians(camera.fov_y_degrees) * 0.5f);
    const float tan_x = tan_y * float(width) / float(height);
    return {with_w(camera.eye, 0.0f), with_w(axes[2], tan_x), with_w(axes[0], tan_y), with_w(axes[1], 0.0f)};
}

}  // namespace aquaform
