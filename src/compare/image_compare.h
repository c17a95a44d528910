// Comparing two images the way idiff does (OpenImageIO's ImageBufAlgo::compare): metrics, a verdict
// against thresholds, an error heat map on a fixed scale, a mask of failing pixels and the worst pixels.
#pragma once

#include "image/image.h"

#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace twinray::compare {

// idiff's semantics: a pixel fails (warns) where any channel differs by more than `fail` (`warn`); the
// comparison FAILS when more than `fail_percent` % of pixels fail or any difference exceeds
// `hard_fail`, else WARNS when more than `warn_percent` % of pixels warn, else PASSES.
struct Thresholds {
    double fail = 0.004;
    double fail_percent = 0;
    double hard_fail = std::numeric_limits<double>::infinity();
    double warn = 0.004;
    double warn_percent = 0;
};

enum class Verdict { pass = 0, warn = 1, fail = 2 };

const char* to_string(Verdict verdict);

struct Metrics {
    double mean_error = 0;
    double rms_error = 0;
    double psnr = 0;
    double max_error = 0;
    int max_x = 0, max_y = 0, max_channel = 0;  // where the max error is (channel 0 = R)
    long warn_pixels = 0;
    long fail_pixels = 0;
    long pixel_count = 0;
};

struct PixelError {
    int x, y;
    double error;  // largest channel difference
};

class ImageReadError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Refuses images of different sizes (OpenImageIO would compare the union of their windows).
Metrics measure(const Image& a, const Image& b, const Thresholds& thresholds);
Verdict judge(const Metrics& metrics, const Thresholds& thresholds);

// The `count` pixels with the largest difference, largest first (ties: top-left first).
std::vector<PixelError> worst_pixels(const Image& a, const Image& b, int count);

// Per pixel, the largest channel difference mapped through the "inferno" colour map with 0 black and
// `scale` (and above) brightest: a fixed scale, so small errors do not vanish next to one outlier.
Image error_heat_map(const Image& a, const Image& b, double scale);
// A horizontal bar of the same colour map, 0 on the left and `scale` on the right.
Image heat_map_legend(int width, int height);
// White where a pixel fails (any channel differs by more than `fail`), the reference dimmed elsewhere.
Image fail_mask(const Image& reference, const Image& other, double fail);

// Each component clamped to [0, 1] (as any stored image), and as an 8-bit PNG stores it:
// round(255·clamp(v)) / 255.
Image clamped(const Image& image);
Image quantized_8bit(const Image& image);

// PNG (libpng) or any other format OpenImageIO reads, chosen by the extension, as float RGB (grey is
// expanded, alpha dropped). Throws ImageReadError for anything else, including images of more than
// `pixel_limit` pixels (checked from the header alone).
Image read_image(const std::filesystem::path& path, std::int64_t pixel_limit = max_image_pixels);

}  // namespace twinray::compare
