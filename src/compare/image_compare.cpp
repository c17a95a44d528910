#include "compare/image_compare.h"

#include "image/exr_file.h"
#include "image/image_file.h"
#include "image/openimageio_module.h"
#include "image/png_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace twinray::compare {
namespace {

// Sums and extremes over the pixels, each channel judged as idiff (OpenImageIO's ImageBufAlgo::compare)
// judges it, so that `twinray compare` prints what idiff prints for the same two images.
class Accumulator {
public:
    Accumulator(const Thresholds& thresholds)
        : fail_(static_cast<float>(thresholds.fail)), warn_(static_cast<float>(thresholds.warn)) {}

    void add_pixel(int x, int y, const Rgb& a, const Rgb& b) {
        pixel_warned_ = pixel_failed_ = false;
        add(x, y, 0, a.r, b.r);
        add(x, y, 1, a.g, b.g);
        add(x, y, 2, a.b, b.b);
        if (++pixels_in_batch_ == batch_pixels) {
            end_batch();
        }
    }

    Metrics finish(long pixel_count) {
        end_batch();
        const double values = 3.0 * static_cast<double>(pixel_count);
        metrics_.mean_error = total_ / values;
        metrics_.rms_error = std::sqrt(total_squares_ / values);
        metrics_.psnr = 20.0 * std::log10(largest_value_ / metrics_.rms_error);
        metrics_.pixel_count = pixel_count;
        return metrics_;
    }

private:
    // Sums of 4096 pixels at a time, then added to the totals, as idiff does, so that the sums round
    // alike: a total far larger than each pixel's error would swallow it.
    static constexpr int batch_pixels = 4096;

    void add(int x, int y, int channel, float a, float b) {
        if (!std::isfinite(a) || !std::isfinite(b)) {
            // NaN matches NaN and infinity matches infinity; any other non-finite difference is the
            // largest error, found once.
            if (std::isnan(a) == std::isnan(b) && std::isinf(a) == std::isinf(b)) {
                return;
            }
            if (std::isfinite(metrics_.max_error)) {
                metrics_.max_error = std::numeric_limits<float>::infinity();
                place_max(x, y, channel);
                return;
            }
        }
        const float a_size = std::abs(a), b_size = std::abs(b);
        largest_value_ = std::max(largest_value_, std::max(a_size, b_size));
        const double difference = std::fabs(a - b);  // in float, as idiff subtracts
        batch_total_ += difference;
        batch_squares_ += difference * difference;
        // !(d <= limit) rather than d > limit: a NaN difference counts as over every limit.
        if (!(difference <= metrics_.max_error)) {
            metrics_.max_error = difference;
            place_max(x, y, channel);
        }
        // idiff also asks the difference relative to the mean size of the two values to exceed a
        // limit, 0 here; that rules out a NaN against a number (their mean size is NaN).
        const auto mean_size = static_cast<float>(a_size * 0.5 + b_size * 0.5);
        const double relative = mean_size > 0.0 ? difference / mean_size : 0.0;
        if (relative <= 0.0) {
            return;
        }
        if (!pixel_warned_ && !(difference <= warn_)) {
            ++metrics_.warn_pixels;
            pixel_warned_ = true;
        }
        if (!pixel_failed_ && !(difference <= fail_)) {
            ++metrics_.fail_pixels;
            pixel_failed_ = true;
        }
    }

    void place_max(int x, int y, int channel) {
        metrics_.max_x = x;
        metrics_.max_y = y;
        metrics_.max_channel = channel;
    }

    void end_batch() {
        total_ += batch_total_;
        total_squares_ += batch_squares_;
        batch_total_ = batch_squares_ = 0;
        pixels_in_batch_ = 0;
    }

    float fail_, warn_;
    Metrics metrics_;
    float largest_value_ = 1;  // the PSNR's peak: 1, or the largest magnitude if larger
    double total_ = 0, total_squares_ = 0, batch_total_ = 0, batch_squares_ = 0;
    int pixels_in_batch_ = 0;
    bool pixel_warned_ = false, pixel_failed_ = false;
};

// OpenImageIO's inferno gives linear colours; PNGs here store values as they are (no gamma), so the colours
// are sRGB-encoded to show the colour map as published: linear ones crush its dark end, a decade of the
// logarithmic map, towards black.
Image inferno_for_display(const Image& levels) {
    Image colours = inferno_colour_map(levels);
    auto encode = [](float linear) {
        return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
    };
    for (int y = 0; y < colours.height(); ++y) {
        for (int x = 0; x < colours.width(); ++x) {
            Rgb& colour = colours.at(x, y);
            colour = {encode(colour.r), encode(colour.g), encode(colour.b)};
        }
    }
    return colours;
}

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text;
}

}  // namespace

void require_same_size(const Image& a, const Image& b) {
    if (a.width() != b.width() || a.height() != b.height()) {
        throw ImageReadError("the images differ in size: " + std::to_string(a.width()) + " x " +
                             std::to_string(a.height()) + " and " + std::to_string(b.width()) + " x " +
                             std::to_string(b.height()));
    }
}

double largest_channel_difference(const Rgb& a, const Rgb& b) {
    return std::max({std::fabs(static_cast<double>(a.r) - b.r), std::fabs(static_cast<double>(a.g) - b.g),
                     std::fabs(static_cast<double>(a.b) - b.b)});
}

const char* to_string(Verdict verdict) {
    switch (verdict) {
        case Verdict::pass: return "PASS";
        case Verdict::warn: return "WARN";
        case Verdict::fail: return "FAIL";
    }
    return "?";
}

Metrics measure(const Image& a, const Image& b, const Thresholds& thresholds) {
    require_same_size(a, b);
    Accumulator accumulator(thresholds);
    for (int y = 0; y < a.height(); ++y) {
        for (int x = 0; x < a.width(); ++x) {
            accumulator.add_pixel(x, y, a.at(x, y), b.at(x, y));
        }
    }
    return accumulator.finish(static_cast<long>(a.pixels().size()));
}

Verdict judge(const Metrics& metrics, const Thresholds& thresholds) {
    double total = static_cast<double>(std::max(metrics.pixel_count, 1L));
    if (100.0 * static_cast<double>(metrics.fail_pixels) / total > thresholds.fail_percent ||
        metrics.max_error > thresholds.hard_fail) {
        return Verdict::fail;
    }
    if (100.0 * static_cast<double>(metrics.warn_pixels) / total > thresholds.warn_percent) {
        return Verdict::warn;
    }
    return Verdict::pass;
}

std::vector<PixelError> worst_pixels(const Image& a, const Image& b, int count) {
    require_same_size(a, b);
    std::vector<PixelError> all;
    all.reserve(a.pixels().size());
    for (int y = 0; y < a.height(); ++y) {
        for (int x = 0; x < a.width(); ++x) {
            all.push_back({x, y, largest_channel_difference(a.at(x, y), b.at(x, y))});
        }
    }
    auto worse = [](const PixelError& p, const PixelError& q) {
        return p.error != q.error ? p.error > q.error : (p.y != q.y ? p.y < q.y : p.x < q.x);
    };
    std::size_t keep = std::min(all.size(), static_cast<std::size_t>(std::max(count, 0)));
    std::partial_sort(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(keep), all.end(), worse);
    all.resize(keep);
    return all;
}

HeatMapScale HeatMapScale::linear(double brightest) {
    return HeatMapScale(0, brightest);
}

HeatMapScale HeatMapScale::logarithmic(double darkest, double brightest) {
    if (!(darkest > 0 && darkest < brightest)) {
        throw std::invalid_argument("a logarithmic heat map needs 0 < darkest < brightest");
    }
    return HeatMapScale(darkest, brightest);
}

double HeatMapScale::level(double error) const {
    if (error == 0) {
        return 0;
    }
    // !(error < brightest) rather than error >= brightest: a NaN or infinite error is the brightest.
    if (!(error < brightest_)) {
        return 1;
    }
    if (!is_logarithmic()) {
        return error / brightest_;
    }
    const double decades = std::log10(brightest_ / darkest_);
    const double above_darkest = std::max(0.0, std::log10(error / darkest_));
    return (1 + above_darkest) / (decades + 1);
}

Image error_heat_map(const Image& a, const Image& b, const HeatMapScale& scale) {
    require_same_size(a, b);
    Image grey(a.width(), a.height());
    for (int y = 0; y < a.height(); ++y) {
        for (int x = 0; x < a.width(); ++x) {
            auto level = static_cast<float>(scale.level(largest_channel_difference(a.at(x, y), b.at(x, y))));
            grey.at(x, y) = {level, level, level};
        }
    }
    return inferno_for_display(grey);
}

Image heat_map_legend(const HeatMapScale& scale, int width, int height) {
    Image grey(width, height);
    for (int x = 0; x < width; ++x) {
        const double position = width > 1 ? static_cast<double>(x) / (width - 1) : 0.0;
        const double error = scale.is_logarithmic()
                                 ? scale.darkest() * std::pow(scale.brightest() / scale.darkest(), position)
                                 : scale.brightest() * position;
        const auto level = static_cast<float>(scale.level(error));
        for (int y = 0; y < height; ++y) {
            grey.at(x, y) = {level, level, level};
        }
    }
    return inferno_for_display(grey);
}

std::vector<LegendTick> legend_ticks(const HeatMapScale& scale) {
    if (!scale.is_logarithmic()) {
        return {{0, 0}, {scale.brightest() / 2, 0.5}, {scale.brightest(), 1}};
    }
    const double decades = std::log10(scale.brightest() / scale.darkest());
    std::vector<LegendTick> ticks;
    for (int decade = 0; decade <= static_cast<int>(decades + 1e-9); ++decade) {
        ticks.push_back({scale.darkest() * std::pow(10.0, decade), decade / decades});
    }
    return ticks;
}

Image fail_mask(const Image& reference, const Image& other, double fail) {
    require_same_size(reference, other);
    Image mask(reference.width(), reference.height());
    for (int y = 0; y < reference.height(); ++y) {
        for (int x = 0; x < reference.width(); ++x) {
            const Rgb& r = reference.at(x, y);
            bool fails = largest_channel_difference(r, other.at(x, y)) > fail;
            mask.at(x, y) = fails ? Rgb{1, 1, 1} : Rgb{0.25f * r.r, 0.25f * r.g, 0.25f * r.b};
        }
    }
    return mask;
}

Image clamped(const Image& image) {
    Image out(image.width(), image.height());
    auto clamp = [](float v) { return std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f); };
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            const Rgb& p = image.at(x, y);
            out.at(x, y) = {clamp(p.r), clamp(p.g), clamp(p.b)};
        }
    }
    return out;
}

Image quantized_8bit(const Image& image) {
    Image out(image.width(), image.height());
    auto level = [](float v) { return static_cast<float>(quantize_8bit(v)) / 255.0f; };
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            const Rgb& p = image.at(x, y);
            out.at(x, y) = {level(p.r), level(p.g), level(p.b)};
        }
    }
    return out;
}

Image read_image(const std::filesystem::path& path, std::int64_t pixel_limit) {
    const std::string extension = path.extension().string();
    if (extension.size() < 2) {
        throw ImageReadError("cannot read " + path.string() +
                             ": no extension to name its format (.png, .exr, or another that OpenImageIO reads)");
    }
    // PNG through libpng, the most common case, without OpenImageIO's start-up; any other format
    // through OpenImageIO, loaded then (image/openimageio_module.h), an EXR once its header's claims
    // are checked.
    try {
        const std::string format = lowercase(extension);
        if (format == ".png") {
            return read_png(path, pixel_limit);
        }
        if (format == ".exr") {
            check_exr_header_claims(path, pixel_limit);
        }
        return read_with_openimageio(path, pixel_limit);
    } catch (const std::runtime_error& error) {
        throw ImageReadError("cannot read " + path.string() + ": " + error.what());
    }
}

}  // namespace twinray::compare
