#include "image/image_file.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <system_error>
#include <unistd.h>
#include <vector>

namespace twinray {
namespace {

namespace fs = std::filesystem;
namespace OIIO = OIIO_NAMESPACE;

std::string lowercase_extension(const fs::path& path) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return extension;
}

// Same folder (so rename is atomic), same extension (OpenImageIO picks the format by it), and a name
// unique to this process.
fs::path temporary_sibling(const fs::path& path) {
    fs::path temporary = path;
    temporary.replace_filename("." + path.stem().string() + ".tmp" + std::to_string(::getpid()) +
                               path.extension().string());
    return temporary;
}

std::vector<unsigned char> to_8bit(const Image& image) {
    std::vector<unsigned char> bytes;
    bytes.reserve(image.pixels().size() * 3);
    for (const Rgb& pixel : image.pixels()) {
        bytes.push_back(quantize_8bit(pixel.r));
        bytes.push_back(quantize_8bit(pixel.g));
        bytes.push_back(quantize_8bit(pixel.b));
    }
    return bytes;
}

void write_file(const Image& image, const fs::path& path, bool eight_bit) {
    auto output = OIIO::ImageOutput::create(path.string());
    if (!output) {
        throw ImageFileError("cannot write " + path.string() + ": " + OIIO::geterror());
    }
    OIIO::ImageSpec spec(image.width(), image.height(), 3, eight_bit ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (!output->open(path.string(), spec)) {
        throw ImageFileError("cannot write " + path.string() + ": " + output->geterror());
    }
    bool written = eight_bit ? output->write_image(OIIO::TypeDesc::UINT8, to_8bit(image).data())
                             : output->write_image(OIIO::TypeDesc::FLOAT, image.pixels().data());
    bool closed = output->close();
    if (!written || !closed) {
        throw ImageFileError("cannot write " + path.string() + ": " + output->geterror());
    }
}

}  // namespace

unsigned char quantize_8bit(float value) {
    // In double, so that 255*v + 0.5 is exact for every float v and no rounding moves a level.
    double clamped = std::isnan(value) ? 0.0 : std::clamp(static_cast<double>(value), 0.0, 1.0);
    return static_cast<unsigned char>(std::floor(255.0 * clamped + 0.5));
}

bool is_supported_image_path(const fs::path& path) {
    std::string extension = lowercase_extension(path);
    return extension == ".png" || extension == ".exr";
}

void write_image(const Image& image, const fs::path& path) {
    if (!is_supported_image_path(path)) {
        throw ImageFileError("cannot write " + path.string() + ": unsupported image format \"" +
                             path.extension().string() + "\"; allowed: .png (8-bit) or .exr (float)");
    }
    static_assert(sizeof(Rgb) == 3 * sizeof(float), "Rgb must be three packed floats for OpenImageIO");
    fs::path temporary = temporary_sibling(path);
    try {
        write_file(image, temporary, lowercase_extension(path) == ".png");
        fs::rename(temporary, path);
    } catch (const std::exception& error) {
        std::error_code ignored;
        fs::remove(temporary, ignored);
        if (dynamic_cast<const ImageFileError*>(&error) != nullptr) {
            throw;
        }
        throw ImageFileError("cannot write " + path.string() + ": " + error.what());
    }
}

}  // namespace twinray
