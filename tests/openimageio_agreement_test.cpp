// twinray reads and writes PNG and EXR without OpenImageIO (libpng, OpenEXR) and computes idiff's
// metrics itself, so that processes that touch no other format never load OpenImageIO's 260 libraries
// (docs/performance.md, "Whole process"). This test, linked to OpenImageIO, holds each of those to what
// OpenImageIO gives for the same files and images, bit for bit.
#include "compare/image_compare.h"
#include "image/image_file.h"
#include "scene/portable_random.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace OIIO = OIIO_NAMESPACE;
using twinray::Image;
using twinray::Rgb;
namespace compare = twinray::compare;

fs::path output(const std::string& name) {
    fs::path folder = fs::path(TWINRAY_TEST_OUTPUT_DIR) / "openimageio_agreement";
    fs::create_directories(folder);
    return folder / name;
}

OIIO::ImageBuf view(const Image& image) {
    OIIO::ImageSpec spec(image.width(), image.height(), 3, OIIO::TypeDesc::FLOAT);
    return OIIO::ImageBuf(spec, const_cast<Rgb*>(image.pixels().data()));
}

// The file as OpenImageIO reads it: float RGB, grey expanded, alpha dropped.
Image read_with_openimageio(const fs::path& file) {
    OIIO::ImageBuf buffer(file.string());
    EXPECT_TRUE(buffer.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << buffer.geterror();
    const OIIO::ImageSpec& spec = buffer.spec();
    Image image(spec.width, spec.height);
    for (int y = 0; y < spec.height; ++y) {
        for (int x = 0; x < spec.width; ++x) {
            float p[4] = {};
            buffer.getpixel(x, y, p, 4);
            image.at(x, y) = spec.nchannels < 3 ? Rgb{p[0], p[0], p[0]} : Rgb{p[0], p[1], p[2]};
        }
    }
    return image;
}

bool same_bits(const Image& a, const Image& b) {
    if (a.width() != b.width() || a.height() != b.height()) {
        return false;
    }
    return std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(Rgb)) == 0;
}

bool same(double a, double b) {
    return a == b || (std::isnan(a) && std::isnan(b));
}

// Values in and beyond [0, 1], with NaN and infinities sprinkled in both images.
Image noisy(int width, int height, std::uint64_t seed, double near) {
    twinray::SplitMix64 random(seed);
    Image image(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            float c[3];
            for (float& v : c) {
                const std::uint64_t pick = random.next() % 1000;
                v = pick == 0   ? std::numeric_limits<float>::quiet_NaN()
                    : pick == 1 ? std::numeric_limits<float>::infinity()
                    : pick == 2 ? -std::numeric_limits<float>::infinity()
                                : static_cast<float>(random.uniform(-0.2, 1.5) * near);
            }
            image.at(x, y) = {c[0], c[1], c[2]};
        }
    }
    return image;
}

TEST(OpenImageIoAgreement, MetricsAreIdiffsOnImagesWithNansInfinitiesAndValuesBeyondOne) {
    const std::pair<Image, Image> pairs[] = {
        {noisy(97, 61, 1, 1), noisy(97, 61, 2, 1)},
        {noisy(640, 480, 7, 1), noisy(640, 480, 8, 1)},
        {noisy(200, 150, 3, 1), noisy(200, 150, 3, 1.0001)},
        {noisy(64, 64, 5, 1), noisy(64, 64, 5, 1)},
    };
    for (const auto& [a, b] : pairs) {
        for (const double threshold : {0.0, 0.004, 0.5}) {
            compare::Thresholds thresholds;
            thresholds.fail = threshold;
            thresholds.warn = 2 * threshold;
            const compare::Metrics ours = compare::measure(a, b, thresholds);
            // On one thread: on several, OpenImageIO splits the image and each part's first non-finite
            // difference goes uncounted, so its counts depend on the thread count.
            const OIIO::ImageBufAlgo::CompareResults theirs =
                OIIO::ImageBufAlgo::compare(view(a), view(b), static_cast<float>(thresholds.fail),
                                            static_cast<float>(thresholds.warn), OIIO::ROI::All(), 1);
            EXPECT_TRUE(same(ours.mean_error, theirs.meanerror)) << ours.mean_error << " " << theirs.meanerror;
            EXPECT_TRUE(same(ours.rms_error, theirs.rms_error)) << ours.rms_error << " " << theirs.rms_error;
            EXPECT_TRUE(same(ours.psnr, theirs.PSNR)) << ours.psnr << " " << theirs.PSNR;
            EXPECT_EQ(ours.max_error, theirs.maxerror);
            EXPECT_EQ(ours.max_x, theirs.maxx);
            EXPECT_EQ(ours.max_y, theirs.maxy);
            EXPECT_EQ(ours.max_channel, theirs.maxc);
            EXPECT_EQ(ours.warn_pixels, static_cast<long>(theirs.nwarn));
            EXPECT_EQ(ours.fail_pixels, static_cast<long>(theirs.nfail));
        }
    }
}

TEST(OpenImageIoAgreement, PngsReadAsOpenImageIoReadsThem) {
    Image levels(256, 3);
    for (int x = 0; x < 256; ++x) {
        const float v = static_cast<float>(x) / 255.0f;
        levels.at(x, 0) = {v, 0, 1 - v};
        levels.at(x, 1) = {0.5f * v, v, 0};
        levels.at(x, 2) = {v, v, v};
    }
    twinray::write_image(levels, output("levels.png"));
    const fs::path images = fs::path(TWINRAY_SOURCE_DIR) / "tests" / "data" / "images";
    for (const fs::path& file : {output("levels.png"), images / "rgb8.png", images / "grey8.png"}) {
        SCOPED_TRACE(file.string());
        EXPECT_TRUE(same_bits(compare::read_image(file), read_with_openimageio(file)));
    }
}

// The one departure: OpenImageIO multiplies a PNG's colour by its alpha; twinray reads the colour as
// stored and drops alpha, as it does for every format (rgba16.png's pixel (1, 1) has alpha 0.875).
TEST(OpenImageIoAgreement, PngColourIsReadAsStoredWhereOpenImageIoMultipliesItByAlpha) {
    const fs::path file = fs::path(TWINRAY_SOURCE_DIR) / "tests" / "data" / "images" / "rgba16.png";
    const Image ours = compare::read_image(file), theirs = read_with_openimageio(file);
    EXPECT_TRUE((ours.at(0, 0) == theirs.at(0, 0))) << "alpha 1";
    EXPECT_NEAR(ours.at(1, 1).g * 0.875f, theirs.at(1, 1).g, 1e-4f);
}

TEST(OpenImageIoAgreement, WrittenFilesReadBackThroughOpenImageIoAsWritten) {
    const Image image = noisy(33, 17, 9, 1);
    twinray::write_image(image, output("noisy.exr"));
    EXPECT_TRUE(same_bits(read_with_openimageio(output("noisy.exr")), image)) << "EXR is float, unclamped";
    twinray::write_image(image, output("noisy.png"));
    OIIO::ImageBuf png(output("noisy.png").string());
    ASSERT_TRUE(png.read(0, 0, true, OIIO::TypeDesc::UINT8)) << png.geterror();
    ASSERT_EQ(png.spec().nchannels, 3);
    std::vector<unsigned char> levels(image.pixels().size() * 3);
    ASSERT_TRUE(png.get_pixels(png.roi(), OIIO::TypeDesc::UINT8, levels.data()));
    for (std::size_t i = 0; i < image.pixels().size(); ++i) {
        const Rgb& p = image.pixels()[i];
        ASSERT_EQ(levels[3 * i], twinray::quantize_8bit(p.r)) << i;
        ASSERT_EQ(levels[3 * i + 1], twinray::quantize_8bit(p.g)) << i;
        ASSERT_EQ(levels[3 * i + 2], twinray::quantize_8bit(p.b)) << i;
    }
}

}  // namespace
