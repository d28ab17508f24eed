// Image output.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "sim/result.h"

namespace aquaform {

struct Image {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<uint8_t> rgba;  ///< width * height * 4 bytes, rows top to bottom
};

/// Writes an RGBA8 image as PNG; the error names the path and the fix.
Result<bool> write_png(const std::filesystem::path& path, const Image& image);

}  // namespace aquaform
