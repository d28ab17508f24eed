// The picture sizes every renderer accepts: one definition for the renderers' own checks, the
// commands' --resolution and the study spec's "resolutions".
#pragma once

#include <cstdint>
#include <string>

#include "core/error.h"

namespace aquaform {

/// Per side, in pixels. At least one tile of the adaptive renderer's screen grid (SURFACE_TILE,
/// 16 px); at most 8192, a 64-megapixel picture whose 16-byte-a-pixel buffers already take 1 GiB
/// each.
inline constexpr uint32_t kMinPictureSide = 16;
inline constexpr uint32_t kMaxPictureSide = 8192;

/// A picture's width and height in pixels.
struct PictureSize {
    uint32_t width = 0, height = 0;
    std::string text() const { return std::to_string(width) + "x" + std::to_string(height); }
};

/// "16 to 8192": how messages and the usage quote the limit.
inline std::string picture_side_range() {
    return std::to_string(kMinPictureSide) + " to " + std::to_string(kMaxPictureSide);
}

inline bool picture_size_ok(uint64_t width, uint64_t height) {
    return width >= kMinPictureSide && height >= kMinPictureSide && width <= kMaxPictureSide &&
           height <= kMaxPictureSide;
}

/// A renderer's check of the size it is made with; `renderer` names it in the message.
inline void require_picture_size(const char* renderer, uint32_t width, uint32_t height) {
    if (!picture_size_ok(width, height))
        throw Failure(std::string(renderer) + ": resolution " + std::to_string(width) + "x" + std::to_string(height) +
                      " is outside " + picture_side_range() + " per side");
}

}  // namespace aquaform
