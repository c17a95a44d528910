#include "compare/image_compare.h"

#include "image/image_file.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

namespace twinray::compare {
namespace {

namespace OIIO = OIIO_NAMESPACE;

// A read-only view of our image as an OpenImageIO buffer (no copy).
OIIO::ImageBuf view(const Image& image) {
    OIIO::ImageSpec spec(image.width(), image.height(), 3, OIIO::TypeDesc::FLOAT);
    return OIIO::ImageBuf(spec, const_cast<Rgb*>(image.pixels().data()));
}

Image from_buffer(const OIIO::ImageBuf& buffer) {
    const OIIO::ImageSpec& spec = buffer.spec();
    Image image(spec.width, spec.height);
    std::vector<float> pixels(static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) * 3);
    OIIO::ROI rgb(spec.x, spec.x + spec.width, spec.y, spec.y + spec.height, 0, 1, 0, 3);
    if (!buffer.get_pixels(rgb, OIIO::TypeDesc::FLOAT, pixels.data())) {
        throw ImageReadError(buffer.geterror());
    }
    for (int y = 0; y < spec.height; ++y) {
        for (int x = 0; x < spec.width; ++x) {
            const float* p = &pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(spec.width) +
                                      static_cast<std::size_t>(x)) *
                                     3];
            image.at(x, y) = {p[0], p[1], p[2]};
        }
    }
    return image;
}

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

Image grey_ramp_through_inferno(const Image& grey) {
    OIIO::ImageBuf mapped = OIIO::ImageBufAlgo::color_map(view(grey), 0, "inferno");
    if (mapped.has_error()) {
        throw std::runtime_error("colour map: " + mapped.geterror());
    }
    return from_buffer(mapped);
}

}  // namespace

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
    OIIO::ImageBufAlgo::CompareResults result = OIIO::ImageBufAlgo::compare(
        view(a), view(b), static_cast<float>(thresholds.fail), static_cast<float>(thresholds.warn));
    Metrics metrics;
    metrics.mean_error = result.meanerror;
    metrics.rms_error = result.rms_error;
    metrics.psnr = result.PSNR;
    metrics.max_error = result.maxerror;
    metrics.max_x = result.maxx;
    metrics.max_y = result.maxy;
    metrics.max_channel = result.maxc;
    metrics.warn_pixels = static_cast<long>(result.nwarn);
    metrics.fail_pixels = static_cast<long>(result.nfail);
    metrics.pixel_count = static_cast<long>(a.pixels().size());
    return metrics;
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

Image error_heat_map(const Image& a, const Image& b, double scale) {
    require_same_size(a, b);
    Image grey(a.width(), a.height());
    for (int y = 0; y < a.height(); ++y) {
        for (int x = 0; x < a.width(); ++x) {
            auto level = static_cast<float>(std::min(1.0, largest_channel_difference(a.at(x, y), b.at(x, y)) / scale));
            grey.at(x, y) = {level, level, level};
        }
    }
    return grey_ramp_through_inferno(grey);
}

Image heat_map_legend(int width, int height) {
    Image grey(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            float level = width > 1 ? static_cast<float>(x) / static_cast<float>(width - 1) : 0.0f;
            grey.at(x, y) = {level, level, level};
        }
    }
    return grey_ramp_through_inferno(grey);
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
    std::string name = path.string();
    auto refuse = [&name](const std::string& why) { return ImageReadError("cannot read " + name + ": " + why); };
    // An ImageInput rather than an ImageBuf: no shared ImageCache that would remember a file by its name.
    // The reader is the one the extension names, without OpenImageIO's fallback of trying every other
    // format on a file its reader refuses: a damaged .png is reported as such, and only one parser
    // reads bytes it did not expect.
    // (Given a file name, ImageInput::create sniffs the content; given the format's name, it cannot.)
    std::string format = path.extension().string();
    if (format.size() < 2) {
        throw refuse("no extension to name its format (.png, .exr, or another that OpenImageIO reads)");
    }
    std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::create(format.substr(1));
    if (!input) {
        throw refuse(OIIO::geterror());
    }
    OIIO::ImageSpec header;
    if (!input->open(name, header)) {
        throw refuse(input->geterror());
    }
    // The header first: any file can claim any size, so the size is checked before pixels are allocated.
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.nchannels < 1 || spec.width < 1 || spec.height < 1 || spec.depth != 1) {
        throw refuse("not a 2-D image with pixels");
    }
    std::int64_t pixel_count = std::int64_t{spec.width} * spec.height;
    if (pixel_count > pixel_limit) {
        throw refuse(std::to_string(spec.width) + " x " + std::to_string(spec.height) + " is " +
                     std::to_string(pixel_count) + " pixels, more than the limit of " + std::to_string(pixel_limit));
    }
    // Grey is read as one channel and expanded; a fourth channel and beyond (alpha) are never read.
    int channels = std::min(spec.nchannels, 3);
    // Not zero-filled: a truncated file that claims 8192 x 8192 fails without touching 768 MiB first.
    auto samples = std::make_unique_for_overwrite<float[]>(static_cast<std::size_t>(pixel_count) *
                                                           static_cast<std::size_t>(channels));
    if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, samples.get())) {
        throw refuse(input->geterror());
    }
    Image image(spec.width, spec.height);
    for (int y = 0; y < spec.height; ++y) {
        for (int x = 0; x < spec.width; ++x) {
            const float* p = &samples[(static_cast<std::size_t>(y) * static_cast<std::size_t>(spec.width) +
                                       static_cast<std::size_t>(x)) *
                                      static_cast<std::size_t>(channels)];
            image.at(x, y) = channels == 3 ? Rgb{p[0], p[1], p[2]} : Rgb{p[0], p[0], p[0]};
        }
    }
    return image;
}

}  // namespace twinray::compare
