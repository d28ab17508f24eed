// Image input and output (PNG).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/result.h"

namespace aquaform {

struct Image {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<uint8_t> rgba;  ///< width * height * 4 bytes, rows top to bottom
};

/// Writes an RGBA8 image as PNG; the error names the path and the fix.
Result<bool> write_png(const std::filesystem::path& path, const Image& image);

/// Reads a PNG (any bit depth or channel count) as RGBA8; the error names the path and the reason.
Result<Image> read_png(const std::filesystem::path& path);

}  // namespace aquaform
