#include "image/image_file.h"

#include "io/atomic_file.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
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

struct CloseFile {
    void operator()(std::FILE* stream) const { std::fclose(stream); }
};

// Errors carry OpenImageIO's words only; write_atomically names the target file.
// OpenImageIO 2.4's PNG writer does not check its writes: on a full disk it reports success and leaves
// a truncated file, which the rename would then put in place of the old image (tests/failure_test.cpp).
// So OpenImageIO writes through a stream of ours, whose error flag and final flush and close we check.
void write_file(const Image& image, const fs::path& temporary, bool eight_bit) {
    auto output = OIIO::ImageOutput::create(temporary.string());
    if (!output) {
        throw std::runtime_error(OIIO::geterror());
    }
    std::unique_ptr<std::FILE, CloseFile> stream(std::fopen(temporary.c_str(), "wb"));
    if (!stream) {
        throw std::runtime_error(std::strerror(errno));
    }
    OIIO::Filesystem::IOFile proxy(stream.get(), OIIO::Filesystem::IOProxy::Write);
    if (!output->set_ioproxy(&proxy)) {
        throw std::runtime_error(std::string("OpenImageIO cannot write ") + output->format_name() + " to a stream");
    }
    OIIO::ImageSpec spec(image.width(), image.height(), 3, eight_bit ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    if (!output->open(temporary.string(), spec)) {
        throw std::runtime_error(output->geterror());
    }
    bool written = eight_bit ? output->write_image(OIIO::TypeDesc::UINT8, to_8bit(image).data())
                             : output->write_image(OIIO::TypeDesc::FLOAT, image.pixels().data());
    bool closed = output->close();
    if (!written || !closed) {
        throw std::runtime_error(output->geterror());
    }
    bool stream_failed = std::ferror(stream.get()) != 0 || std::fflush(stream.get()) != 0;
    int stream_errno = errno;
    if (std::fclose(stream.release()) != 0 && !stream_failed) {
        stream_failed = true;
        stream_errno = errno;
    }
    if (stream_failed) {
        throw std::runtime_error(std::string("write failed: ") + std::strerror(stream_errno));
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
    try {
        io::write_atomically(path, [&](const fs::path& temporary) {
            write_file(image, temporary, lowercase_extension(path) == ".png");
        });
    } catch (const io::FileWriteError& error) {
        throw ImageFileError(error.what());
    }
}

}  // namespace twinray
