// Accuracy metrics for the surface renderers: a method's frame against the exhaustive reference
// (depth, normal and coverage errors, PSNR of the shaded pictures, smoothness of flat surfaces).
// The picture metrics they use (PSNR, Delta E, heat maps, golden images) are pictures/image_metrics.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/surface_frame.h"

namespace aquaform {

/// Per-pixel errors of a test frame against the reference, row-major like the frames.
struct SurfaceErrorMaps {
    std::vector<float> depth_err;       ///< |t_test - t_ref| / particle_radius; 0 unless both hit
    std::vector<float> normal_err_deg;  ///< angle between the normals [deg]; 0 unless both hit
};

/// Throws aquaform::Failure when the frames differ in size or are malformed, or the radius is not positive.
SurfaceErrorMaps surface_error_maps(const SurfaceFrame& reference, const SurfaceFrame& test, float particle_radius);

struct SurfaceComparison {
    // Over the pixels where both frames have a surface; p95 is the nearest-rank 95th percentile.
    double depth_err_mean = 0.0;  ///< in particle radii
    double depth_err_p95 = 0.0;
    double depth_err_max = 0.0;
    double normal_err_deg_mean = 0.0;
    double normal_err_deg_p95 = 0.0;

    size_t both_hit = 0;        ///< pixels where both frames have a surface
    size_t only_reference = 0;  ///< pixels the test frame missed
    size_t only_test = 0;       ///< pixels where the test frame found a surface the reference has not
    /// (only_reference + only_test) / pixels with a surface in either frame (0 when neither has one).
    double coverage_mismatch = 0.0;

    double psnr_db = 0.0;  ///< of the shaded colour images, capped at kPsnrCapDb
    /// Smoothness (surface_roughness): the test frame's rms normal deviation [deg] from the plane
    /// the reference's surface fits, over the regions the reference shows flat; 0 when none.
    double roughness_deg = 0.0;
    size_t flat_pixels = 0;      ///< pixels (on a stride) in those regions
    double evals_per_ray = 0.0;  ///< test frame: mean density evaluations over the pixels that cast a ray
    size_t rays = 0;             ///< test frame: pixels that cast a ray (normal.w > 0)
};

/// Compares `test` against `reference`; throws aquaform::Failure when the frames (or their
/// colour images) differ in size or are malformed, or the radius is not positive.
SurfaceComparison compare_surfaces(const SurfaceFrame& reference, const SurfaceFrame& test, float particle_radius);

/// How bumpy a method draws surfaces that are flat: every particle showing as a bump is what
/// blended normals and anisotropic kernels exist to prevent, and depth error cannot see it (the
/// bumps are a fraction of a radius deep, but tilt the normals by tens of degrees). On a stride
/// of kRoughnessStride pixels, a region is flat where the reference's surface points within a
/// window kRoughnessWindowRadii particle radii wide (in the pixels that span it there) are all
/// present, continuous and fit by a plane within kFlatResidualRadii particle radii (rms); there
/// the test frame's normal is compared with that plane's. The reference's own normals measure
/// the bumps of the SPH field itself (compare a frame with itself for that floor).
struct SurfaceRoughness {
    double rms_deg = 0.0;
    size_t flat_pixels = 0;
};
constexpr uint32_t kRoughnessStride = 3;
constexpr float kRoughnessWindowRadii = 6.0f;
constexpr float kFlatResidualRadii = 0.25f;
SurfaceRoughness surface_roughness(const SurfaceFrame& reference, const SurfaceFrame& test, float particle_radius);

}  // namespace aquaform
