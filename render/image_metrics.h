// Accuracy metrics for the surface renderers (a method's frame against the exhaustive reference),
// heat-map views of per-pixel errors, and golden-image checks with a perceptual (CIELAB) tolerance.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "render/image_io.h"
#include "render/surface_frame.h"

namespace aquaform {

/// What psnr() reports for identical images (and anything above it): a finite stand-in for
/// +infinity, so that results stay comparable and serialisable (JSON has no infinity).
constexpr double kPsnrCapDb = 99.0;

/// PSNR [dB] of the RGB channels (alpha ignored) of two equally sized RGBA8 images, capped at
/// kPsnrCapDb. Throws aquaform::Failure when the sizes differ or an image is malformed.
double psnr(const Image& a, const Image& b);

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

    double psnr_db = 0.0;        ///< of the shaded colour images, capped at kPsnrCapDb
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

/// CIELAB (D65 white) of an 8-bit sRGB colour: L* in 0..100.
struct Lab {
    double l = 0.0, a = 0.0, b = 0.0;
};
Lab srgb_to_lab(uint8_t r, uint8_t g, uint8_t b);

/// Per-pixel CIE76 Delta E between the RGB (alpha ignored) of two equally sized images, row-major.
/// Throws aquaform::Failure when the sizes differ or an image is malformed.
std::vector<float> delta_e_map(const Image& a, const Image& b);

/// `values` (row-major, width * height) as colours of an inferno-like ramp whose lightness rises
/// with the value: 0 dark, `max_value` and above bright yellow. Pixels with value <= 0 (or NaN)
/// show `background` darkened, or black without one. With `legend`, a small ramp bar with min and
/// max ticks goes in the bottom-right corner when the image is at least 48x48 pixels. Throws
/// aquaform::Failure on a size mismatch or a max_value that is not positive and finite.
Image heat_map(const std::vector<float>& values, uint32_t width, uint32_t height, float max_value,
               const Image* background = nullptr, bool legend = true);

/// `image` blended towards `colour` by `amount` (0: unchanged, 1: flat colour); alpha is kept.
Image tint_image(const Image& image, const std::array<uint8_t, 3>& colour, float amount);

struct GoldenTolerance {
    double mean_delta_e = 1.0;       ///< fail above this mean Delta E
    double pixel_delta_e = 10.0;     ///< a pixel is "bad" above this Delta E
    double max_bad_fraction = 0.005; ///< fail when more than this fraction of pixels is bad
};

struct GoldenCheck {
    bool passed = false;
    std::string message;  ///< what was compared, the measurements against the tolerance, where the evidence went
    double mean_delta_e = 0.0;  ///< NaN when nothing could be compared (golden missing or of other size)
    double bad_fraction = 0.0;  ///< NaN when nothing could be compared
};

/// Compares `actual` with the PNG at `golden` in CIELAB (RGB only, alpha ignored). On failure, and
/// when the golden is missing, unreadable or of other size, writes `<stem>.actual.png` and (when
/// there was something to compare) `<stem>.diff.png`, a Delta E heat map whose full scale is
/// tol.pixel_delta_e, into `output_dir` (created if needed). With the environment variable
/// AQUAFORM_UPDATE_GOLDEN=1, writes `actual` to `golden` instead (creating directories) and passes.
/// Throws aquaform::Failure when `actual` is malformed.
GoldenCheck check_golden(const Image& actual, const std::filesystem::path& golden,
                         const std::filesystem::path& output_dir, const GoldenTolerance& tol = {});

}  // namespace aquaform
