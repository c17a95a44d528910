// OpenEXR files through OpenEXR itself, the library OpenImageIO uses for them, linked directly so that
// a process that writes an EXR does not load OpenImageIO's 260 libraries (docs/performance.md).
#pragma once

#include "image/image.h"

#include <cstdio>

namespace twinray {

// 32-bit float RGB, unclamped, ZIP-compressed scanlines (as OpenImageIO wrote them), into an open stream;
// the caller checks and closes it. Throws std::runtime_error with OpenEXR's or the system's words.
void write_exr(const Image& image, std::FILE* stream);

}  // namespace twinray
