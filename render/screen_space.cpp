#include "render/screen_space.h"

#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"
#include "render/picture_size.h"
#include "render/surface_settings.h"

namespace aquaform {

namespace {

using shader::SurfacePassPush;

template <typename T>
Result<bool> out_of_range(const char* name, T value, const char* range) {
    std::ostringstream text;
    text << "screen-space setting " << name << " = " << value << " is out of range; use " << range;
    return Error{text.str()};
}

SurfacePassPush axis_push(uint32_t axis) {
    SurfacePassPush push{};
    push.axis = axis;
    return push;
}

uint32_t filter_code(ScreenSpaceFilter filter) {
    switch (filter) {
        case ScreenSpaceFilter::bilateral:
            return SS_FILTER_BILATERAL;
        case ScreenSpaceFilter::curvature_flow:
            return SS_FILTER_CURVATURE_FLOW;
        case ScreenSpaceFilter::narrow_range:
            return SS_FILTER_NARROW_RANGE;
    }
    return SS_FILTER_BILATERAL;
}

shader::ScreenSpaceParams make_filter_params(const ScreenSpaceSettings& s, const shader::SurfaceParams& p) {
    shader::ScreenSpaceParams f{};
    const float r = p.particle_radius;
    f.screen = {p.screen.x, p.screen.y, filter_code(s.filter), s.max_filter_px};
    f.pixel_scale = p.pixel_scale;
    f.particle_radius = r;
    f.sigma = (s.filter == ScreenSpaceFilter::narrow_range ? s.narrow_sigma_radii : s.bilateral_sigma_radii) * r;
    f.depth_sigma = s.bilateral_depth_sigma_radii * r;
    f.range = s.narrow_range_radii * r;
    f.clamp_offset = s.narrow_clamp_radii * r;
    f.flow_step = s.flow_step;
    f.flow_jump = s.flow_jump_radii * r;
    // forward.w = tan(fov_x / 2), right.w = tan(fov_y / 2) (surface_layout.h).
    f.cx = 2.0f * p.forward.w / float(p.screen.x);
    f.cy = 2.0f * p.right.w / float(p.screen.y);
    return f;
}

}  // namespace

const char* filter_name(ScreenSpaceFilter filter) {
    switch (filter) {
        case ScreenSpaceFilter::bilateral:
            return "bilateral";
        case ScreenSpaceFilter::curvature_flow:
            return "curvature_flow";
        case ScreenSpaceFilter::narrow_range:
            return "narrow_range";
    }
    return "?";
}

Result<ScreenSpaceFilter> parse_filter(const std::string& text) {
    for (ScreenSpaceFilter f :
         {ScreenSpaceFilter::bilateral, ScreenSpaceFilter::curvature_flow, ScreenSpaceFilter::narrow_range})
        if (text == filter_name(f)) return f;
    return Error{"unknown screen-space filter '" + text +
                 "'; use bilateral (Green 2010), curvature_flow (van der Laan et al. 2009) or narrow_range "
                 "(Truong & Yuksel 2018)"};
}

Result<bool> validate(const ScreenSpaceSettings& s) {
    if (!(s.sprite_radius >= 0.25f && s.sprite_radius <= 4.0f))
        return out_of_range("sprite_radius", s.sprite_radius, "0.25..4 particle radii");
    if (s.max_filter_px < 1 || s.max_filter_px > 64) return out_of_range("max_filter_px", s.max_filter_px, "1..64 px");
    if (!(s.bilateral_sigma_radii > 0.0f && s.bilateral_sigma_radii <= 16.0f))
        return out_of_range("bilateral_sigma", s.bilateral_sigma_radii, "(0, 16] particle radii");
    if (!(s.bilateral_depth_sigma_radii > 0.0f && s.bilateral_depth_sigma_radii <= 64.0f))
        return out_of_range("bilateral_depth_sigma", s.bilateral_depth_sigma_radii, "(0, 64] particle radii");
    if (!(s.narrow_sigma_radii > 0.0f && s.narrow_sigma_radii <= 16.0f))
        return out_of_range("narrow_sigma", s.narrow_sigma_radii, "(0, 16] particle radii");
    if (!(s.narrow_range_radii > 0.0f && s.narrow_range_radii <= 64.0f))
        return out_of_range("narrow_range", s.narrow_range_radii, "(0, 64] particle radii");
    if (!(s.narrow_clamp_radii >= 0.0f && s.narrow_clamp_radii <= s.narrow_range_radii))
        return out_of_range("narrow_clamp", s.narrow_clamp_radii, "0..narrow_range particle radii");
    if (s.flow_iterations < 1 || s.flow_iterations > 1000)
        return out_of_range("flow_iterations", s.flow_iterations, "1..1000");
    if (!(s.flow_step > 0.0f && s.flow_step <= 0.25f))
        return out_of_range("flow_step", s.flow_step, "(0, 0.25] px^2 (the explicit scheme's stability bound)");
    if (!(s.flow_jump_radii > 0.0f && s.flow_jump_radii <= 64.0f))
        return out_of_range("flow_jump", s.flow_jump_radii, "(0, 64] particle radii");
    return true;
}

ScreenSpaceRenderer::ScreenSpaceRenderer(gpu::Context& ctx, const ParticleDomain& domain, uint32_t width,
                                         uint32_t height, uint32_t max_particles)
    : ctx_(&ctx),
      domain_(domain),
      width_(width),
      height_(height),
      max_particles_(std::max(max_particles, 1u)),
      buffers_(ctx) {
    require_picture_size("screen-space renderer", width, height);
    const uint64_t pixels = uint64_t(width) * height;
    params_buf_ = &buffers_.add("ss.params", sizeof(shader::SurfaceParams));
    filter_params_buf_ = &buffers_.add("ss.filter_params", sizeof(shader::ScreenSpaceParams));
    aggregate_ = &buffers_.add("ss.aggregate", uint64_t(max_particles_) * 4);
    // The splat's D_agg, classification and D_splash_back outputs: with no aggregates and mode 0
    // it writes none, so one small buffer stands in for them instead of three per-pixel maps.
    unused_ = &buffers_.add("ss.unused_splat_outputs", 16);
    splat_counters_ = &buffers_.add("ss.splat_counters", SPLAT_COUNTERS * 4);
    raw_ = &buffers_.add("ss.depth_raw", pixels * 4);
    filtered_ = &buffers_.add("ss.depth_filtered", pixels * 4);
    scratch_ = &buffers_.add("ss.depth_scratch", pixels * 4);
    thickness_ = &buffers_.add("ss.thickness", pixels * 4);
    hit_ = &buffers_.add("ss.hit", pixels * 16);
    normal_ = &buffers_.add("ss.normal", pixels * 16);
    color_ = &buffers_.add("ss.color", pixels * 4);

    const uint32_t push = sizeof(SurfacePassPush);
    splat_ = gpu::ComputePass(ctx, {"render/splat.comp", 10, push});
    bilateral_ = gpu::ComputePass(ctx, {"render/ss_bilateral.comp", 3, push});
    narrow_range_ = gpu::ComputePass(ctx, {"render/ss_narrow_range.comp", 3, push});
    curvature_flow_ = gpu::ComputePass(ctx, {"render/ss_curvature_flow.comp", 3});
    normals_ = gpu::ComputePass(ctx, {"render/screen_normals.comp", 3});
    hit_pass_ = gpu::ComputePass(ctx, {"render/ss_hit.comp", 3});
    compose_ = gpu::ComputePass(ctx, {"render/compose.comp", 7});
    // Every particle is a splash to the splat (no D_agg): zero once, never written again.
    ctx.submit_and_wait([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, aggregate_->buffer, 0, VK_WHOLE_SIZE, 0u); });
}

ScreenSpaceRenderer::~ScreenSpaceRenderer() = default;

void ScreenSpaceRenderer::record(VkCommandBuffer cmd, const FrameInput& frame, const ViewCamera& camera,
                                 const ScreenSpaceSettings& settings, gpu::GpuTimer* timer) {
    if (auto valid = validate(settings); !valid) throw Failure(valid.error());
    frame.check("screen-space renderer", max_particles_);
    const gpu::Buffer& positions = *frame.positions;
    const uint32_t count = frame.count;
    if (!(glm::length(camera.target - camera.eye) > 0.0f))
        throw Failure("screen-space renderer: the camera's eye and target coincide; move the eye away");
    // The splat and compose passes read no grid; a one-cell grid keeps the block's field terms finite.
    SurfaceSettings surface;
    GridGeometry no_grid{domain_.bounds.min, render_radius(surface, domain_), glm::uvec3(1u)};
    params_ = make_surface_params(surface, domain_, no_grid, camera, width_, height_, count);
    add_solids(params_.tank, frame.solids);
    params_.sprite_radius = settings.sprite_radius * params_.particle_radius;
    params_.flags = 0;  // none of the ray marchers' mechanisms run here
    filter_params_ = make_filter_params(settings, params_);
    gpu::record_upload(*ctx_, cmd, *params_buf_, &params_, sizeof(params_));
    gpu::record_upload(*ctx_, cmd, *filter_params_buf_, &filter_params_, sizeof(filter_params_));

    const uint32_t pixels = width_ * height_;
    {
        gpu::GpuScope scope(timer, cmd, "ss_splat");
        gpu::fill(*ctx_, cmd, *raw_, DEPTH_EMPTY);
        gpu::fill(*ctx_, cmd, *thickness_, 0u);
        gpu::fill(*ctx_, cmd, *splat_counters_, 0u);
        gpu::dispatch(*ctx_, cmd, splat_, std::max(count, 1u), axis_push(0),
                      {{"params", params_buf_},
                       {"sorted", &positions},
                       {"shape", unused_},
                       {"aggregate", aggregate_},
                       {"depth_all", raw_},
                       {"depth_agg", unused_},
                       {"thickness", thickness_},
                       {"front_class", unused_},
                       {"depth_splash_back", unused_},
                       {"splat_counters", splat_counters_}});
    }
    {
        gpu::GpuScope scope(timer, cmd, "ss_filter");
        record_filter(cmd, settings);
    }
    {
        gpu::GpuScope scope(timer, cmd, "ss_normals");
        gpu::dispatch(*ctx_, cmd, normals_, pixels,
                      {{"params", params_buf_}, {"depth_smooth", filtered_}, {"normal_screen", normal_}});
        gpu::dispatch(*ctx_, cmd, hit_pass_, pixels, {{"params", params_buf_}, {"depth", filtered_}, {"hit", hit_}});
    }
    {
        gpu::GpuScope scope(timer, cmd, "ss_compose");
        gpu::dispatch(*ctx_, cmd, compose_, pixels,
                      {{"params", params_buf_},
                       {"hit", hit_},
                       {"normal", normal_},
                       {"thickness", thickness_},
                       {"color", color_},
                       {"spray", unused_},
                       {"solid_nodes", &solid_nodes(frame.solids, *params_buf_)}});
    }
    whitewater_.record(
        *ctx_, cmd, frame.whitewater, width_, height_, camera, *hit_,
        {&params_.tank, params_.domain_min, params_.domain_max, &solid_nodes(frame.solids, *params_buf_)}, *color_,
        timer);
}

void ScreenSpaceRenderer::record_filter(VkCommandBuffer cmd, const ScreenSpaceSettings& settings) {
    const uint32_t pixels = width_ * height_;
    if (settings.filter == ScreenSpaceFilter::curvature_flow) {
        // Ping-pong between scratch and filtered, starting on the side that ends on filtered.
        const uint32_t n = settings.flow_iterations;
        const gpu::Buffer* src = raw_;
        for (uint32_t i = 0; i < n; ++i) {
            const gpu::Buffer* dst = (n - 1 - i) % 2 == 0 ? filtered_ : scratch_;
            gpu::dispatch(*ctx_, cmd, curvature_flow_, pixels,
                          {{"ss", filter_params_buf_}, {"src", src}, {"dst", dst}});
            src = dst;
        }
        return;
    }
    const gpu::ComputePass& pass = settings.filter == ScreenSpaceFilter::bilateral ? bilateral_ : narrow_range_;
    gpu::dispatch(*ctx_, cmd, pass, pixels, axis_push(0),
                  {{"ss", filter_params_buf_}, {"src", raw_}, {"dst", scratch_}});
    gpu::dispatch(*ctx_, cmd, pass, pixels, axis_push(1),
                  {{"ss", filter_params_buf_}, {"src", scratch_}, {"dst", filtered_}});
}

SurfaceFrame ScreenSpaceRenderer::render(const FrameInput& frame, const ViewCamera& camera,
                                         const ScreenSpaceSettings& settings, gpu::GpuTimer* timer) {
    gpu::submit_timed(*ctx_, timer, [&](VkCommandBuffer cmd) { record(cmd, frame, camera, settings, timer); });
    return read_frame();
}

SurfaceFrame ScreenSpaceRenderer::read_frame() {
    return download_surface_frame(*ctx_, width_, height_, *hit_, *normal_, *color_);
}

std::vector<float> ScreenSpaceRenderer::raw_depth() {
    return gpu::download_vector<float>(*ctx_, *raw_, size_t(width_) * height_);
}

std::vector<float> ScreenSpaceRenderer::filtered_depth() {
    return gpu::download_vector<float>(*ctx_, *filtered_, size_t(width_) * height_);
}

std::vector<gpu::BufferReport> ScreenSpaceRenderer::memory_report() const { return buffers_.report(); }

}  // namespace aquaform
