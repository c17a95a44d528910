// OpenImageIO in a module of our own (libtwinray_openimageio.so), loaded with dlopen on first use:
// linking it would load its 260 libraries (GDAL, OpenVDB, FFmpeg, ...) into every process at start-up,
// about 0.3 s, also into the many that read no image (docs/performance.md, "Whole process").
#pragma once

#include "image/image.h"

#include <cstdint>
#include <filesystem>

namespace twinray {

// Any format OpenImageIO reads, chosen by the extension without falling back to others, as float RGB:
// grey expanded, alpha dropped, images of more than `pixel_limit` pixels refused from the header alone.
// Throws std::runtime_error with OpenImageIO's words, or when the module cannot be loaded.
Image read_with_openimageio(const std::filesystem::path& path, std::int64_t pixel_limit);

// Each pixel's red channel (0 to 1) through OpenImageIO's "inferno" colour map.
Image inferno_colour_map(const Image& grey);

// What the module offers, returned by its one exported symbol, twinray_openimageio_functions.
struct OpenImageIoFunctions {
    Image (*read)(const std::filesystem::path& path, std::int64_t pixel_limit);
    Image (*inferno)(const Image& grey);
};

}  // namespace twinray

extern "C" const twinray::OpenImageIoFunctions* twinray_openimageio_functions();
