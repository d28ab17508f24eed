#include "render/surface_views.h"

#include <array>
#include <stdexcept>

#include "core/error.h"
#include "pictures/image_metrics.h"
#include "shaders/shared/render/surface_layout.h"

namespace aquaform {

namespace {

constexpr std::array<uint8_t, 3> kSplashColour{250, 210, 40};
constexpr std::array<uint8_t, 3> kAggregateColour{40, 190, 70};

void blend_pixel(Image& image, size_t pixel, const std::array<uint8_t, 3>& colour, float amount) {
    for (int c = 0; c < 3; ++c) {
        uint8_t& v = image.rgba[pixel * 4 + c];
        v = uint8_t(float(v) * (1.0f - amount) + float(colour[c]) * amount + 0.5f);
    }
}

}  // namespace

Image evals_view(const SurfaceFrame& frame, float max_evals) {
    std::vector<float> evals(frame.normal.size());
    for (size_t i = 0; i < evals.size(); ++i) evals[i] = frame.normal[i].w;
    return heat_map(evals, frame.width, frame.height, max_evals, &frame.color);
}

Image steps_view(const SurfaceFrame& frame, const std::vector<uint32_t>& march_steps, float max_steps) {
    if (march_steps.size() != frame.normal.size()) throw Failure("steps view: one step count per pixel expected");
    return heat_map(std::vector<float>(march_steps.begin(), march_steps.end()), frame.width, frame.height, max_steps,
                    &frame.color);
}

Image classification_view(const Image& image, const std::vector<uint32_t>& front_classes) {
    if (front_classes.size() != size_t(image.width) * image.height)
        throw Failure("classification view: one class per pixel expected");
    Image out = tint_image(image, {0, 0, 0}, 0.5f);
    for (size_t i = 0; i < front_classes.size(); ++i) {
        if (front_classes[i] == 1) blend_pixel(out, i, kSplashColour, 0.8f);
        if (front_classes[i] == 2) blend_pixel(out, i, kAggregateColour, 0.8f);
    }
    return out;
}

Image tile_view(const Image& image, const std::vector<uint32_t>& tile_levels, uint32_t tiles_per_row) {
    Image out = image;
    for (uint32_t y = 0; y < image.height; ++y) {
        for (uint32_t x = 0; x < image.width; ++x) {
            const size_t tile = size_t(y / SURFACE_TILE) * tiles_per_row + x / SURFACE_TILE;
            if (tile >= tile_levels.size()) throw Failure("tile view: fewer tile levels than tiles");
            const uint32_t level = tile_levels[tile];
            if (level == TILE_EMPTY) continue;
            const std::array<uint8_t, 3> colour = level == TILE_FULL   ? std::array<uint8_t, 3>{230, 50, 40}
                                                  : level == TILE_HALF ? std::array<uint8_t, 3>{240, 200, 40}
                                                                       : std::array<uint8_t, 3>{50, 200, 80};
            const bool border = x % SURFACE_TILE == 0 || y % SURFACE_TILE == 0;
            blend_pixel(out, size_t(y) * image.width + x, colour, border ? 0.9f : 0.35f);
        }
    }
    return out;
}

}  // namespace aquaform
