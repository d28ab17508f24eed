#include "control/raster_placement.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>

#include "core/error.h"
#include "gpu/barriers.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "shaders/shared/control/raster_layout.h"

namespace aquaform::control {

namespace {

using Clock = std::chrono::steady_clock;

double milliseconds_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// Lattice columns beyond this are refused: the layer lists alone would need 8.6 GB.
constexpr double kMaxPixels = double(1u << 26);

/// The most threads of `workgroup` one dispatch along x can run on this device.
double max_threads(const gpu::Context& ctx, uint32_t workgroup) {
    return double(ctx.limits().maxComputeWorkGroupCount[0]) * workgroup;
}

constexpr VkDeviceSize kLayerBytes = 2 * sizeof(float);         // (z, step)
constexpr VkDeviceSize kTriangleBytes = 3 * sizeof(glm::vec4);  // its corners

/// raster_fill.comp counts each column's points (emit 0) or writes them at the column's offset (emit 1).
gpu::ComputePassDesc raster_fill(uint32_t emit) {
    return {"control/raster_fill.comp", 5, sizeof(shader::RasterPush), RASTER_FILL_WORKGROUP, {emit}};
}

/// The columns (i, j) of the lattice origin + spacing * (i, j, .) under the xy bounds, one of slack
/// per side: the exact edge test decides, so an extra empty column costs nothing but a thread.
glm::ivec4 pixel_rect(const Box& bounds, float spacing, glm::vec3 origin, double max_pixels) {
    const glm::dvec2 low = glm::floor((glm::dvec2(bounds.min) - glm::dvec2(origin)) / double(spacing)) - 1.0;
    const glm::dvec2 high = glm::ceil((glm::dvec2(bounds.max) - glm::dvec2(origin)) / double(spacing)) + 1.0;
    const glm::dvec2 size = high - low + 1.0;
    const double limit = double(1 << 30);
    if (!(std::abs(low.x) < limit && std::abs(low.y) < limit && std::abs(high.x) < limit && std::abs(high.y) < limit &&
          size.x * size.y <= max_pixels))
        throw Failure("raster placement: the mesh spans " + std::to_string(size.x) + " x " + std::to_string(size.y) +
                      " lattice columns at spacing " + std::to_string(spacing) + " (at most " +
                      std::to_string(uint64_t(max_pixels)) +
                      "); use a larger spacing or a lattice origin nearer the mesh");
    return glm::ivec4(int(low.x), int(low.y), int(size.x), int(size.y));
}

}  // namespace

RasterPlacer::RasterPlacer(gpu::Context& ctx, uint32_t max_triangles, uint32_t max_points, uint32_t max_pixels)
    : ctx_(&ctx),
      layers_pass_(ctx, {"control/raster_layers.comp", 3, sizeof(shader::RasterPush), RASTER_LAYERS_WORKGROUP}),
      count_pass_(ctx, raster_fill(0u)),
      emit_pass_(ctx, raster_fill(1u)),
      timer_(ctx, 4) {
    reserve_triangles(max_triangles * kTriangleBytes);
    grow(layer_count_, "raster.layer_count", VkDeviceSize(max_pixels) * sizeof(uint32_t), gpu::MemoryUse::device);
    grow(layers_, "raster.layers", VkDeviceSize(max_pixels) * RASTER_MAX_LAYERS * kLayerBytes, gpu::MemoryUse::device);
    grow(counters_, "raster.counters", RASTER_COUNTERS * sizeof(uint32_t), gpu::MemoryUse::device);
    grow(counters_readback_, "raster.counters_readback", RASTER_COUNTERS * sizeof(uint32_t), gpu::MemoryUse::host);
    set_point_capacity(max_points);
    reserve_columns(max_pixels);
}

RasterPlacer::~RasterPlacer() {
    for (gpu::Buffer* buffer : own_buffers(*this)) gpu::destroy_buffer(*ctx_, *buffer);
}

void RasterPlacer::grow(gpu::Buffer& buffer, const char* name, VkDeviceSize bytes, gpu::MemoryUse use) {
    if (buffer.buffer && buffer.size >= bytes) return;
    gpu::destroy_buffer(*ctx_, buffer);
    buffer = gpu::create_buffer(*ctx_, name, bytes, use);
}

void RasterPlacer::reserve_triangles(VkDeviceSize corner_bytes) {
    grow(triangles_staging_, "raster.triangles_staging", corner_bytes, gpu::MemoryUse::host);
    grow(triangles_, "raster.triangles", corner_bytes, gpu::MemoryUse::device);
}

void RasterPlacer::set_point_capacity(uint32_t max_points) {
    if (points_.buffer && max_points <= point_capacity_) return;
    point_capacity_ = max_points;
    grow(points_, "raster.points", VkDeviceSize(max_points) * sizeof(glm::vec4), gpu::MemoryUse::device);
}

void RasterPlacer::reserve_columns(uint32_t pixels) {
    if (column_buffers_ && pixels <= column_capacity_) return;
    const uint32_t entries = std::max(pixels, 1u) + 1;  // + 1: the scan's end is the total
    scan_ = gpu::PrefixSum();
    column_offsets_ = nullptr;
    column_buffers_ = std::make_unique<gpu::BufferSet>(*ctx_);
    column_offsets_ = &column_buffers_->add("raster.column_offsets", VkDeviceSize(entries) * sizeof(uint32_t));
    scan_ = gpu::PrefixSum(*ctx_, *column_buffers_, entries, "raster");
    column_capacity_ = entries - 1;
}

std::vector<gpu::BufferReport> RasterPlacer::memory() const {
    std::vector<gpu::BufferReport> report;
    for (const gpu::Buffer* buffer : own_buffers(*this)) report.push_back({buffer->name, buffer->size});
    for (const gpu::BufferReport& entry : column_buffers_->report()) report.push_back(entry);
    return report;
}

void RasterPlacer::record_placement(VkCommandBuffer cmd, const shader::RasterPush& push, VkDeviceSize corner_bytes,
                                    uint32_t pixels) {
    timer_.reset(cmd);
    const VkBufferCopy upload{0, 0, corner_bytes};
    gpu::copy(*ctx_, cmd, triangles_staging_, triangles_, upload);
    gpu::fill(*ctx_, cmd, layer_count_, 0, VkDeviceSize(pixels) * sizeof(uint32_t));
    gpu::fill(*ctx_, cmd, counters_, 0);
    gpu::fill(*ctx_, cmd, *column_offsets_, 0, VkDeviceSize(pixels + 1) * sizeof(uint32_t));
    {
        gpu::GpuScope scope(&timer_, cmd, "raster_layers");
        gpu::dispatch(*ctx_, cmd, layers_pass_, push.triangle_count, push,
                      {{"corners", &triangles_}, {"layer_count", &layer_count_}, {"layers", &layers_}});
    }
    // Count, scan, emit: each column writes its points at its offset in the scan, so the list is
    // in column order on every run (an atomic counter handing out slots would give the order
    // the threads ran in, and the control force's sums over the list would differ run to run).
    const gpu::Bindings fill_buffers = {{"layer_count", &layer_count_},
                                        {"layers", &layers_},
                                        {"counters", &counters_},
                                        {"points", &points_},
                                        {"column_offsets", column_offsets_}};
    {
        gpu::GpuScope scope(&timer_, cmd, "raster_count");
        gpu::dispatch(*ctx_, cmd, count_pass_, pixels, push, fill_buffers);
    }
    {
        gpu::GpuScope scope(&timer_, cmd, "raster_scan");
        scan_.record(cmd, *column_offsets_, pixels + 1);
    }
    {
        gpu::GpuScope scope(&timer_, cmd, "raster_emit");
        gpu::dispatch(*ctx_, cmd, emit_pass_, pixels, push, fill_buffers);
    }
    const VkBufferCopy readback{0, 0, RASTER_COUNTERS * sizeof(uint32_t)};
    gpu::copy(*ctx_, cmd, counters_, counters_readback_, readback);
    gpu::host_read_barrier(cmd);
}

RasterStats RasterPlacer::place_on_gpu(const std::vector<glm::vec3>& triangles, float spacing, glm::vec3 lattice_origin,
                                       float w_value) {
    const auto start = Clock::now();
    if (!(spacing > 0.0f) || !std::isfinite(spacing))
        throw Failure("raster placement: the spacing must be a positive number, got " + std::to_string(spacing));
    if (triangles.size() % 3 != 0)
        throw Failure("raster placement: " + std::to_string(triangles.size()) +
                      " corners do not make whole triangles (three per triangle)");
    RasterStats stats;
    const uint32_t triangle_count = uint32_t(triangles.size() / 3);
    if (triangle_count == 0) return stats;

    if (triangle_count > max_threads(*ctx_, RASTER_LAYERS_WORKGROUP))
        throw Failure("raster placement: " + std::to_string(triangle_count) + " triangles, more than " +
                      ctx_->info().name + " can rasterise in one pass; simplify the mesh");
    const glm::ivec4 rect = pixel_rect(bounds_of(triangles), spacing, lattice_origin,
                                       std::min(kMaxPixels, max_threads(*ctx_, RASTER_FILL_WORKGROUP)));
    stats.pixels = uint32_t(rect.z) * uint32_t(rect.w);
    // Deforming meshes change their extent a little every frame: grow with headroom.
    const auto headroom = [](VkDeviceSize bytes) { return bytes + bytes / 4; };
    const VkDeviceSize corner_bytes = triangles.size() * sizeof(glm::vec4);
    if (triangles_.size < corner_bytes) reserve_triangles(headroom(corner_bytes));
    if (layer_count_.size < VkDeviceSize(stats.pixels) * sizeof(uint32_t)) {
        grow(layer_count_, "raster.layer_count", headroom(VkDeviceSize(stats.pixels) * sizeof(uint32_t)),
             gpu::MemoryUse::device);
        grow(layers_, "raster.layers", headroom(VkDeviceSize(stats.pixels) * RASTER_MAX_LAYERS * kLayerBytes),
             gpu::MemoryUse::device);
    }
    if (column_capacity_ < stats.pixels)
        reserve_columns(uint32_t(std::min(headroom(stats.pixels), VkDeviceSize(kMaxPixels))));
    auto* corners = static_cast<glm::vec4*>(triangles_staging_.mapped);
    for (size_t i = 0; i < triangles.size(); ++i) corners[i] = glm::vec4(triangles[i], 1.0f);

    shader::RasterPush push{};
    push.origin_spacing = glm::vec4(lattice_origin, spacing);
    push.pixel_rect = rect;
    push.triangle_count = triangle_count;
    push.max_points = point_capacity_;
    push.w_value = w_value;
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) { record_placement(cmd, push, corner_bytes, stats.pixels); });
    timer_.collect();
    for (const auto& [name, ms] : timer_.totals_ms()) stats.gpu_ms += ms;
    timer_.clear_totals();

    const auto* counters = static_cast<const uint32_t*>(counters_readback_.mapped);
    const uint32_t wanted = counters[RASTER_COUNTER_POINTS];
    stats.points = std::min(wanted, point_capacity_);
    stats.dropped_points = wanted - stats.points;
    stats.overflowed_pixels = counters[RASTER_COUNTER_OVERFLOWED];
    stats.open_pixels = counters[RASTER_COUNTER_OPEN];
    stats.ms = milliseconds_since(start);
    return stats;
}

ControlPoints place_raster(gpu::Context& ctx, const std::vector<glm::vec3>& triangles, float spacing,
                           std::optional<glm::vec3> lattice_origin, RasterStats* stats_out) {
    const auto start = Clock::now();
    ControlPoints result;
    result.method = "raster";
    if (!(spacing > 0.0f) || !std::isfinite(spacing))
        throw Failure("raster placement: the spacing must be a positive number, got " + std::to_string(spacing));
    const Box bounds = bounds_of(triangles);
    const glm::vec3 origin = lattice_origin.value_or(centred_lattice_origin(bounds, spacing));
    // First guess: half the lattice points of the bounding box (a sphere fills 52 %), at most 2^22;
    // a short guess costs one more placement, not lost points.
    const glm::dvec3 cells = glm::dvec3(bounds.max - bounds.min) / double(spacing) + 1.0;
    const double guess = std::clamp(0.5 * cells.x * cells.y * cells.z, 1024.0, double(1u << 22));
    const double pixels = std::min((cells.x + 3.0) * (cells.y + 3.0), kMaxPixels);
    RasterPlacer placer(ctx, uint32_t(triangles.size() / 3), uint32_t(guess), uint32_t(pixels));
    RasterStats stats = placer.place_on_gpu(triangles, spacing, origin);
    if (stats.dropped_points > 0) {
        placer.set_point_capacity(stats.points + stats.dropped_points);
        stats = placer.place_on_gpu(triangles, spacing, origin);
    }
    const std::vector<glm::vec4> points = gpu::download_vector<glm::vec4>(ctx, placer.points(), stats.points);
    result.points.reserve(points.size());
    for (const glm::vec4& point : points) result.points.emplace_back(point);
    // The GPU writes the points in column order (y, x, z), the same every run; place_inside() and
    // the callers use layer order (z, y, x), so both methods give identical lists.
    std::sort(result.points.begin(), result.points.end(),
              [](const glm::vec3& a, const glm::vec3& b) { return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x); });
    result.ms = milliseconds_since(start);
    if (stats_out) *stats_out = stats;
    return result;
}

}  // namespace aquaform::control
