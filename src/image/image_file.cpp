#include "image/image_file.h"

#include "image/exr_file.h"
#include "image/png_file.h"
#include "io/atomic_file.h"
#include "io/file_handle.h"

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

std::string lowercase_extension(const fs::path& path) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return extension;
}

// Errors carry the libraries' or the system's words only; write_atomically names the target file.
// Both libraries write onto a stream of ours whose error flag and final flush and close are checked:
// a write that fails part-way (a full disk) must fail the image, not leave a truncated file to be
// renamed over the old image (tests/failure_test.cpp). OpenImageIO's PNG writer did not check its
// writes, and OpenEXR swallows errors in the destructor that writes its offset table.
void write_file(const Image& image, const fs::path& temporary, bool eight_bit) {
    io::FileHandle stream(std::fopen(temporary.c_str(), "wb"));
    if (!stream) {
        throw std::runtime_error(std::strerror(errno));
    }
    if (eight_bit) {
        write_png(image, stream.get());
    } else {
        write_exr(image, stream.get());
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
    try {
        io::write_atomically(path, [&](const fs::path& temporary) {
            write_file(image, temporary, lowercase_extension(path) == ".png");
        });
    } catch (const io::FileWriteError& error) {
        throw ImageFileError(error.what());
    }
}

}  // namespace twinray
