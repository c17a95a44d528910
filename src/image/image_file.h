// Image files twinray writes: PNG through libpng, EXR through OpenEXR (reading any format is
// compare::read_image's). Writes are atomic: a temporary file in the target folder, renamed
// over the target only once complete, so a failed or interrupted write never leaves a partial image.
#pragma once

#include "image/image.h"

#include <filesystem>
#include <stdexcept>

namespace twinray {

class ImageFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Formats chosen by extension: ".png" (8-bit, floor(255*clamp(v,0,1) + 0.5), no gamma) or ".exr"
// (32-bit float, unclamped).
bool is_supported_image_path(const std::filesystem::path& path);
void write_image(const Image& image, const std::filesystem::path& path);

// The 8-bit value stored in a PNG for a linear colour component (docs/scene-format.md).
unsigned char quantize_8bit(float value);

}  // namespace twinray
