// Picture metrics: PSNR and per-pixel CIELAB Delta E of two images, heat-map views of per-pixel
// values, and golden-image checks with a perceptual (CIELAB) tolerance. The surface renderers'
// accuracy metrics (a method's frame against the exhaustive reference) are render/surface_metrics.h.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "pictures/image_io.h"

namespace aquaform {

/// What psnr() reports for identical images (and anything above it): a finite stand-in for
/// +infinity, so that results stay comparable and serialisable (JSON has no infinity).
constexpr double kPsnrCapDb = 99.0;

/// PSNR [dB] of the RGB channels (alpha ignored) of two equally sized RGBA8 images, capped at
/// kPsnrCapDb. Throws aquaform::Failure when the sizes differ or an image is malformed.
double psnr(const Image& a, const Image& b);

/// "WxH", as the messages about pictures give a size.
std::string size_text(uint32_t width, uint32_t height);
/// Throws a Failure naming `what` when `image` does not hold its width x height RGBA pixels.
void require_well_formed(const Image& image, const std::string& what);

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
    double mean_delta_e = 1.0;        ///< fail above this mean Delta E
    double pixel_delta_e = 10.0;      ///< a pixel is "bad" above this Delta E
    double max_bad_fraction = 0.005;  ///< fail when more than this fraction of pixels is bad
};

struct GoldenCheck {
    bool passed = false;
    std::string message;        ///< what was compared, the measurements against the tolerance, where the evidence went
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
