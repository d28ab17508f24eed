#include "render/metaball_renderer.h"

#include <algorithm>
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

using shader::MetaballCounters;
using shader::MetaballPush;

template <typename T>
Result<bool> out_of_range(const char* name, T value, const char* range) {
    std::ostringstream text;
    text << "metaball setting " << name << " = " << value << " is out of range; use " << range;
    return Error{text.str()};
}

MetaballPush mode_push(uint32_t mode) {
    MetaballPush push{};
    push.mode = mode;
    return push;
}

uint32_t method_code(MetaballMethod method) {
    switch (method) {
        case MetaballMethod::brute_force:
            return METABALL_BRUTE_FORCE;
        case MetaballMethod::a_buffer:
            return METABALL_A_BUFFER;
        case MetaballMethod::s_buffer:
            return METABALL_S_BUFFER;
    }
    return METABALL_BRUTE_FORCE;
}

std::string mib(uint64_t bytes) {
    std::ostringstream text;
    text.precision(1);
    text << std::fixed << double(bytes) / (1024.0 * 1024.0) << " MiB";
    return text.str();
}

}  // namespace

const char* method_name(MetaballMethod method) {
    switch (method) {
        case MetaballMethod::brute_force:
            return "brute";
        case MetaballMethod::a_buffer:
            return "abuffer";
        case MetaballMethod::s_buffer:
            return "sbuffer";
    }
    return "?";
}

Result<MetaballMethod> parse_metaball_method(const std::string& text) {
    for (MetaballMethod m : {MetaballMethod::brute_force, MetaballMethod::a_buffer, MetaballMethod::s_buffer})
        if (text == method_name(m)) return m;
    return Error{"unknown metaball method '" + text + "'; use brute, abuffer or sbuffer"};
}

const char* visual_name(MetaballVisual visual) { return visual == MetaballVisual::gradient ? "gradient" : "real"; }

Result<MetaballVisual> parse_visual(const std::string& text) {
    for (MetaballVisual v : {MetaballVisual::gradient, MetaballVisual::real})
        if (text == visual_name(v)) return v;
    return Error{"unknown metaball visual '" + text +
                 "'; use gradient (normal colours) or real (reflection and refraction)"};
}

Result<bool> validate(const MetaballSettings& s) {
    if (!(s.size >= 0.5f && s.size <= 8.0f)) return out_of_range("size", s.size, "0.5..8 particle spacings");
    if (!(s.iso > 0.0f && s.iso < 1.0f)) return out_of_range("iso", s.iso, "0 < iso < 1 (a lone ball's peak is 1)");
    if (!(s.step_radii >= 0.01f && s.step_radii <= 4.0f))
        return out_of_range("step", s.step_radii, "0.01..4 particle radii");
    if (s.max_steps < 1 || s.max_steps > 1000000) return out_of_range("max_steps", s.max_steps, "1..1000000");
    if (s.bisection_steps > 32) return out_of_range("bisection_steps", s.bisection_steps, "0..32");
    if (s.recursion_depth < 1 || s.recursion_depth > METABALL_MAX_DEPTH)
        return out_of_range("recursion_depth", s.recursion_depth, "1..4");
    return true;
}

float metaball_radius(const MetaballSettings& settings, const ParticleDomain& domain) {
    return settings.size * domain.particle_spacing;
}

uint32_t list_entry_bytes(MetaballMethod method) { return method == MetaballMethod::a_buffer ? 8u : 4u; }

std::string MetaballStats::describe() const {
    std::ostringstream text;
    if (list_capacity == 0)
        text << "brute force: no lists";
    else
        text << list_entries << " list entries of " << list_capacity;
    if (overflow)
        text << ": OVERFLOW, the lists were cut short; this frame needs " << mib(list_bytes_needed)
             << " of list memory (give the renderer at least that, or make the metaballs smaller)";
    if (cut_pixels)
        text << "; " << cut_pixels << " pixels CUT SHORT by the device's loop limit (the software device ends a shader "
             << "invocation after 65535 loop iterations): their surface may be missing and the time is a lower bound; "
             << "use fewer particles per ray (lists, smaller metaballs) or a hardware GPU";
    if (dropped_particles && near_kept)
        text << "; " << dropped_particles << " particles reach the eye plane and were visited from the near list";
    else if (dropped_particles)
        text << "; " << dropped_particles << " particles reach the eye plane and are in no list (no finite billboard): "
             << "the surface near the eye is missing; move the camera back, keep them (keep_near) or use brute force";
    return text.str();
}

MetaballRenderer::MetaballRenderer(gpu::Context& ctx, const ParticleDomain& domain, uint32_t width, uint32_t height,
                                   uint32_t max_particles, uint64_t list_bytes)
    : ctx_(&ctx),
      domain_(domain),
      width_(width),
      height_(height),
      max_particles_(std::max(max_particles, 1u)),
      buffers_(ctx) {
    require_picture_size("metaball renderer", width, height);
    const uint64_t pixels = uint64_t(width) * height;
    list_bytes_ = list_bytes ? list_bytes : pixels * kDefaultListBytesPerPixel;
    list_bytes_ = std::max<uint64_t>(list_bytes_ / 8 * 8, 8);
    // The counters and node indices are 32-bit.
    if (list_bytes_ / 4 >= METABALL_NIL)
        throw Failure("metaball renderer: " + mib(list_bytes_) + " of list memory (" +
                      std::to_string(list_bytes_ / pixels) + " B per pixel at " + std::to_string(width) + "x" +
                      std::to_string(height) +
                      ") is more than its 32-bit entry indices address (16 GiB); lower "
                      "--list-bytes (list_bytes_per_pixel) or the resolution");
    params_buf_ = &buffers_.add("metaball.params", sizeof(shader::MetaballParams));
    counters_ = &buffers_.add("metaball.counters", sizeof(MetaballCounters));
    heads_ = &buffers_.add("metaball.heads", pixels * 4);
    entries_ = &buffers_.add("metaball.lists", list_bytes_);
    offsets_ = &buffers_.add("metaball.offsets", (pixels + 1) * 4);
    cursors_ = &buffers_.add("metaball.cursors", pixels * 4);
    span_ = &buffers_.add("metaball.span", pixels * 8);
    hit_ = &buffers_.add("metaball.hit", pixels * 16);
    normal_ = &buffers_.add("metaball.normal", pixels * 16);
    color_ = &buffers_.add("metaball.color", pixels * 4);
    visits_ = &buffers_.add("metaball.visits", pixels * 4);
    near_ = &buffers_.add("metaball.near", uint64_t(max_particles_) * 4);
    scan_ = gpu::PrefixSum(ctx, buffers_, uint32_t(pixels + 1), "metaball");

    bounds_ = gpu::ComputePass(ctx, {"render/metaball_bounds.comp", 3, 0, METABALL_WORKGROUP});
    lists_ = gpu::ComputePass(ctx, {"render/metaball_lists.comp", 10, sizeof(MetaballPush), METABALL_WORKGROUP});
    march_ = gpu::ComputePass(ctx, {"render/metaball_march.comp", 14, sizeof(MetaballPush), METABALL_WORKGROUP});
}

MetaballRenderer::~MetaballRenderer() = default;

void MetaballRenderer::record(VkCommandBuffer cmd, const FrameInput& frame, const ViewCamera& camera,
                              const MetaballSettings& settings, gpu::GpuTimer* timer) {
    if (auto valid = validate(settings); !valid) throw Failure(valid.error());
    frame.check("metaball renderer", max_particles_);
    const gpu::Buffer& positions = *frame.positions;
    const uint32_t count = frame.count;
    if (!(glm::length(camera.target - camera.eye) > 0.0f))
        throw Failure("metaball renderer: the camera's eye and target coincide; move the eye away");

    shader::MetaballParams& p = params_;
    p = {};
    const CameraBlock view = camera_block(camera, width_, height_);
    p.eye = view.eye;
    p.forward = view.forward;
    p.right = view.right;
    p.up = view.up;
    p.screen = {width_, height_, 0u, 0u};
    p.domain_min = glm::vec4(domain_.bounds.min, 0.0f);
    p.domain_max = glm::vec4(domain_.bounds.max, 0.0f);
    p.light_dir = kLightDirection;
    p.fluid_color = kFluidOptics;
    p.tank = make_tank_params(domain_);
    add_solids(p.tank, frame.solids);
    p.radius = metaball_radius(settings, domain_);
    p.inv_radius2 = 1.0f / (p.radius * p.radius);
    p.iso = settings.iso;
    p.particle_radius = 0.5f * domain_.particle_spacing;
    p.step = settings.step_radii * p.particle_radius;
    p.max_steps = settings.max_steps;
    p.refine_steps = settings.bisection_steps;
    p.particle_count = count;
    p.method = method_code(settings.method);
    p.visual = settings.visual == MetaballVisual::gradient ? METABALL_GRADIENT : METABALL_REAL;
    p.recursion_depth = settings.recursion_depth;
    p.list_capacity = uint32_t(list_capacity(settings.method));
    p.flags = settings.keep_near ? METABALL_KEEP_NEAR : 0u;
    keep_near_ = settings.keep_near;
    gpu::record_upload(*ctx_, cmd, *params_buf_, &p, sizeof(p));

    const uint32_t pixels = width_ * height_;
    const uint32_t particles = std::max(count, 1u);
    const gpu::Bindings list_buffers{{"params", params_buf_}, {"positions", &positions}, {"counters", counters_},
                                     {"heads", heads_},       {"nodes", entries_},       {"offsets", offsets_},
                                     {"cursors", cursors_},   {"ids", entries_},         {"span", span_},
                                     {"near_ids", near_}};
    {
        gpu::GpuScope scope(timer, cmd, "metaball_bounds");
        MetaballCounters init{};
        init.bounds_min_x = init.bounds_min_y = init.bounds_min_z = 0xffffffffu;
        gpu::record_upload(*ctx_, cmd, *counters_, &init, sizeof(init));
        gpu::dispatch(*ctx_, cmd, bounds_, particles,
                      {{"params", params_buf_}, {"positions", &positions}, {"counters", counters_}});
    }
    if (settings.method != MetaballMethod::brute_force) {
        gpu::GpuScope scope(timer, cmd, "metaball_lists");
        gpu::fill(*ctx_, cmd, *span_, 0u);  // both keys 0: an empty list
        if (settings.method == MetaballMethod::a_buffer) {
            gpu::fill(*ctx_, cmd, *heads_, METABALL_NIL);
            gpu::dispatch(*ctx_, cmd, lists_, particles, mode_push(METABALL_LIST_A_INSERT), list_buffers);
        } else {
            gpu::fill(*ctx_, cmd, *offsets_, 0u);
            gpu::fill(*ctx_, cmd, *cursors_, 0u);
            gpu::dispatch(*ctx_, cmd, lists_, particles, mode_push(METABALL_LIST_S_COUNT), list_buffers);
            scan_.record(cmd, *offsets_, pixels + 1);
            gpu::dispatch(*ctx_, cmd, lists_, particles, mode_push(METABALL_LIST_S_FILL), list_buffers);
        }
    }
    // Brute force visits every particle at every sample: its worst case (every ray taking its
    // max_steps and bisection, on every surface interaction of a "Real" path) is split into
    // dispatches of whole workgroups within the device's work budget. The lists' methods visit
    // a pixel's list, whose length only the GPU knows; they run whole.
    uint32_t slices = ctx_->long_pass_slices();
    if (settings.method == MetaballMethod::brute_force) {
        const double samples = double(p.max_steps + p.refine_steps) * std::max(p.recursion_depth, 1u);
        slices = std::max(slices, ctx_->dispatch_slices(double(pixels) * samples * particles));
    }
    const uint32_t groups = (pixels + METABALL_WORKGROUP - 1) / METABALL_WORKGROUP;
    const uint32_t per_slice = (groups + std::min(slices, groups) - 1) / std::min(slices, groups) * METABALL_WORKGROUP;
    for (uint32_t first = 0; first < pixels; first += per_slice) {
        gpu::GpuScope scope(timer, cmd, "metaball_march");
        MetaballPush push{};
        push.first_pixel = first;
        gpu::dispatch(*ctx_, cmd, march_, std::min(per_slice, pixels - first), push,
                      {{"params", params_buf_},
                       {"positions", &positions},
                       {"counters", counters_},
                       {"heads", heads_},
                       {"nodes", entries_},
                       {"offsets", offsets_},
                       {"ids", entries_},
                       {"span", span_},
                       {"hit", hit_},
                       {"normal", normal_},
                       {"color", color_},
                       {"visits", visits_},
                       {"near_ids", near_},
                       {"solid_nodes", &solid_nodes(frame.solids, *params_buf_)}});
    }
    whitewater_.record(
        *ctx_, cmd, frame.whitewater, width_, height_, camera, *hit_,
        {&params_.tank, params_.domain_min, params_.domain_max, &solid_nodes(frame.solids, *params_buf_)}, *color_,
        timer);
    method_ = settings.method;
}

SurfaceFrame MetaballRenderer::render(const FrameInput& frame, const ViewCamera& camera,
                                      const MetaballSettings& settings, gpu::GpuTimer* timer) {
    gpu::submit_timed(*ctx_, timer, [&](VkCommandBuffer cmd) { record(cmd, frame, camera, settings, timer); });
    return read_frame();
}

SurfaceFrame MetaballRenderer::read_frame() {
    return download_surface_frame(*ctx_, width_, height_, *hit_, *normal_, *color_);
}

MetaballStats MetaballRenderer::stats() {
    const size_t pixels = size_t(width_) * height_;
    MetaballStats s;
    const MetaballCounters counters = gpu::download_vector<MetaballCounters>(*ctx_, *counters_, 1)[0];
    if (method_ != MetaballMethod::brute_force) {
        s.dropped_particles = counters.dropped;
        s.near_kept = keep_near_;
    }
    if (method_ == MetaballMethod::a_buffer) {
        s.list_entries = counters.entries;
    } else if (method_ == MetaballMethod::s_buffer) {
        uint32_t total = 0;
        gpu::download(*ctx_, *offsets_, &total, 4, pixels * 4);
        s.list_entries = total;
    }
    if (method_ != MetaballMethod::brute_force) {
        s.list_capacity = list_capacity(method_);
        s.overflow = s.list_entries > s.list_capacity;
        s.list_bytes_needed = s.list_entries * list_entry_bytes(method_);
    }
    for (uint32_t v : gpu::download_vector<uint32_t>(*ctx_, *visits_, pixels)) {
        s.kernel_evaluations += v & 0x7fffffffu;
        s.cut_pixels += v >> 31;
    }
    for (const glm::vec4& n : gpu::download_vector<glm::vec4>(*ctx_, *normal_, pixels))
        s.field_evaluations += uint64_t(n.w);
    return s;
}

std::vector<std::vector<uint32_t>> MetaballRenderer::pixel_lists() {
    const size_t pixels = size_t(width_) * height_;
    std::vector<std::vector<uint32_t>> lists(pixels);
    if (method_ == MetaballMethod::a_buffer) {
        const uint64_t used = std::min<uint64_t>(stats().list_entries, list_capacity(method_));
        const auto heads = gpu::download_vector<uint32_t>(*ctx_, *heads_, pixels);
        const auto nodes = gpu::download_vector<glm::uvec2>(*ctx_, *entries_, used);
        for (size_t p = 0; p < pixels; ++p)
            for (uint32_t at = heads[p]; at != METABALL_NIL && at < used; at = nodes[at].y)
                lists[p].push_back(nodes[at].x);
    } else if (method_ == MetaballMethod::s_buffer) {
        const auto offsets = gpu::download_vector<uint32_t>(*ctx_, *offsets_, pixels + 1);
        const uint64_t used = std::min<uint64_t>(offsets[pixels], list_capacity(method_));
        const auto ids = gpu::download_vector<uint32_t>(*ctx_, *entries_, used);
        for (size_t p = 0; p < pixels; ++p)
            for (uint64_t k = offsets[p]; k < std::min<uint64_t>(offsets[p + 1], used); ++k) lists[p].push_back(ids[k]);
    }
    for (auto& list : lists) std::sort(list.begin(), list.end());
    return lists;
}

Box MetaballRenderer::particle_bounds() {
    const MetaballCounters c = gpu::download_vector<MetaballCounters>(*ctx_, *counters_, 1)[0];
    auto decode = [](uint32_t key) {
        const uint32_t bits = shader::float_order_bits(key);
        float f;
        std::memcpy(&f, &bits, 4);
        return f;
    };
    return {{decode(c.bounds_min_x), decode(c.bounds_min_y), decode(c.bounds_min_z)},
            {decode(c.bounds_max_x), decode(c.bounds_max_y), decode(c.bounds_max_z)}};
}

std::vector<gpu::BufferReport> MetaballRenderer::memory_report() const { return buffers_.report(); }

}  // namespace aquaform
