#include "render/surface_renderer.h"

#include <cstring>
#include <stdexcept>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"
#include "render/picture_size.h"

namespace aquaform {

namespace {

using shader::SurfacePassPush;

constexpr uint32_t kMissBits = 0xbf800000u;  // -1.0f: hit.w of a pixel without a surface

/// Evaluations a ray makes per march pass before it yields to a resume pass, on every device:
/// RAY_MARCH_EVALS_PER_PASS, scaled down where the device ends long loops
/// (DeviceInfo::loop_iteration_limit). With it a dispatch's work has a bound (rays x this x
/// kFieldVisitsPerEvaluation), which SurfaceRenderer::march_slices keeps within the device's budget.
uint32_t march_evals_per_pass(const gpu::DeviceInfo& device) {
    if (device.loop_iteration_limit == 0) return RAY_MARCH_EVALS_PER_PASS;
    return std::max<uint32_t>(1, uint32_t(uint64_t(RAY_MARCH_EVALS_PER_PASS) * device.loop_iteration_limit / 65535u));
}

/// Resume passes at most: with RAY_MARCH_EVALS_PER_PASS, 64 x 256 evaluations a ray (the
/// reference's fine steps across a deep volume); rays still marching after them are counted as cut.
constexpr uint32_t kMaxResumePasses = 64;

/// The smallest picture at which adaptive resolution is used on a GPU (issue 36). Its fixed costs
/// (the upsample over every pixel, the silhouette rays' second march with its own resume passes)
/// do not shrink with the picture, while the rays it saves do. On an H200 (docs/measurements.md)
/// it lost at 512x512 (calm: 4.1 ms against 2.8 ms at full resolution) and tied or won at
/// 2048x2048 (12.5 against 12.8 ms; 19.2 against 30.1 ms); Wu et al. (Table 1) gain from 1024^2
/// on. 1920x1080 is the smallest size the GPU check measures it at both ways. The software
/// device always uses it, so that every test and picture there exercises the mechanism; its time
/// there says little of a GPU's (0.67-1.0x the full-resolution march at 512x512 on 2026-12-02,
/// 1.0-1.5x on 2026-12-04 under load: the silhouette rays it marches again are the slowest, and
/// a SIMD group of rays lasts as long as its slowest).
constexpr uint64_t kAdaptiveResolutionMinPixels = 1920ull * 1080ull;

SurfacePassPush axis_push(uint32_t axis) {
    SurfacePassPush push{};
    push.axis = axis;
    return push;
}

}  // namespace

SurfaceRenderer::SurfaceRenderer(gpu::Context& ctx, const ParticleDomain& domain, uint32_t width, uint32_t height,
                                 uint32_t max_particles)
    : ctx_(&ctx),
      domain_(domain),
      width_(width),
      height_(height),
      max_particles_(std::max(max_particles, 1u)),
      buffers_(ctx) {
    require_picture_size("surface renderer", width, height);
    const uint64_t pixels = uint64_t(width) * height;
    const uint64_t tiles =
        uint64_t((width + SURFACE_TILE - 1) / SURFACE_TILE) * ((height + SURFACE_TILE - 1) / SURFACE_TILE);
    const uint64_t n = max_particles_;
    params_buf_ = &buffers_.add("render.params", sizeof(shader::SurfaceParams));
    class_density_ = &buffers_.add("render.class_density", n * 4);
    aggregate_ = &buffers_.add("render.aggregate", n * 4);
    depth_all_ = &buffers_.add("render.depth_all", pixels * 4);
    depth_agg_ = &buffers_.add("render.depth_agg", pixels * 4);
    depth_splash_back_ = &buffers_.add("render.depth_splash_back", pixels * 4);
    thickness_ = &buffers_.add("render.thickness", pixels * 4);
    front_class_ = &buffers_.add("render.front_class", pixels * 4);
    smooth_a_ = &buffers_.add("render.depth_smooth", pixels * 4);
    smooth_b_ = &buffers_.add("render.depth_smooth_tmp", pixels * 4);
    normal_screen_ = &buffers_.add("render.normal_screen", pixels * 16);
    tile_level_ = &buffers_.add("render.tile_level", tiles * 4);
    rays_ = &buffers_.add("render.rays", pixels * 4);
    ray_count_ = &buffers_.add("render.ray_count", 16);
    edge_rays_ = &buffers_.add("render.edge_rays", pixels * 4);
    edge_count_ = &buffers_.add("render.edge_count", 16);
    march_groups_ = &buffers_.add("render.march_groups", 16);
    hit_ = &buffers_.add("render.hit", pixels * 16);
    march_cut_ = &buffers_.add("render.march_cut", 16);
    for (int k = 0; k < 2; ++k) {
        resume_rays_[k] = &buffers_.add("render.resume_rays" + std::to_string(k), pixels * 4);
        resume_count_[k] = &buffers_.add("render.resume_count" + std::to_string(k), 16);
    }
    resume_state_ = &buffers_.add("render.resume_state", pixels * 16);
    ray_counts_ = &buffers_.add("render.ray_counts", pixels * 8);
    blend_weights_ = &buffers_.add("render.blend_weights", pixels * 8);
    normal_ = &buffers_.add("render.normal", pixels * 16);
    normal_tmp_ = &buffers_.add("render.normal_tmp", pixels * 16);
    spray_ = &buffers_.add("render.spray", pixels * 4);
    color_ = &buffers_.add("render.color", pixels * 4);
    splat_counters_ = &buffers_.add("render.splat_counters", SPLAT_COUNTERS * 4);

    const uint32_t push = sizeof(SurfacePassPush);
    gather_ = gpu::ComputePass(ctx, {"render/gather.comp", 4});
    classify_density_ = gpu::ComputePass(ctx, {"render/classify_density.comp", 7});
    mask_convolve_ = gpu::ComputePass(ctx, {"render/mask_convolve.comp", 5, push});
    mask_bound_ = gpu::ComputePass(ctx, {"render/mask_bound.comp", 6});
    mask_pack_ = gpu::ComputePass(ctx, {"render/mask_pack.comp", 4});
    for (uint32_t balanced : {0u, 1u})
        splat_[balanced] = gpu::ComputePass(ctx, {"render/splat.comp", 10, push, gpu::kDefaultLocalSize, {balanced}});
    depth_smooth_ = gpu::ComputePass(ctx, {"render/depth_smooth.comp", 3, push});
    screen_normals_ = gpu::ComputePass(ctx, {"render/screen_normals.comp", 3});
    tiles_ = gpu::ComputePass(ctx, {"render/tiles.comp", 5, 0, 64});
    set_march_lanes(default_march_lanes(ctx.info()));
    upsample_ = gpu::ComputePass(ctx, {"render/upsample.comp", 7});
    normal_filter_ = gpu::ComputePass(ctx, {"render/normal_filter.comp", 4, push});
    compose_ = gpu::ComputePass(ctx, {"render/compose.comp", 7});
    // The default grid now, so that a scene whose grid cannot fit fails at construction.
    prepare_grid(render_radius(SurfaceSettings{}, domain));
}

SurfaceRenderer::~SurfaceRenderer() = default;

// A new radius re-makes the grid's geometry and the mask's buffers, also inside a recording
// (the render grid's table is uploaded there); the old buffers are freed at once, so a frame
// with another radius than the one recorded before it in the same submission must get a
// submission of its own.
void SurfaceRenderer::prepare_grid(float radius) {
    if (mask_buffers_ && geometry_.cell_size == radius) return;
    auto geometry = grid_for_domain(domain_.bounds.min, domain_.bounds.max, radius);
    if (!geometry) throw resource_failure("surface renderer: " + geometry.error());
    own_grid_.reset();
    own_buffers_.reset();
    kernels_.reset();
    kernel_buffers_.reset();
    mask_buffers_ = std::make_unique<gpu::BufferSet>(*ctx_);
    geometry_ = geometry.value();
    kernel_buffers_ = std::make_unique<gpu::BufferSet>(*ctx_);
    kernels_ = std::make_unique<SurfaceKernels>(*ctx_, *kernel_buffers_, geometry_, max_particles_, "render");
    const uint64_t cells = geometry_.cell_count();
    auto words = [](uint32_t cells_on_axis, uint32_t block) { return uint64_t((cells_on_axis + block - 1) / block); };
    const uint64_t wx = words(geometry_.dims.x, MASK_BLOCK_X), wy = words(geometry_.dims.y, MASK_BLOCK_Y),
                   wz = words(geometry_.dims.z, MASK_BLOCK_Z);
    conv_a_ = &mask_buffers_->add("render.mask_counts", cells * 4);
    conv_b_ = &mask_buffers_->add("render.mask_counts_tmp", cells * 4);
    mask_ = &mask_buffers_->add("render.mask", wx * wy * wz * 4);
    coarse_ = &mask_buffers_->add("render.mask_coarse",
                                  words(wx, MASK_COARSE) * words(wy, MASK_COARSE) * words(wz, MASK_COARSE) * 4);
}

// Made on first use: a renderer that reads the solver's grid in place never needs it.
void SurfaceRenderer::prepare_own_grid() {
    if (own_grid_) return;
    own_buffers_ = std::make_unique<gpu::BufferSet>(*ctx_);
    own_grid_ = std::make_unique<NeighborGrid>(*ctx_, *own_buffers_, geometry_, max_particles_, "render.grid");
    own_sorted_ = &own_buffers_->add("render.sorted", uint64_t(max_particles_) * 16);
}

bool SurfaceRenderer::reads_in_place() const {
    const GridGeometry* shared = shared_grid_ ? &shared_grid_->geometry() : nullptr;
    return shared && shared->cell_size == geometry_.cell_size && shared->origin == geometry_.origin &&
           shared->dims == geometry_.dims;
}

void SurfaceRenderer::record_mask(VkCommandBuffer cmd, bool tight) {
    gpu::fill(*ctx_, cmd, *coarse_, 0u);
    const uint32_t cells = geometry_.cell_count();
    if (tight) {
        gpu::dispatch(*ctx_, cmd, mask_bound_, cells,
                      {{"params", params_buf_},
                       {"sorted", field_sorted_},
                       {"cell_rank", field_cell_rank_},
                       {"cell_start", field_cell_start_},
                       {"shape", field_shape_},
                       {"dst", conv_a_}});
    } else {
        // counts (from the grid) -x-> a -y-> b -z-> a
        gpu::dispatch(*ctx_, cmd, mask_convolve_, cells, axis_push(0),
                      {{"params", params_buf_},
                       {"cell_rank", field_cell_rank_},
                       {"cell_start", field_cell_start_},
                       {"src", conv_b_},
                       {"dst", conv_a_}});
        gpu::dispatch(*ctx_, cmd, mask_convolve_, cells, axis_push(1),
                      {{"params", params_buf_},
                       {"cell_rank", field_cell_rank_},
                       {"cell_start", field_cell_start_},
                       {"src", conv_a_},
                       {"dst", conv_b_}});
        gpu::dispatch(*ctx_, cmd, mask_convolve_, cells, axis_push(2),
                      {{"params", params_buf_},
                       {"cell_rank", field_cell_rank_},
                       {"cell_start", field_cell_start_},
                       {"src", conv_b_},
                       {"dst", conv_a_}});
    }
    gpu::dispatch(*ctx_, cmd, mask_pack_, params_.mask_dims.w,
                  {{"params", params_buf_}, {"counts", conv_a_}, {"mask", mask_}, {"coarse", coarse_}});
}

void SurfaceRenderer::record(VkCommandBuffer cmd, const FrameInput& frame, const ViewCamera& camera,
                             const SurfaceSettings& settings, gpu::GpuTimer* timer) {
    if (auto valid = validate(settings); !valid) throw Failure(valid.error());
    frame.check("surface renderer", max_particles_);
    const gpu::Buffer& positions = *frame.positions;
    const uint32_t count = frame.count;
    shared_grid_ = frame.grid;
    if (!(glm::length(camera.target - camera.eye) > 0.0f))
        throw Failure("surface renderer: the camera's eye and target coincide; move the eye away");
    prepare_grid(render_radius(settings, domain_));
    count_ = count;
    params_ = make_surface_params(settings, domain_, geometry_, camera, width_, height_, count);
    add_solids(params_.tank, frame.solids);
    resolution_note_.clear();
    if ((params_.flags & SURFACE_ADAPTIVE_RES) && !adaptive_resolution_pays()) {
        params_.flags &= ~SURFACE_ADAPTIVE_RES;
        resolution_note_ = "full resolution: adaptive resolution pays on a GPU from " +
                           std::to_string(kAdaptiveResolutionMinPixels) + " pixels (1920x1080) on; this picture has " +
                           std::to_string(uint64_t(width_) * height_);
    }
    gpu::record_upload(*ctx_, cmd, *params_buf_, &params_, sizeof(params_));

    const uint32_t pixels = width_ * height_;
    const bool adaptive = params_.method == SURFACE_METHOD_ADAPTIVE;
    const uint32_t particles = std::max(count, 1u);  // empty dispatches are fine; keep the barrier
    if (reads_in_place()) {
        // The solver's frame grid: the particles are sorted by it and each lies in its cell.
        particles_ = &positions;
        cell_rank_ = &shared_grid_->cell_rank();
        cell_start_ = &shared_grid_->cell_start();
    } else {
        gpu::GpuScope scope(timer, cmd, "render_grid");
        prepare_own_grid();
        own_grid_->build(cmd, positions, count, nullptr);
        gpu::dispatch(*ctx_, cmd, gather_, particles,
                      {{"params", params_buf_},
                       {"positions", &positions},
                       {"order", &own_grid_->order()},
                       {"sorted", own_sorted_}});
        particles_ = own_sorted_;
        cell_rank_ = &own_grid_->cell_rank();
        cell_start_ = &own_grid_->cell_start();
    }
    const bool anisotropic_field = params_.flags & SURFACE_ANISOTROPIC_FIELD;
    const bool classify = adaptive || (params_.shading & SHADE_SPRAY);
    if (classify || anisotropic_field) {
        gpu::GpuScope scope(timer, cmd, "render_classify");
        if ((params_.flags & SURFACE_ANISOTROPIC) || anisotropic_field)
            kernels_->record_shapes(cmd, *params_buf_, *particles_, *cell_rank_, *cell_start_, particles);
        if (classify)
            gpu::dispatch(*ctx_, cmd, classify_density_, particles,
                          {{"params", params_buf_},
                           {"sorted", particles_},
                           {"cell_rank", cell_rank_},
                           {"cell_start", cell_start_},
                           {"shape", &kernels_->particle_shapes()},
                           {"class_density", class_density_},
                           {"aggregate", aggregate_}});
    }
    if (!classify) gpu::fill(*ctx_, cmd, *aggregate_, 0u);
    field_sorted_ = particles_;
    field_shape_ = &kernels_->particle_shapes();  // unread by the isotropic field
    field_aggregate_ = aggregate_;
    field_class_density_ = class_density_;
    field_cell_rank_ = cell_rank_;
    field_cell_start_ = cell_start_;
    if (anisotropic_field) {
        gpu::GpuScope scope(timer, cmd, "render_kernels");
        kernels_->record_kernels(cmd, *params_buf_, *aggregate_, *class_density_, count);
        field_sorted_ = &kernels_->centres();
        field_shape_ = &kernels_->shapes();
        field_aggregate_ = &kernels_->aggregate();
        field_class_density_ = &kernels_->class_density();
        field_cell_rank_ = &kernels_->cell_rank();
        field_cell_start_ = &kernels_->cell_start();
    }
    if (params_.flags & SURFACE_USE_MASK) {
        gpu::GpuScope scope(timer, cmd, "render_mask");
        // The reference's mask is exact either way; the tight bound is the smaller.
        record_mask(cmd, settings.tight_mask || params_.method == SURFACE_METHOD_REFERENCE);
    }
    {
        gpu::GpuScope scope(timer, cmd, "render_splat");
        gpu::fill(*ctx_, cmd, *depth_all_, DEPTH_EMPTY);
        gpu::fill(*ctx_, cmd, *depth_agg_, DEPTH_EMPTY);
        gpu::fill(*ctx_, cmd, *depth_splash_back_, 0u);
        gpu::fill(*ctx_, cmd, *thickness_, 0u);
        gpu::fill(*ctx_, cmd, *front_class_, 0u);
        gpu::fill(*ctx_, cmd, *splat_counters_, 0u);
    }
    const gpu::Bindings splat_buffers{{"params", params_buf_},
                                      {"sorted", field_sorted_},
                                      {"shape", field_shape_},
                                      {"aggregate", field_aggregate_},
                                      {"depth_all", depth_all_},
                                      {"depth_agg", depth_agg_},
                                      {"thickness", thickness_},
                                      {"front_class", front_class_},
                                      {"depth_splash_back", depth_splash_back_},
                                      {"splat_counters", splat_counters_}};
    // The splat is a long pass too: where the caller shares the queue (gpu::Context::QueueSharing)
    // it runs in slices of particles, each its own timed scope, so that the queue can be cut
    // between them (as in record_first_march).
    // Slices are whole workgroups: the shader only checks the particle count, so a slice's
    // rounded-up last group must not reach into the next slice (it would splat twice).
    const uint32_t slices = ctx_->long_pass_slices(), group = splat_pass().desc().local_size;
    const uint32_t per_slice = ((particles + slices - 1) / slices + group - 1) / group * group;
    for (uint32_t first = 0; first < particles; first += per_slice) {
        gpu::GpuScope scope(timer, cmd, "render_splat");
        SurfacePassPush push = axis_push(0);
        push.first = first;
        gpu::dispatch(*ctx_, cmd, splat_pass(), std::min(per_slice, particles - first), push, splat_buffers);
    }
    if ((params_.flags & SURFACE_USE_SKIP) && !(params_.flags & SURFACE_WU_SKIP)) {  // the exact skip's D_splash_back
        gpu::GpuScope scope(timer, cmd, "render_splat");
        gpu::dispatch(*ctx_, cmd, splat_pass(), particles, axis_push(2), splat_buffers);
    }
    if (adaptive && diagnostics_) {
        gpu::GpuScope scope(timer, cmd, "render_splat");
        gpu::dispatch(*ctx_, cmd, splat_pass(), particles, axis_push(1), splat_buffers);
    }
    record_screen_passes(cmd, timer);
    record_first_march(cmd, timer);
    {
        gpu::GpuScope scope(timer, cmd, "render_march");
        record_resumes(cmd);
    }
    if (params_.flags & SURFACE_ADAPTIVE_RES) {
        gpu::GpuScope scope(timer, cmd, "render_upsample");
        gpu::fill(*ctx_, cmd, *edge_count_, 0u);
        gpu::dispatch(*ctx_, cmd, upsample_, pixels,
                      {{"params", params_buf_},
                       {"tile_level", tile_level_},
                       {"hit", hit_},
                       {"normal", normal_},
                       {"edge_rays", edge_rays_},
                       {"edge_count", edge_count_},
                       {"spray", spray_}});
        record_march(cmd, *edge_rays_, *edge_count_);
    }
    if ((params_.flags & SURFACE_XIAO_NORMALS) || params_.normal_smoothing > 0.0f) {
        gpu::GpuScope scope(timer, cmd, "render_normal_filter");
        gpu::dispatch(*ctx_, cmd, normal_filter_, pixels, axis_push(0),
                      {{"params", params_buf_}, {"hit", hit_}, {"src", normal_}, {"dst", normal_tmp_}});
        gpu::dispatch(*ctx_, cmd, normal_filter_, pixels, axis_push(1),
                      {{"params", params_buf_}, {"hit", hit_}, {"src", normal_tmp_}, {"dst", normal_}});
    }
    {
        gpu::GpuScope scope(timer, cmd, "render_compose");
        gpu::dispatch(*ctx_, cmd, compose_, pixels,
                      {{"params", params_buf_},
                       {"hit", hit_},
                       {"normal", normal_},
                       {"thickness", thickness_},
                       {"color", color_},
                       {"spray", spray_},
                       {"solid_nodes", &solid_nodes(frame.solids, *params_buf_)}});
    }
    whitewater_.record(
        *ctx_, cmd, frame.whitewater, width_, height_, camera, *hit_,
        {&params_.tank, params_.domain_min, params_.domain_max, &solid_nodes(frame.solids, *params_buf_)}, *color_,
        timer);
}

void SurfaceRenderer::record_first_march(VkCommandBuffer cmd, gpu::GpuTimer* timer) {
    {
        gpu::GpuScope scope(timer, cmd, "render_march");
        gpu::fill(*ctx_, cmd, *hit_, kMissBits);
        gpu::fill(*ctx_, cmd, *normal_, 0u);
        gpu::fill(*ctx_, cmd, *ray_counts_, 0u);
        gpu::fill(*ctx_, cmd, *blend_weights_, kMissBits);
        gpu::fill(*ctx_, cmd, *march_cut_, 0u);
        gpu::fill(*ctx_, cmd, *resume_count_[0], 0u);
    }
    // The list's length is only known on the GPU: the slices cover a list as long as the longest
    // (one ray per pixel), and those past its end find no rays.
    const uint32_t pixels = width_ * height_, chunk = march_chunk();
    for (uint32_t first = 0; first < pixels; first += chunk) {
        gpu::GpuScope scope(timer, cmd, "render_march");  // the timer adds the slices up
        dispatch_march(cmd, rays_, *ray_count_, 0, 0, first, chunk);
    }
}

uint32_t default_march_lanes(const gpu::DeviceInfo& device) {
    // The software device marches 8 rays side by side in its SIMD lanes already, and loads have
    // no latency to hide there: a lane per ray. On a GPU, 4 lanes a ray (issue 36; the H200's
    // figures with 1 lane are in docs/measurements.md, `bench render --march-lanes` measures others),
    // where its subgroups can share them (DeviceInfo::subgroup_size is 1 without compute shuffles).
    constexpr uint32_t kGpuLanes = 4;
    const bool shares = device.subgroup_size % kGpuLanes == 0;
    return device.type == VK_PHYSICAL_DEVICE_TYPE_CPU || !shares ? 1u : kGpuLanes;
}

void SurfaceRenderer::set_march_lanes(uint32_t lanes) {
    if (lanes == 0 || lanes > kMaxMarchLanes || (lanes & (lanes - 1)) != 0)
        throw Failure("surface renderer: " + std::to_string(lanes) + " march lanes a ray; use 1, 2, 4 or 8");
    if (lanes > 1 && ctx_->info().subgroup_size % lanes != 0)
        throw Failure("surface renderer: " + std::to_string(lanes) +
                      " march lanes a ray do not divide the device's subgroup of " +
                      std::to_string(ctx_->info().subgroup_size) + " lanes; use fewer");
    if (lanes == march_lanes_ && ray_march_[0].pipeline()) return;
    march_lanes_ = lanes;
    const uint32_t push = sizeof(SurfacePassPush);
    for (uint32_t anisotropic : {0u, 1u})
        ray_march_[anisotropic] =
            gpu::ComputePass(*ctx_, {"render/ray_march.comp", 23, push, RAY_MARCH_WORKGROUP, {anisotropic, lanes}});
    ray_args_ = gpu::ComputePass(*ctx_, {"render/ray_args.comp", 2, 0, 1, {RAY_MARCH_WORKGROUP / lanes}});
}

bool adaptive_resolution_pays(VkPhysicalDeviceType device, uint32_t width, uint32_t height) {
    return device == VK_PHYSICAL_DEVICE_TYPE_CPU || uint64_t(width) * height >= kAdaptiveResolutionMinPixels;
}

bool SurfaceRenderer::adaptive_resolution_pays() const {
    return aquaform::adaptive_resolution_pays(ctx_->info().type, width_, height_);
}

uint32_t SurfaceRenderer::evals_per_pass() const {
    return std::min(march_evals_per_pass(ctx_->info()), std::max(params_.max_steps, 1u));
}

uint32_t SurfaceRenderer::march_slices() const {
    const double worst = double(width_) * height_ * evals_per_pass() * kFieldVisitsPerEvaluation;
    return ctx_->dispatch_slices(worst);
}

uint32_t SurfaceRenderer::march_chunk() const {
    // Contiguous shares of the list, not every slices-th ray: a short list (a GPU's usual frame)
    // then fills the first slices with rays side by side, and the rest find none at once. Spread
    // over every slice, an H200 marched a few thousand scattered rays a dispatch, each dispatch
    // as long as its slowest ray, and the march took time in proportion to the pixels (86 ms at
    // 2048x2048 for 0.6M rays or 1.5M alike). A whole number of workgroups, so that no thread of
    // a slice reaches the next one's rays.
    const uint32_t pixels = width_ * height_, slices = march_slices();
    if (slices == 1) return pixels;
    const uint32_t local = march_pass().desc().local_size / march_lanes_;  // rays a workgroup marches
    return std::max(local, pixels / slices / local * local);
}

uint32_t SurfaceRenderer::resume_passes() const {
    const uint32_t e = evals_per_pass();
    const uint64_t steps = std::max(params_.max_steps, 1u);
    const uint32_t needed = uint32_t(std::min<uint64_t>((steps + e - 1) / e - 1, kMaxResumePasses));
    // A device that ends long loops may cut a ray within its pass's budget (bisection and normal
    // included): those rays always get resume passes.
    return ctx_->info().loop_iteration_limit ? std::max(needed, kResumePasses) : needed;
}

void SurfaceRenderer::dispatch_march_list(VkCommandBuffer cmd, const gpu::Buffer* rays, const gpu::Buffer& ray_count,
                                          uint32_t mode, int resume_out) {
    // The list's length is only known on the GPU: the slices cover a list as long as the longest
    // (one ray per pixel) in contiguous shares (march_chunk).
    const uint32_t pixels = width_ * height_;
    if (march_slices() == 1) return dispatch_march(cmd, rays, ray_count, mode, resume_out);
    const uint32_t chunk = march_chunk();
    for (uint32_t first = 0; first < pixels; first += chunk)
        dispatch_march(cmd, rays, ray_count, mode, resume_out, first, chunk);
}

void SurfaceRenderer::dispatch_march(VkCommandBuffer cmd, const gpu::Buffer* rays, const gpu::Buffer& ray_count,
                                     uint32_t mode, int resume_out, uint32_t first, uint32_t threads) {
    const gpu::Bindings buffers{{"params", params_buf_},
                                {"sorted", field_sorted_},
                                {"shape", field_shape_},
                                {"cell_rank", field_cell_rank_},
                                {"cell_start", field_cell_start_},
                                {"mask", mask_},
                                {"coarse", coarse_},
                                {"depth_all", depth_all_},
                                {"depth_agg", depth_agg_},
                                {"normal_screen", normal_screen_},
                                {"rays", rays},
                                {"ray_count", &ray_count},
                                {"hit", hit_},
                                {"normal", normal_},
                                {"march_cut", march_cut_},
                                {"resume_rays", resume_rays_[resume_out]},
                                {"resume_count", resume_count_[resume_out]},
                                {"resume_state", resume_state_},
                                {"ray_counts", ray_counts_},
                                {"blend_weights", blend_weights_},
                                {"depth_splash_back", depth_splash_back_},
                                {"class_density", field_class_density_},
                                {"spray", spray_}};
    SurfacePassPush push = axis_push(mode);
    push.first = first;
    push.evals_per_pass = resume_passes() > 0 ? evals_per_pass() : 0u;  // 0: no pass follows, count cut rays
    if (threads > 0) {
        gpu::dispatch(*ctx_, cmd, march_pass(), threads * march_lanes_, push, buffers);
        return;
    }
    gpu::dispatch(*ctx_, cmd, ray_args_, 1, {{"ray_count", &ray_count}, {"group_counts", march_groups_}});
    gpu::dispatch_indirect(*ctx_, cmd, march_pass(), *march_groups_, push, buffers);
}

void SurfaceRenderer::record_march(VkCommandBuffer cmd, const gpu::Buffer& rays, const gpu::Buffer& ray_count) {
    gpu::fill(*ctx_, cmd, *resume_count_[0], 0u);
    dispatch_march_list(cmd, &rays, ray_count, 0, 0);
    record_resumes(cmd);
}

void SurfaceRenderer::record_resumes(VkCommandBuffer cmd) {
    // The rays cut short (list 0) are marched again, each pass with a fresh budget, ping-ponging
    // between the two lists; the last pass counts what is still cut. A pass with no rays left
    // dispatches no workgroups.
    const uint32_t passes = resume_passes();
    for (uint32_t pass = 1; pass <= passes; ++pass) {
        const int in = int((pass + 1) % 2), out = int(pass % 2);
        gpu::fill(*ctx_, cmd, *resume_count_[out], 0u);
        dispatch_march_list(cmd, resume_rays_[in], *resume_count_[in], pass == passes ? 2u : 1u, out);
    }
}

void SurfaceRenderer::record_screen_passes(VkCommandBuffer cmd, gpu::GpuTimer* timer) {
    const uint32_t pixels = width_ * height_;
    if (params_.flags & SURFACE_BLEND_NORMALS) {
        {
            gpu::GpuScope scope(timer, cmd, "render_smooth");
            gpu::dispatch(*ctx_, cmd, depth_smooth_, pixels, axis_push(0),
                          {{"params", params_buf_}, {"src", depth_all_}, {"dst", smooth_b_}});
            gpu::dispatch(*ctx_, cmd, depth_smooth_, pixels, axis_push(1),
                          {{"params", params_buf_}, {"src", smooth_b_}, {"dst", smooth_a_}});
        }
        gpu::GpuScope scope(timer, cmd, "render_screen_normals");
        gpu::dispatch(*ctx_, cmd, screen_normals_, pixels,
                      {{"params", params_buf_}, {"depth_smooth", smooth_a_}, {"normal_screen", normal_screen_}});
    }
    gpu::GpuScope scope(timer, cmd, "render_tiles");
    gpu::fill(*ctx_, cmd, *ray_count_, 0u);
    gpu::dispatch(*ctx_, cmd, tiles_, params_.screen.z * params_.screen.w,
                  {{"params", params_buf_},
                   {"depth_all", depth_all_},
                   {"tile_level", tile_level_},
                   {"rays", rays_},
                   {"ray_count", ray_count_}});
}

SurfaceFrame SurfaceRenderer::render(const FrameInput& frame, const ViewCamera& camera, const SurfaceSettings& settings,
                                     gpu::GpuTimer* timer) {
    gpu::submit_timed(*ctx_, timer, [&](VkCommandBuffer cmd) { record(cmd, frame, camera, settings, timer); });
    return read_frame();
}

SurfaceFrame SurfaceRenderer::read_frame() {
    return download_surface_frame(*ctx_, width_, height_, *hit_, *normal_, *color_);
}

std::vector<uint32_t> SurfaceRenderer::tile_levels() {
    return gpu::download_vector<uint32_t>(*ctx_, *tile_level_, size_t(params_.screen.z) * params_.screen.w);
}
std::vector<uint32_t> SurfaceRenderer::front_classes() {
    return gpu::download_vector<uint32_t>(*ctx_, *front_class_, size_t(width_) * height_);
}
std::vector<float> SurfaceRenderer::depth_all() {
    return gpu::download_vector<float>(*ctx_, *depth_all_, size_t(width_) * height_);
}
std::vector<float> SurfaceRenderer::depth_splash_back() {
    return gpu::download_vector<float>(*ctx_, *depth_splash_back_, size_t(width_) * height_);
}
std::vector<float> SurfaceRenderer::thickness() {
    const auto micrometres = gpu::download_vector<uint32_t>(*ctx_, *thickness_, size_t(width_) * height_);
    std::vector<float> metres(micrometres.size());
    for (size_t i = 0; i < metres.size(); ++i) metres[i] = float(micrometres[i]) * 1.0e-6f;
    return metres;
}
std::vector<float> SurfaceRenderer::depth_agg() {
    return gpu::download_vector<float>(*ctx_, *depth_agg_, size_t(width_) * height_);
}
std::vector<glm::vec4> SurfaceRenderer::sorted_positions() {
    return particles_ ? gpu::download_vector<glm::vec4>(*ctx_, *particles_, count_) : std::vector<glm::vec4>{};
}
std::vector<glm::vec4> SurfaceRenderer::kernel_centres() {
    if (!(params_.flags & SURFACE_ANISOTROPIC_FIELD)) return {};
    return gpu::download_vector<glm::vec4>(*ctx_, kernels_->centres(), count_);
}
std::vector<glm::vec4> SurfaceRenderer::kernel_shapes() {
    if (!(params_.flags & SURFACE_ANISOTROPIC_FIELD)) return {};
    return gpu::download_vector<glm::vec4>(*ctx_, kernels_->shapes(), size_t(count_) * 3);
}
std::vector<uint32_t> SurfaceRenderer::aggregate_flags() {
    return gpu::download_vector<uint32_t>(*ctx_, *aggregate_, count_);
}
std::vector<float> SurfaceRenderer::class_densities() {
    return gpu::download_vector<float>(*ctx_, *class_density_, count_);
}
std::vector<uint32_t> SurfaceRenderer::mask_words() {
    return gpu::download_vector<uint32_t>(*ctx_, *mask_, params_.mask_dims.w);
}
std::vector<uint32_t> SurfaceRenderer::coarse_words() {
    return gpu::download_vector<uint32_t>(*ctx_, *coarse_, params_.coarse_dims.w);
}
std::vector<RayCounts> SurfaceRenderer::ray_counts() {
    const auto packed = gpu::download_vector<glm::uvec2>(*ctx_, *ray_counts_, size_t(width_) * height_);
    std::vector<RayCounts> counts(packed.size());
    for (size_t i = 0; i < packed.size(); ++i)
        counts[i] = {packed[i].x, packed[i].y & ((1u << RAY_COUNT_BISECTION_BITS) - 1u),
                     packed[i].y >> RAY_COUNT_BISECTION_BITS};
    return counts;
}
std::vector<glm::vec2> SurfaceRenderer::blend_weights() {
    return gpu::download_vector<glm::vec2>(*ctx_, *blend_weights_, size_t(width_) * height_);
}
uint32_t SurfaceRenderer::cut_rays() { return gpu::download_vector<uint32_t>(*ctx_, *march_cut_, 1)[0]; }

SpriteCounts SurfaceRenderer::sprite_counts() {
    const auto c = gpu::download_vector<uint32_t>(*ctx_, *splat_counters_, SPLAT_COUNTERS);
    return {c[SPLAT_COUNTER_SPRITES],           c[SPLAT_COUNTER_PIXELS],
            c[SPLAT_COUNTER_COVERED],           c[SPLAT_COUNTER_DEPTH_ATOMICS],
            c[SPLAT_COUNTER_THICKNESS_ATOMICS], c[SPLAT_COUNTER_LONGEST_WALK],
            c[SPLAT_COUNTER_LARGEST_FOOTPRINT]};
}

uint32_t SurfaceRenderer::rays_cast() {
    uint32_t rays = gpu::download_vector<uint32_t>(*ctx_, *ray_count_, 1)[0];
    if (params_.flags & SURFACE_ADAPTIVE_RES) rays += gpu::download_vector<uint32_t>(*ctx_, *edge_count_, 1)[0];
    return rays;
}

std::vector<gpu::BufferReport> SurfaceRenderer::memory_report() const {
    auto report = buffers_.report();
    for (const gpu::BufferSet* set : {mask_buffers_.get(), own_buffers_.get(), kernel_buffers_.get()})
        if (set)
            for (auto& entry : set->report()) report.push_back(entry);
    if (kernels_)
        for (auto& entry : kernels_->kernel_memory_report()) report.push_back(entry);
    return report;
}

}  // namespace aquaform
