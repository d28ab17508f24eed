// Control-particle placement (c) of Karpati et al. section 3.2, last paragraph: the mesh is
// rasterised in an orthographic view along +z with every depth layer kept, and points are placed
// between entry and exit depths at the particle spacing. Fast enough to run every frame for a
// deforming mesh; the points stay on the GPU.
//
// Design: instead of K graphics passes of classic depth peeling, compute passes. One thread per
// triangle captures every depth layer of every pixel in ONE geometry pass, into fixed-capacity
// per-pixel lists (k-buffer style, Bavoil et al. 2007); one thread per pixel then sorts its layers,
// walks them with a winding count and counts the lattice points inside; a prefix sum over the
// pixels gives each its output offset, and the same walk emits the points there, so the point list
// is in column order whatever order the device ran its threads in. Pixels are the lattice columns
// themselves, so the points are exactly origin + spacing * (i, j, k): the lattice of
// method (b), place_inside(), and the two methods agree point for point away from the surface.
// Layouts and the winding convention: shaders/shared/control/raster_layout.h.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "control/placement.h"
#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "gpu/timer.h"
#include "grid/prefix_sum.h"

namespace aquaform::shader {
struct RasterPush;
}  // namespace aquaform::shader

namespace aquaform::control {

/// What one placement did. Nothing is lost silently: a full point buffer, a column with more
/// depth layers than the lists hold and a column through a hole are each counted.
struct RasterStats {
    uint32_t points = 0;             ///< points written to RasterPlacer::points()
    uint32_t dropped_points = 0;     ///< points that did not fit into the point capacity
    uint32_t overflowed_pixels = 0;  ///< columns with more than RASTER_MAX_LAYERS layers, left empty
    uint32_t open_pixels = 0;        ///< columns whose winding did not return to 0 (a hole), left empty
    uint32_t pixels = 0;             ///< lattice columns rasterised
    double gpu_ms = 0.0;             ///< all passes, from GPU timestamps
    double ms = 0.0;                 ///< wall time of place_on_gpu(): upload, passes, wait, read-back
};

class RasterPlacer {
public:
    /// Capacities; triangles and pixels grow as needed, the point capacity only through
    /// set_point_capacity() (points beyond it are counted in RasterStats::dropped_points).
    RasterPlacer(gpu::Context& ctx, uint32_t max_triangles, uint32_t max_points, uint32_t max_pixels);
    ~RasterPlacer();
    RasterPlacer(const RasterPlacer&) = delete;
    RasterPlacer& operator=(const RasterPlacer&) = delete;

    /// Uploads the triangles (three points each), records and submits the passes, waits and reads
    /// back the counters only. The points stay on the GPU: the first `stats.points` entries of
    /// points(), vec4 (xyz, w = `w_value`), in column order: by lattice row j, then column i, then
    /// z up (the same bytes every time for the same input; when the capacity is short, the first
    /// columns' points are kept). The lattice covers the triangles' xy bounds; throws aquaform::Failure for a bad spacing or a lattice too large to rasterise.
    RasterStats place_on_gpu(const std::vector<glm::vec3>& triangles, float spacing, glm::vec3 lattice_origin,
                             float w_value = 0.0f);

    const gpu::Buffer& points() const { return points_; }
    uint32_t point_capacity() const { return point_capacity_; }
    /// Replaces the point buffer (its contents are lost) when `max_points` exceeds the capacity.
    void set_point_capacity(uint32_t max_points);
    /// Bytes per buffer, for the memory report.
    std::vector<gpu::BufferReport> memory() const;

private:
    void grow(gpu::Buffer& buffer, const char* name, VkDeviceSize bytes, gpu::MemoryUse use);
    /// The corners' upload and device buffers for at least `corner_bytes`.
    void reserve_triangles(VkDeviceSize corner_bytes);
    /// Column offsets and the prefix sum over them for at least `pixels` columns.
    void reserve_columns(uint32_t pixels);
    /// The placement's passes for `pixels` columns (the corners uploaded, the counters read back).
    void record_placement(VkCommandBuffer cmd, const shader::RasterPush& push, VkDeviceSize corner_bytes,
                          uint32_t pixels);
    /// The buffers this placer owns outright (the column buffers are a set of their own).
    template <class Self>
    static auto own_buffers(Self& self) {
        return std::array{&self.triangles_staging_, &self.triangles_,         &self.layer_count_, &self.layers_,
                          &self.counters_,          &self.counters_readback_, &self.points_};
    }

    gpu::Context* ctx_;
    gpu::ComputePass layers_pass_;
    gpu::ComputePass count_pass_;  // raster_fill.comp, kEmit false
    gpu::ComputePass emit_pass_;   // raster_fill.comp, kEmit true
    gpu::GpuTimer timer_;
    uint32_t point_capacity_ = 0;
    gpu::Buffer triangles_staging_;  // host: the vec4 corners, copied in the same submission
    gpu::Buffer triangles_;
    gpu::Buffer layer_count_;        // per pixel
    gpu::Buffer layers_;             // RASTER_MAX_LAYERS per pixel
    gpu::Buffer counters_;           // RASTER_COUNTERS
    gpu::Buffer counters_readback_;  // host
    gpu::Buffer points_;
    uint32_t column_capacity_ = 0;
    std::unique_ptr<gpu::BufferSet> column_buffers_;  // the offsets and the scan's block sums
    gpu::Buffer* column_offsets_ = nullptr;           // per pixel, + 1: counts, then offsets and total
    gpu::PrefixSum scan_;
};

/// Places, then downloads the points (method "raster"; `ms` includes pipeline creation and the
/// download). The point capacity is sized from the bounding box and grown once when it was short, so
/// no point is dropped. `lattice_origin` defaults to centred_lattice_origin() of the triangles' bounds,
/// the lattice place_inside() uses. `stats`, when given, receives the final placement's figures.
ControlPoints place_raster(gpu::Context& ctx, const std::vector<glm::vec3>& triangles, float spacing,
                           std::optional<glm::vec3> lattice_origin = {}, RasterStats* stats = nullptr);

}  // namespace aquaform::control
