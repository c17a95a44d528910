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

// Throws ImageReadError unless both are of one size (OpenImageIO would compare the union of their windows);
// every comparison below refuses images of different sizes so.
void require_same_size(const Image& a, const Image& b);

Metrics measure(const Image& a, const Image& b, const Thresholds& thresholds);
Verdict judge(const Metrics& metrics, const Thresholds& thresholds);

// The `count` pixels with the largest difference, largest first (ties: top-left first).
std::vector<PixelError> worst_pixels(const Image& a, const Image& b, int count);

// A pixel's error as every map, mask and list here measures it: its largest channel difference.
double largest_channel_difference(const Rgb& a, const Rgb& b);

// How a heat map turns an error into a level of its colour map (0 black, 1 brightest). Fixed, so small
// errors do not vanish next to one outlier.
class HeatMapScale {
public:
    // 0 black, `brightest` (and above) brightest, evenly in between.
    static HeatMapScale linear(double brightest);
    // Decades from `darkest` to `brightest` evenly spaced, one more decade's width kept below `darkest` so
    // that exact zero alone is black: from 1e-7 to 1, 0 → 0, 1e-7 (and any error below it) → 1/8,
    // 1e-4 → 1/2, 1 (and above) → 1.
    static HeatMapScale logarithmic(double darkest, double brightest);

    double level(double error) const;
    bool is_logarithmic() const { return darkest_ > 0; }
    double darkest() const { return darkest_; }
    double brightest() const { return brightest_; }

private:
    HeatMapScale(double darkest, double brightest) : darkest_(darkest), brightest_(brightest) {}
    double darkest_;  // 0 for a linear scale
    double brightest_;
};

// Per pixel, the largest channel difference through the "inferno" colour map at the scale's level, in the
// map's published (sRGB-encoded) colours, ready to be viewed as stored.
Image error_heat_map(const Image& a, const Image& b, const HeatMapScale& scale);

// The scale's legend: a horizontal bar of `width` errors from the scale's lowest (0, or `darkest`) on the
// left to `brightest` on the right, each coloured as the map colours it, and where to label it.
Image heat_map_legend(const HeatMapScale& scale, int width, int height);
struct LegendTick {
    double error;
    double position;  // 0 at the bar's left edge, 1 at its right
};
// Each decade of a logarithmic scale; 0, the middle and `brightest` of a linear one.
std::vector<LegendTick> legend_ticks(const HeatMapScale& scale);
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
