// The surface-accuracy metrics measure what was put into crafted frames; the heat map's ramp gets
// lighter with the value; golden checks tolerate noise, catch real changes and say how to update;
// PNG reading round-trips writing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "pictures/image_io.h"
#include "pictures/image_metrics.h"
#include "render/surface_metrics.h"

namespace aquaform {
namespace {

constexpr uint32_t kW = 32, kH = 24;
constexpr float kRadius = 0.01f;

/// A sphere-ish test frame: a disc of surface in the middle, every pixel cast one ray of `evals` evaluations.
SurfaceFrame disc_frame(float evals = 40.0f) {
    SurfaceFrame frame{kW, kH, {}, {}, Image{kW, kH, std::vector<uint8_t>(size_t(kW) * kH * 4, 255)}};
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const glm::vec2 offset(float(x) - kW / 2.0f, float(y) - kH / 2.0f);
            const bool inside = glm::length(offset) < 8.0f;
            const float t = inside ? 1.0f + 0.001f * float(x) : -1.0f;
            const glm::vec3 normal = inside ? glm::normalize(glm::vec3(offset / 10.0f, 1.0f)) : glm::vec3(0.0f);
            frame.hit.emplace_back(float(x), float(y), t, t);
            frame.normal.emplace_back(normal, evals);
            uint8_t* p = &frame.color.rgba[(size_t(y) * kW + x) * 4];
            p[0] = uint8_t(x * 7);
            p[1] = uint8_t(inside ? 200 : 40);
            p[2] = uint8_t(y * 9);
        }
    return frame;
}

Image solid_image(uint32_t width, uint32_t height, uint8_t r, uint8_t g, uint8_t b) {
    Image image{width, height, {}};
    for (size_t i = 0; i < size_t(width) * height; ++i) image.rgba.insert(image.rgba.end(), {r, g, b, 255});
    return image;
}

/// Grey with a red square whose top-left corner is at (left, top).
Image square_image(uint32_t left, uint32_t top) {
    Image image = solid_image(64, 64, 128, 128, 128);
    for (uint32_t y = top; y < top + 16; ++y)
        for (uint32_t x = left; x < left + 16; ++x) {
            uint8_t* p = &image.rgba[(size_t(y) * image.width + x) * 4];
            p[0] = 220;
            p[1] = 30;
            p[2] = 30;
        }
    return image;
}

/// A fresh directory for one test, removed afterwards.
class ScratchDir {
public:
    ScratchDir() {
        const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = std::filesystem::temp_directory_path() /
                ("aquaform_image_metrics_" + std::string(test->name()) + "_" + std::to_string(::getpid()));
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

/// Sets (or with nullopt clears) AQUAFORM_UPDATE_GOLDEN for one scope, so that a developer's
/// environment does not change what these tests see.
class UpdateGoldenVariable {
public:
    explicit UpdateGoldenVariable(std::optional<std::string> value) {
        if (const char* old = std::getenv(kName)) previous_ = old;
        if (value)
            ::setenv(kName, value->c_str(), 1);
        else
            ::unsetenv(kName);
    }
    ~UpdateGoldenVariable() {
        if (previous_)
            ::setenv(kName, previous_->c_str(), 1);
        else
            ::unsetenv(kName);
    }

private:
    static constexpr const char* kName = "AQUAFORM_UPDATE_GOLDEN";
    std::optional<std::string> previous_;
};

TEST(ImageMetrics, IdenticalFramesHaveNoError) {
    const SurfaceFrame frame = disc_frame();
    const SurfaceComparison same = compare_surfaces(frame, frame, kRadius);
    EXPECT_EQ(same.depth_err_mean, 0.0);
    EXPECT_EQ(same.depth_err_p95, 0.0);
    EXPECT_EQ(same.depth_err_max, 0.0);
    EXPECT_EQ(same.normal_err_deg_mean, 0.0);
    EXPECT_EQ(same.normal_err_deg_p95, 0.0);
    EXPECT_GT(same.both_hit, 150u);
    EXPECT_EQ(same.only_reference, 0u);
    EXPECT_EQ(same.only_test, 0u);
    EXPECT_EQ(same.coverage_mismatch, 0.0);
    EXPECT_EQ(same.psnr_db, kPsnrCapDb) << "identical images report the finite cap, not infinity";
    EXPECT_EQ(psnr(frame.color, frame.color), kPsnrCapDb);
    EXPECT_EQ(same.rays, size_t(kW) * kH);
    EXPECT_FLOAT_EQ(same.evals_per_ray, 40.0);
}

TEST(ImageMetrics, DepthOffsetIsMeasuredInParticleRadii) {
    const SurfaceFrame reference = disc_frame();
    SurfaceFrame test = reference;
    for (size_t i = 0; i < test.hit.size(); ++i)
        if (test.has_surface(i)) test.hit[i].w += (i % 2 ? 0.5f : -0.5f) * kRadius;
    const SurfaceComparison result = compare_surfaces(reference, test, kRadius);
    EXPECT_NEAR(result.depth_err_mean, 0.5, 1e-4);
    EXPECT_NEAR(result.depth_err_p95, 0.5, 1e-4);
    EXPECT_NEAR(result.depth_err_max, 0.5, 1e-4);
    EXPECT_EQ(result.only_reference + result.only_test, 0u);

    // one outlier moves the maximum but not the 95th percentile
    for (size_t i = 0; i < test.hit.size(); ++i)
        if (test.has_surface(i)) {
            test.hit[i].w = reference.hit[i].w + 3.0f * kRadius;
            break;
        }
    const SurfaceComparison outlier = compare_surfaces(reference, test, kRadius);
    EXPECT_NEAR(outlier.depth_err_max, 3.0, 1e-3);
    EXPECT_NEAR(outlier.depth_err_p95, 0.5, 1e-4);
}

TEST(ImageMetrics, RotatedNormalsGiveTheRotationAngle) {
    const SurfaceFrame reference = disc_frame();
    SurfaceFrame test = reference;
    // rotating about an axis perpendicular to each normal turns it by exactly the rotation angle
    for (auto& normal : test.normal) {
        const glm::vec3 n(normal);
        if (glm::length(n) == 0.0f) continue;
        const glm::vec3 axis = glm::normalize(glm::cross(n, glm::vec3(1.0f, 0.0f, 0.0f)));
        normal = glm::vec4(glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(10.0f), axis) * glm::vec4(n, 0.0f)),
                           normal.w);
    }
    const SurfaceComparison result = compare_surfaces(reference, test, kRadius);
    EXPECT_NEAR(result.normal_err_deg_mean, 10.0, 1e-3);
    EXPECT_NEAR(result.normal_err_deg_p95, 10.0, 1e-3);
    EXPECT_EQ(result.depth_err_max, 0.0);
}

TEST(ImageMetrics, CoverageCountsOnCraftedMasks) {
    SurfaceFrame reference = disc_frame(), test = disc_frame();
    for (auto& hit : reference.hit) hit.w = -1.0f;
    for (auto& hit : test.hit) hit.w = -1.0f;
    // pixels 0-9: both; 10-13: reference only; 14-19: test only
    for (size_t i = 0; i < 14; ++i) reference.hit[i].w = 1.0f;
    for (size_t i = 0; i < 10; ++i) test.hit[i].w = 1.0f;
    for (size_t i = 14; i < 20; ++i) test.hit[i].w = 1.0f;
    const SurfaceComparison result = compare_surfaces(reference, test, kRadius);
    EXPECT_EQ(result.both_hit, 10u);
    EXPECT_EQ(result.only_reference, 4u);
    EXPECT_EQ(result.only_test, 6u);
    EXPECT_DOUBLE_EQ(result.coverage_mismatch, 10.0 / 20.0);

    for (auto& hit : reference.hit) hit.w = -1.0f;
    for (auto& hit : test.hit) hit.w = -1.0f;
    EXPECT_EQ(compare_surfaces(reference, test, kRadius).coverage_mismatch, 0.0) << "no surface anywhere";
}

TEST(ImageMetrics, EvaluationsPerRayCountOnlyPixelsThatCastARay) {
    const SurfaceFrame reference = disc_frame();
    SurfaceFrame test = disc_frame(0.0f);                                                        // all interpolated ...
    for (size_t i = 0; i < test.normal.size(); i += 4) test.normal[i].w = 10.0f + float(i % 8);  // ... but every 4th
    const SurfaceComparison result = compare_surfaces(reference, test, kRadius);
    EXPECT_EQ(result.rays, test.normal.size() / 4);
    EXPECT_NEAR(result.evals_per_ray, 12.0, 1e-9) << "alternating 10 and 14";
}

TEST(ImageMetrics, PsnrOfAUniformErrorMatchesTheFormula) {
    const Image a = solid_image(16, 8, 100, 150, 200);
    for (int error : {1, 5, 40}) {
        Image b = a;
        for (size_t i = 0; i < b.rgba.size(); ++i)
            if (i % 4 != 3) b.rgba[i] = uint8_t(b.rgba[i] + (i % 2 ? error : -error));
        b.rgba[3] = 0;  // alpha does not count
        EXPECT_NEAR(psnr(a, b), 20.0 * std::log10(255.0 / error), 1e-9) << "error " << error;
    }
}

TEST(ImageMetrics, SizeMismatchThrowsWithTheSizes) {
    const SurfaceFrame reference = disc_frame();
    SurfaceFrame smaller = reference;
    smaller.width = kW / 2;
    smaller.hit.resize(size_t(kW / 2) * kH);
    smaller.normal.resize(size_t(kW / 2) * kH);
    smaller.color = solid_image(kW / 2, kH, 0, 0, 0);
    try {
        compare_surfaces(reference, smaller, kRadius);
        FAIL() << "expected aquaform::Failure";
    } catch (const Failure& e) {
        EXPECT_NE(std::string(e.what()).find("32x24"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("16x24"), std::string::npos) << e.what();
    }
    EXPECT_THROW(psnr(reference.color, smaller.color), Failure);
    EXPECT_THROW(compare_surfaces(reference, reference, 0.0f), Failure);
    SurfaceFrame truncated = reference;
    truncated.normal.pop_back();
    EXPECT_THROW(compare_surfaces(reference, truncated, kRadius), Failure);
}

TEST(ImageMetrics, HeatMapRampGetsLighterWithTheValue) {
    constexpr uint32_t kSteps = 256;
    std::vector<float> values(kSteps);
    for (uint32_t i = 0; i < kSteps; ++i) values[i] = float(i + 1) / kSteps;
    const Image ramp = heat_map(values, kSteps, 1, 1.0f);
    double previous_lightness = -1.0;
    for (uint32_t i = 0; i < kSteps; ++i) {
        const uint8_t* p = &ramp.rgba[i * 4];
        const double lightness = srgb_to_lab(p[0], p[1], p[2]).l;
        EXPECT_GE(lightness, previous_lightness) << "value " << values[i];
        previous_lightness = lightness;
    }
    const auto lightness_at = [&](uint32_t i) {
        return srgb_to_lab(ramp.rgba[i * 4], ramp.rgba[i * 4 + 1], ramp.rgba[i * 4 + 2]).l;
    };
    EXPECT_GT(lightness_at(kSteps - 1) - lightness_at(0), 80.0) << "the ramp spans dark to light";

    // above full scale saturates; zero shows the darkened background (black without one)
    const Image background = solid_image(3, 1, 200, 200, 200);
    const Image mixed = heat_map({5.0f, 0.0f, -1.0f}, 3, 1, 1.0f, &background);
    EXPECT_EQ(std::vector<uint8_t>(mixed.rgba.begin(), mixed.rgba.begin() + 4),
              std::vector<uint8_t>(ramp.rgba.end() - 4, ramp.rgba.end()));
    EXPECT_LT(mixed.rgba[4], 200);
    EXPECT_GT(mixed.rgba[4], 0);
    EXPECT_EQ(mixed.rgba[8], mixed.rgba[4]);
    EXPECT_EQ(heat_map({0.0f}, 1, 1, 1.0f).rgba, (std::vector<uint8_t>{0, 0, 0, 255}));
    EXPECT_THROW(heat_map({1.0f}, 2, 1, 1.0f), Failure);
    EXPECT_THROW(heat_map({1.0f}, 1, 1, 0.0f), Failure);
}

TEST(ImageMetrics, HeatMapLegendSitsInTheBottomRightCorner) {
    const std::vector<float> zeros(64 * 64, 0.0f);
    const Image with_legend = heat_map(zeros, 64, 64, 1.0f);
    const Image without = heat_map(zeros, 64, 64, 1.0f, nullptr, false);
    size_t changed = 0;
    for (size_t i = 0; i < with_legend.rgba.size(); i += 4) {
        if (with_legend.rgba[i] == without.rgba[i] && with_legend.rgba[i + 1] == without.rgba[i + 1]) continue;
        ++changed;
        const size_t x = (i / 4) % 64, y = (i / 4) / 64;
        EXPECT_GE(x, 48u);
        EXPECT_GE(y, 32u);
    }
    EXPECT_GT(changed, 50u);
}

TEST(ImageMetrics, ReadPngRoundTripsWritePng) {
    const ScratchDir dir;
    Image image = square_image(5, 9);
    image.rgba[7] = 17;  // a translucent pixel: alpha survives too
    const auto path = dir.path() / "round_trip.png";
    ASSERT_TRUE(write_png(path, image).ok());
    const Result<Image> read = read_png(path);
    ASSERT_TRUE(read.ok()) << read.error();
    EXPECT_EQ(read.value().width, image.width);
    EXPECT_EQ(read.value().height, image.height);
    EXPECT_EQ(read.value().rgba, image.rgba);

    const Result<Image> missing = read_png(dir.path() / "missing.png");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().find("missing.png"), std::string::npos) << missing.error();
}

TEST(ImageMetrics, GoldenPassesForIdenticalAndSlightlyNoisyImages) {
    const UpdateGoldenVariable no_update(std::nullopt);
    const ScratchDir dir;
    const Image golden_image = square_image(20, 20);
    const auto golden = dir.path() / "golden" / "square.png";
    std::filesystem::create_directories(golden.parent_path());
    ASSERT_TRUE(write_png(golden, golden_image).ok());

    const GoldenCheck same = check_golden(golden_image, golden, dir.path() / "out");
    EXPECT_TRUE(same.passed) << same.message;
    EXPECT_EQ(same.mean_delta_e, 0.0);
    EXPECT_EQ(same.bad_fraction, 0.0);

    Image noisy = golden_image;
    std::mt19937 random(7);
    for (size_t i = 0; i < noisy.rgba.size(); ++i)
        if (i % 4 != 3) noisy.rgba[i] = uint8_t(noisy.rgba[i] + (random() % 2 ? 1 : -1));
    const GoldenCheck noise = check_golden(noisy, golden, dir.path() / "out");
    EXPECT_TRUE(noise.passed) << noise.message;
    EXPECT_GT(noise.mean_delta_e, 0.0);
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "out")) << "a pass leaves no files behind";
}

TEST(ImageMetrics, GoldenFailsForAShiftedSquareAndLeavesTheEvidence) {
    const UpdateGoldenVariable no_update(std::nullopt);
    const ScratchDir dir;
    const auto golden = dir.path() / "square.png";
    ASSERT_TRUE(write_png(golden, square_image(20, 20)).ok());
    const auto out = dir.path() / "out";

    const GoldenCheck shifted = check_golden(square_image(24, 20), golden, out);
    EXPECT_FALSE(shifted.passed);
    EXPECT_NEAR(shifted.bad_fraction, 2.0 * 4 * 16 / (64.0 * 64.0), 1e-9) << "two 4x16 strips changed";
    const auto actual_path = out / "square.actual.png", diff_path = out / "square.diff.png";
    EXPECT_TRUE(std::filesystem::exists(actual_path));
    EXPECT_TRUE(std::filesystem::exists(diff_path));
    for (const std::string& expected : {golden.string(), actual_path.string(), diff_path.string(),
                                        std::string("AQUAFORM_UPDATE_GOLDEN=1"), std::string("tolerance")})
        EXPECT_NE(shifted.message.find(expected), std::string::npos) << "missing '" << expected << "' in\n"
                                                                     << shifted.message;
    const Result<Image> actual_written = read_png(actual_path);
    ASSERT_TRUE(actual_written.ok());
    EXPECT_EQ(actual_written.value().rgba, square_image(24, 20).rgba);
}

TEST(ImageMetrics, MissingOrResizedGoldenFailsAndSaysHowToCreateIt) {
    const UpdateGoldenVariable no_update(std::nullopt);
    const ScratchDir dir;
    const auto golden = dir.path() / "golden" / "absent.png";
    const GoldenCheck missing = check_golden(square_image(0, 0), golden, dir.path() / "out");
    EXPECT_FALSE(missing.passed);
    EXPECT_TRUE(std::isnan(missing.mean_delta_e));
    EXPECT_NE(missing.message.find(golden.string()), std::string::npos) << missing.message;
    EXPECT_NE(missing.message.find("AQUAFORM_UPDATE_GOLDEN=1"), std::string::npos) << missing.message;
    EXPECT_TRUE(std::filesystem::exists(dir.path() / "out" / "absent.actual.png"));

    const auto small_golden = dir.path() / "small.png";
    ASSERT_TRUE(write_png(small_golden, solid_image(8, 8, 1, 2, 3)).ok());
    const GoldenCheck resized = check_golden(square_image(0, 0), small_golden, dir.path() / "out");
    EXPECT_FALSE(resized.passed);
    EXPECT_NE(resized.message.find("8x8"), std::string::npos) << resized.message;
    EXPECT_NE(resized.message.find("64x64"), std::string::npos) << resized.message;
}

TEST(ImageMetrics, UpdateGoldenVariableWritesTheGolden) {
    const ScratchDir dir;
    const auto golden = dir.path() / "new" / "dir" / "square.png";
    {
        const UpdateGoldenVariable update("1");
        const GoldenCheck created = check_golden(square_image(3, 4), golden, dir.path() / "out");
        EXPECT_TRUE(created.passed) << created.message;
        EXPECT_NE(created.message.find("updated"), std::string::npos) << created.message;
    }
    const UpdateGoldenVariable no_update(std::nullopt);
    const GoldenCheck after = check_golden(square_image(3, 4), golden, dir.path() / "out");
    EXPECT_TRUE(after.passed) << after.message;
}

/// A plane z = 0 seen head-on: pixel (x, y) hits (x f, y f, 0) at distance 1 with normal `n(x, y)`;
/// `height(x, y)` displaces the points along z.
template <typename Normal, typename Height>
SurfaceFrame plane_frame(uint32_t size, float footprint, Normal n, Height height) {
    SurfaceFrame f;
    f.width = f.height = size;
    f.color.width = f.color.height = size;
    f.color.rgba.assign(size_t(size) * size * 4, 255);
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const float z = height(x, y);
            f.hit.emplace_back(float(x) * footprint, float(y) * footprint, z, 1.0f - z);
            f.normal.emplace_back(n(x, y), 5.0f);
        }
    return f;
}

TEST(SurfaceRoughness, SeesBumpyNormalsOnAFlatSurfaceAndOnlyWhereTheReferenceIsFlat) {
    const float radius = 0.01f, footprint = 0.006f;  // a particle radius spans about 1.7 pixels
    const auto flat = [](uint32_t, uint32_t) { return 0.0f; };
    const auto up = [](uint32_t, uint32_t) { return glm::vec3(0.0f, 0.0f, 1.0f); };
    // Each particle a bump: normals tilted by 20 degrees one way and the other, every 3 pixels.
    const float tilt = glm::radians(20.0f);
    const auto bumpy = [&](uint32_t x, uint32_t) {
        const float a = (x / 3) % 2 ? tilt : -tilt;
        return glm::vec3(std::sin(a), 0.0f, std::cos(a));
    };
    const SurfaceFrame reference = plane_frame(64, footprint, up, flat);
    const SurfaceRoughness smooth = surface_roughness(reference, reference, radius);
    EXPECT_GT(smooth.flat_pixels, 100u);
    EXPECT_LT(smooth.rms_deg, 0.01);
    const SurfaceRoughness rough = surface_roughness(reference, plane_frame(64, footprint, bumpy, flat), radius);
    EXPECT_EQ(rough.flat_pixels, smooth.flat_pixels);
    EXPECT_NEAR(rough.rms_deg, 20.0, 0.01);
    // A reference whose points leave the plane by more than the flat residual: no region counts.
    const auto corrugated = [&](uint32_t x, uint32_t) { return (x / 4) % 2 ? 0.6f * radius : -0.6f * radius; };
    const SurfaceFrame wavy = plane_frame(64, footprint, up, corrugated);
    EXPECT_EQ(surface_roughness(wavy, plane_frame(64, footprint, bumpy, flat), radius).flat_pixels, 0u);
    // compare_surfaces reports it.
    const SurfaceComparison c = compare_surfaces(reference, plane_frame(64, footprint, bumpy, flat), radius);
    EXPECT_NEAR(c.roughness_deg, 20.0, 0.01);
    EXPECT_EQ(c.flat_pixels, smooth.flat_pixels);
}

}  // namespace
}  // namespace aquaform
