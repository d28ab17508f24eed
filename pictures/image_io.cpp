#include "pictures/image_io.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <string>
#include <system_error>

#include "core/file_write.h"

// Private (static) copies of stb_image_write and stb_image: no clash with the symbols of Debian's
// libstb, whichever of the two the linker sees first. The pragmas silence their unused functions.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace aquaform {

namespace {

void append(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<uint8_t>*>(context);
    const auto* bytes = static_cast<const uint8_t*>(data);
    out->insert(out->end(), bytes, bytes + size);
}

}  // namespace

Result<bool> write_png(const std::filesystem::path& path, const Image& image) {
    const std::string where = "cannot write PNG to " + path.string();
    if (image.width == 0 || image.height == 0)
        return Error{where + ": the image is empty (" + std::to_string(image.width) + "x" +
                     std::to_string(image.height) + " pixels); render at least 1x1 pixels"};
    if (image.rgba.size() != size_t(image.width) * image.height * 4)
        return Error{where + ": the image holds " + std::to_string(image.rgba.size()) + " bytes but " +
                     std::to_string(image.width) + "x" + std::to_string(image.height) + " RGBA pixels need " +
                     std::to_string(size_t(image.width) * image.height * 4)};
    // stb takes int sizes and strides
    if (image.width > (1u << 24) || image.height > (1u << 24))
        return Error{where + ": " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                     " pixels is too large for the PNG writer; render a smaller image"};

    const std::filesystem::path parent = path.parent_path();
    std::error_code ec;
    if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
        return Error{where + ": the directory " + parent.string() +
                     " does not exist; create it first (or check that the directory exists and is writable)"};

    std::vector<uint8_t> png;
    png.reserve(image.rgba.size() / 2);
    const int ok = stbi_write_png_to_func(&append, &png, int(image.width), int(image.height), 4, image.rgba.data(),
                                          int(image.width * 4));
    if (!ok) return Error{where + ": the PNG encoder failed (out of memory?)"};

    return write_file_with(path, [&](std::ostream& out) {
        out.write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
    });
}

Result<Image> read_png(const std::filesystem::path& path) {
    const std::string where = "cannot read PNG " + path.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        return Error{where + ": the file does not exist (or is not a regular file); check the path"};
    std::ifstream file(path, std::ios::binary);
    if (!file) return Error{where + " (" + std::strerror(errno) + "); check that the file is readable"};
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
    if (bytes.size() > size_t(std::numeric_limits<int>::max()))
        return Error{where + ": the file is too large (" + std::to_string(bytes.size()) + " bytes)"};

    int width = 0, height = 0, channels_in_file = 0;
    const std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
        stbi_load_from_memory(bytes.data(), int(bytes.size()), &width, &height, &channels_in_file, 4),
        &stbi_image_free);
    if (!pixels)
        return Error{where + ": " + (stbi_failure_reason() ? stbi_failure_reason() : "unknown decoder error") +
                     " (is it a valid PNG file?)"};

    Image image;
    image.width = uint32_t(width);
    image.height = uint32_t(height);
    image.rgba.assign(pixels.get(), pixels.get() + size_t(width) * size_t(height) * 4);
    return image;
}

}  // namespace aquaform
