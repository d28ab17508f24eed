#include "pictures/image_metrics.h"

#include "core/error.h"
#include "core/format_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <system_error>

namespace aquaform {

namespace {

using Rgb = std::array<uint8_t, 3>;

size_t pixel_count(uint32_t width, uint32_t height) { return size_t(width) * size_t(height); }

void require_same_size(const Image& a, const Image& b, const std::string& what) {
    require_well_formed(a, what + " (first image)");
    require_well_formed(b, what + " (second image)");
    if (a.width != b.width || a.height != b.height)
        throw Failure(what + ": the images differ in size (" + size_text(a.width, a.height) + " vs " +
                      size_text(b.width, b.height) + ")");
}

double srgb_to_linear(uint8_t value) {
    const double c = value / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

/// Lab of every pixel's RGB.
std::vector<Lab> lab_pixels(const Image& image) {
    std::vector<Lab> lab(pixel_count(image.width, image.height));
    for (size_t i = 0; i < lab.size(); ++i) {
        const uint8_t* p = &image.rgba[i * 4];
        lab[i] = srgb_to_lab(p[0], p[1], p[2]);
    }
    return lab;
}

/// Inferno-like ramp (sampled from matplotlib's inferno): lightness rises monotonically.
constexpr std::array<Rgb, 9> kRamp = {{{0, 0, 4},
                                       {31, 12, 72},
                                       {85, 15, 109},
                                       {136, 34, 106},
                                       {186, 54, 85},
                                       {227, 89, 51},
                                       {249, 140, 10},
                                       {249, 201, 50},
                                       {252, 255, 164}}};

Rgb ramp_colour(double fraction) {
    const double position = std::clamp(fraction, 0.0, 1.0) * double(kRamp.size() - 1);
    const size_t low = std::min(size_t(position), kRamp.size() - 2);
    const double weight = position - double(low);
    Rgb colour;
    for (size_t c = 0; c < 3; ++c)
        colour[c] = uint8_t(std::lround((1.0 - weight) * kRamp[low][c] + weight * kRamp[low + 1][c]));
    return colour;
}

void set_pixel(Image& image, uint32_t x, uint32_t y, const Rgb& colour) {
    uint8_t* p = &image.rgba[(size_t(y) * image.width + x) * 4];
    p[0] = colour[0];
    p[1] = colour[1];
    p[2] = colour[2];
    p[3] = 255;
}

/// A vertical ramp bar (max at the top) in a dark frame, with white ticks at its ends, bottom right.
void draw_legend(Image& image) {
    constexpr uint32_t kMinSide = 48, kMargin = 4, kBarWidth = 6, kTickLength = 3;
    if (image.width < kMinSide || image.height < kMinSide) return;
    const uint32_t bar_height = std::clamp(image.height / 4, 16u, 64u);
    const uint32_t x0 = image.width - kMargin - kBarWidth, y0 = image.height - kMargin - bar_height;
    for (uint32_t y = y0 - 1; y <= y0 + bar_height; ++y)
        for (uint32_t x = x0 - 1; x <= x0 + kBarWidth; ++x) set_pixel(image, x, y, {0, 0, 0});
    for (uint32_t row = 0; row < bar_height; ++row) {
        const Rgb colour = ramp_colour(1.0 - double(row) / double(bar_height - 1));
        for (uint32_t x = x0; x < x0 + kBarWidth; ++x) set_pixel(image, x, y0 + row, colour);
    }
    for (const uint32_t tick_row : {y0, y0 + bar_height - 1})
        for (uint32_t x = x0 - 1 - kTickLength; x < x0 - 1; ++x) set_pixel(image, x, tick_row, {255, 255, 255});
}

/// Why a golden comparison could not be made, or empty when `delta_e` holds it.
struct GoldenComparison {
    std::string problem;
    std::vector<float> delta_e;
};

GoldenComparison compare_with_golden(const Image& actual, const std::filesystem::path& golden) {
    std::error_code ec;
    if (!std::filesystem::exists(golden, ec))
        return {"the golden image " + golden.string() + " does not exist yet", {}};
    Result<Image> expected = read_png(golden);
    if (!expected) return {expected.error(), {}};
    if (expected.value().width != actual.width || expected.value().height != actual.height)
        return {"the golden image " + golden.string() + " is " +
                    size_text(expected.value().width, expected.value().height) + " pixels but the actual image is " +
                    size_text(actual.width, actual.height),
                {}};
    return {"", delta_e_map(actual, expected.value())};
}

std::string percent(double fraction) { return format_text("%.3g%%", 100.0 * fraction); }

bool update_requested() {
    const char* value = std::getenv("AQUAFORM_UPDATE_GOLDEN");
    return value && std::string(value) == "1";
}

}  // namespace

std::string size_text(uint32_t width, uint32_t height) { return std::to_string(width) + "x" + std::to_string(height); }

void require_well_formed(const Image& image, const std::string& what) {
    const size_t bytes = pixel_count(image.width, image.height) * 4;
    if (image.rgba.size() != bytes)
        throw Failure(what + " is malformed: " + size_text(image.width, image.height) + " RGBA pixels need " +
                      std::to_string(bytes) + " bytes but it holds " + std::to_string(image.rgba.size()));
}

double psnr(const Image& a, const Image& b) {
    require_same_size(a, b, "cannot compute PSNR");
    const size_t pixels = pixel_count(a.width, a.height);
    if (pixels == 0) return kPsnrCapDb;
    double squared_error = 0.0;
    for (size_t i = 0; i < pixels; ++i)
        for (size_t c = 0; c < 3; ++c) {
            const double difference = double(a.rgba[i * 4 + c]) - double(b.rgba[i * 4 + c]);
            squared_error += difference * difference;
        }
    const double mse = squared_error / double(pixels * 3);
    if (mse == 0.0) return kPsnrCapDb;
    return std::min(kPsnrCapDb, 10.0 * std::log10(255.0 * 255.0 / mse));
}

Lab srgb_to_lab(uint8_t r, uint8_t g, uint8_t b) {
    // sRGB -> linear -> XYZ (D65), relative to the D65 white
    const double lr = srgb_to_linear(r), lg = srgb_to_linear(g), lb = srgb_to_linear(b);
    const double x = (0.4124564 * lr + 0.3575761 * lg + 0.1804375 * lb) / 0.95047;
    const double y = 0.2126729 * lr + 0.7151522 * lg + 0.0721750 * lb;
    const double z = (0.0193339 * lr + 0.1191920 * lg + 0.9503041 * lb) / 1.08883;
    constexpr double kDelta = 6.0 / 29.0;
    const auto f = [&](double t) {
        return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3.0 * kDelta * kDelta) + 4.0 / 29.0;
    };
    const double fx = f(x), fy = f(y), fz = f(z);
    return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

std::vector<float> delta_e_map(const Image& a, const Image& b) {
    require_same_size(a, b, "cannot compute Delta E");
    const std::vector<Lab> lab_a = lab_pixels(a), lab_b = lab_pixels(b);
    std::vector<float> delta_e(lab_a.size());
    for (size_t i = 0; i < delta_e.size(); ++i)
        delta_e[i] = float(std::hypot(lab_a[i].l - lab_b[i].l, lab_a[i].a - lab_b[i].a, lab_a[i].b - lab_b[i].b));
    return delta_e;
}

Image heat_map(const std::vector<float>& values, uint32_t width, uint32_t height, float max_value,
               const Image* background, bool legend) {
    const size_t pixels = pixel_count(width, height);
    if (values.size() != pixels)
        throw Failure("cannot draw a heat map: " + size_text(width, height) + " pixels but " +
                      std::to_string(values.size()) + " values");
    if (!(max_value > 0.0f) || !std::isfinite(max_value))
        throw Failure("cannot draw a heat map: the full-scale value must be positive and finite, not " +
                      std::to_string(max_value));
    Image image{width, height, std::vector<uint8_t>(pixels * 4, 0)};
    if (background) {
        require_well_formed(*background, "the heat map's background");
        if (background->width != width || background->height != height)
            throw Failure("cannot draw a heat map: " + size_text(width, height) + " pixels but the background is " +
                          size_text(background->width, background->height));
        // darkened so that the ramp's colours stand out against it
        image = tint_image(*background, {0, 0, 0}, 0.6f);
    }
    for (size_t i = 0; i < pixels; ++i) {
        uint8_t* p = &image.rgba[i * 4];
        p[3] = 255;
        if (!(values[i] > 0.0f)) continue;  // NaN too
        const Rgb colour = ramp_colour(double(values[i]) / double(max_value));
        std::copy(colour.begin(), colour.end(), p);
    }
    if (legend) draw_legend(image);
    return image;
}

Image tint_image(const Image& image, const std::array<uint8_t, 3>& colour, float amount) {
    require_well_formed(image, "the image to tint");
    const float weight = std::clamp(amount, 0.0f, 1.0f);
    Image tinted = image;
    for (size_t i = 0; i < tinted.rgba.size(); i += 4)
        for (size_t c = 0; c < 3; ++c)
            tinted.rgba[i + c] = uint8_t(std::lround((1.0f - weight) * image.rgba[i + c] + weight * colour[c]));
    return tinted;
}

GoldenCheck check_golden(const Image& actual, const std::filesystem::path& golden,
                         const std::filesystem::path& output_dir, const GoldenTolerance& tol) {
    require_well_formed(actual, "the actual image for golden " + golden.string());
    const GoldenComparison comparison = compare_with_golden(actual, golden);
    const bool compared = comparison.problem.empty();

    GoldenCheck check;
    std::string measurements = comparison.problem;
    if (compared) {
        const auto& delta_e = comparison.delta_e;
        const size_t bad = size_t(
            std::count_if(delta_e.begin(), delta_e.end(), [&](float value) { return value > tol.pixel_delta_e; }));
        const double count = double(std::max<size_t>(1, delta_e.size()));
        check.mean_delta_e = std::accumulate(delta_e.begin(), delta_e.end(), 0.0) / count;
        check.bad_fraction = double(bad) / count;
        measurements = "mean Delta E " + format_text("%.3g", check.mean_delta_e) + " (tolerance " +
                       format_text("%g", tol.mean_delta_e) + "), " + percent(check.bad_fraction) +
                       " of pixels with Delta E > " + format_text("%g", tol.pixel_delta_e) + " (tolerance " +
                       percent(tol.max_bad_fraction) + ")";
    } else {
        check.mean_delta_e = check.bad_fraction = std::numeric_limits<double>::quiet_NaN();
    }

    std::error_code ec;
    if (update_requested()) {
        if (golden.has_parent_path()) std::filesystem::create_directories(golden.parent_path(), ec);
        const Result<bool> written = write_png(golden, actual);
        check.passed = written.ok();
        check.message = written.ok() ? "updated the golden image " + golden.string() +
                                           " from the actual image (AQUAFORM_UPDATE_GOLDEN=1); before: " + measurements
                                     : "AQUAFORM_UPDATE_GOLDEN=1 but " + written.error();
        return check;
    }

    if (compared && check.mean_delta_e <= tol.mean_delta_e && check.bad_fraction <= tol.max_bad_fraction) {
        check.passed = true;
        check.message = "matches the golden image " + golden.string() + ": " + measurements;
        return check;
    }

    // Failed: leave the evidence next to the test's other outputs.
    check.message = "golden image check failed for " + golden.string() + ": " + measurements;
    std::filesystem::create_directories(output_dir, ec);
    const std::string name = golden.stem().string();
    const std::filesystem::path actual_path = output_dir / (name + ".actual.png");
    const Result<bool> actual_written = write_png(actual_path, actual);
    check.message += actual_written.ok() ? "; actual image: " + actual_path.string()
                                         : "; could not save the actual image: " + actual_written.error();
    if (compared) {
        const std::filesystem::path diff_path = output_dir / (name + ".diff.png");
        const Result<bool> diff_written = write_png(
            diff_path, heat_map(comparison.delta_e, actual.width, actual.height, float(tol.pixel_delta_e), &actual));
        check.message += diff_written.ok() ? "; Delta E heat map (full scale at Delta E " +
                                                 format_text("%g", tol.pixel_delta_e) + "): " + diff_path.string()
                                           : "; could not save the Delta E heat map: " + diff_written.error();
    }
    check.message +=
        ". If the actual image is the intended result, re-run the test with the environment variable "
        "AQUAFORM_UPDATE_GOLDEN=1 to update the golden image";
    return check;
}

}  // namespace aquaform
