// The body of libtwinray_openimageio.so (image/openimageio_module.h): the only code linked to
// OpenImageIO.
#include "image/openimageio_module.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>

namespace twinray {
namespace {

namespace OIIO = OIIO_NAMESPACE;

// `channels` samples per pixel (1: grey, expanded; 3: RGB), row-major.
Image from_samples(const float* samples, int width, int height, int channels) {
    Image image(width, height);
    std::size_t pixel = 0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x, ++pixel) {
            const float* p = samples + pixel * static_cast<std::size_t>(channels);
            image.at(x, y) = channels == 3 ? Rgb{p[0], p[1], p[2]} : Rgb{p[0], p[0], p[0]};
        }
    }
    return image;
}

Image read(const std::filesystem::path& path, std::int64_t pixel_limit) {
    // An ImageInput rather than an ImageBuf: no shared ImageCache that would remember a file by its name.
    // The reader is the one the extension names, without OpenImageIO's fallback of trying every other
    // format on a file its reader refuses: a damaged file is reported as such, and only one parser
    // reads bytes it did not expect.
    // (Given a file name, ImageInput::create sniffs the content; given the format's name, it cannot.)
    std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::create(path.extension().string().substr(1));
    if (!input) {
        throw std::runtime_error(OIIO::geterror());
    }
    OIIO::ImageSpec header;
    if (!input->open(path.string(), header)) {
        throw std::runtime_error(input->geterror());
    }
    // The header first: any file can claim any size, so the size is checked before pixels are allocated.
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.nchannels < 1 || spec.width < 1 || spec.height < 1 || spec.depth != 1) {
        throw std::runtime_error("not a 2-D image with pixels");
    }
    std::int64_t pixel_count = std::int64_t{spec.width} * spec.height;
    if (pixel_count > pixel_limit) {
        throw std::runtime_error(std::to_string(spec.width) + " x " + std::to_string(spec.height) + " is " +
                                 std::to_string(pixel_count) + " pixels, more than the limit of " +
                                 std::to_string(pixel_limit));
    }
    // Grey is read as one channel and expanded; a fourth channel and beyond (alpha) are never read.
    int channels = std::min(spec.nchannels, 3);
    // Not zero-filled: a truncated file that claims 8192 x 8192 fails without touching 768 MiB first.
    auto samples = std::make_unique_for_overwrite<float[]>(static_cast<std::size_t>(pixel_count) *
                                                           static_cast<std::size_t>(channels));
    if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, samples.get())) {
        throw std::runtime_error(input->geterror());
    }
    return from_samples(samples.get(), spec.width, spec.height, channels);
}

Image inferno(const Image& grey) {
    OIIO::ImageSpec spec(grey.width(), grey.height(), 3, OIIO::TypeDesc::FLOAT);
    // A read-only view of the grey image (no copy).
    const OIIO::ImageBuf source(spec, const_cast<Rgb*>(grey.pixels().data()));
    const OIIO::ImageBuf mapped = OIIO::ImageBufAlgo::color_map(source, 0, "inferno");
    std::vector<float> samples(grey.pixels().size() * 3);
    if (mapped.has_error() || !mapped.get_pixels(mapped.roi(), OIIO::TypeDesc::FLOAT, samples.data())) {
        throw std::runtime_error("colour map: " + mapped.geterror());
    }
    return from_samples(samples.data(), grey.width(), grey.height(), 3);
}

const OpenImageIoFunctions functions{read, inferno};

}  // namespace
}  // namespace twinray

extern "C" const twinray::OpenImageIoFunctions* twinray_openimageio_functions() {
    return &twinray::functions;
}
