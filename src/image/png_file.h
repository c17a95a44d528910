// PNG files through libpng, the library OpenImageIO itself uses for them, linked directly so that a
// process that writes or reads a PNG does not load OpenImageIO's 260 libraries (docs/performance.md).
#pragma once

#include "image/image.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>

namespace twinray {

// 8-bit RGB, each component quantize_8bit(v), into an open stream; the caller checks and closes it.
// Throws std::runtime_error with libpng's words.
void write_png(const Image& image, std::FILE* stream);

// Any PNG as float RGB: 8- and 16-bit samples divided by 255 or 65535 (no gamma), grey expanded to
// three channels, palettes expanded, alpha dropped (colour as stored, not multiplied by alpha). Images
// of more than `pixel_limit` pixels are refused from the header. Throws std::runtime_error saying why.
Image read_png(const std::filesystem::path& path, std::int64_t pixel_limit);

}  // namespace twinray
