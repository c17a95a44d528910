// Running POV-Ray 3.7 headless on an exported scene, the way TOOLING.md prescribes, for the pov judge
// (tests/pov_test.cpp) and `twinray diff --pov`.
#pragma once

#include "image/image.h"

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

namespace twinray::pov {

class PovrayError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The povray executable on PATH, if any.
std::optional<std::filesystem::path> find_povray();

// What POV-Ray reports of a render in its statistics (+GS): the CPU seconds of its parse, of building its
// bounding hierarchy and of tracing the image, all threads together.
struct PovrayStatistics {
    double parse_cpu_seconds = 0;
    double bounding_cpu_seconds = 0;
    double trace_cpu_seconds = 0;
};

// Renders `pov_text` in `folder` (clean, e.g. under the build tree): no display (-D), one ray per pixel
// (-A), 8-bit PNG without gamma (+FN8 File_Gamma=1.0), `threads` threads (+WTn), quiet but keeping warnings
// and errors (-GS -GR -GD), an empty povray.ini (POVINI), every message in NAME.log. With `statistics`, the
// statistics too (+GS), read back from the log into it. Throws PovrayError with the log's end when POV-Ray
// fails, or when statistics were asked for and the log lacks them.
Image render_with_povray(const std::filesystem::path& povray, const std::filesystem::path& folder,
                         const std::string& name, const std::string& pov_text, int width, int height, int threads = 1,
                         PovrayStatistics* statistics = nullptr);

}  // namespace twinray::pov
