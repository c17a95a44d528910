// OpenEXR files through OpenEXR itself, the library OpenImageIO uses for them, linked directly so that
// a process that writes an EXR does not load OpenImageIO's 260 libraries (docs/performance.md).
#pragma once

#include "image/image.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>

namespace twinray {

// 32-bit float RGB, unclamped, ZIP-compressed scanlines (as OpenImageIO wrote them), into an open stream;
// the caller checks and closes it. Throws std::runtime_error with OpenEXR's or the system's words.
void write_exr(const Image& image, std::FILE* stream);

// OpenEXR 3.1 allocates what a header claims before it reads or checks it: each attribute at its size
// field, a line or tile buffer at the data window's or tiles' size. So an EXR header is walked here
// first, without allocating, and a file is refused (std::runtime_error saying what it claims) when an
// attribute claims more bytes than the file holds, or the data window or a tile claims more pixels than
// `pixel_limit`. Single- and multi-part files; what it does not read, OpenEXR checks afterwards.
void check_exr_header_claims(const std::filesystem::path& path, std::int64_t pixel_limit);

}  // namespace twinray
