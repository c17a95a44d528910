// The comparison library (metrics, verdicts, worst pixels, heat maps, tolerance manifest) on images
// made by hand, so every expected number is known.
#include "compare/image_compare.h"
#include "compare/tolerances.h"
#include "image/image_file.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;
using twinray::Image;
using twinray::Rgb;
namespace compare = twinray::compare;

Image flat(int width, int height, Rgb colour) {
    Image image(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            image.at(x, y) = colour;
    return image;
}

TEST(CompareMetrics, OneChangedChannelIsFoundWithItsPixelChannelAndMagnitude) {
    Image a = flat(10, 10, {0.5f, 0.5f, 0.5f});
    Image b = a;
    b.at(7, 3).g = 0.75f;
    compare::Thresholds thresholds;  // fail = warn = 0.004
    compare::Metrics m = compare::measure(a, b, thresholds);
    EXPECT_NEAR(m.max_error, 0.25, 1e-7);
    EXPECT_EQ(m.max_x, 7);
    EXPECT_EQ(m.max_y, 3);
    EXPECT_EQ(m.max_channel, 1);
    EXPECT_EQ(m.fail_pixels, 1);
    EXPECT_EQ(m.pixel_count, 100);
    EXPECT_NEAR(m.mean_error, 0.25 / 300.0, 1e-9);  // mean over every channel of every pixel
}

TEST(CompareVerdict, FollowsIdiffFailPercentHardFailAndWarnRules) {
    Image a = flat(10, 10, {0, 0, 0});
    Image b = a;
    b.at(0, 0) = {0.1f, 0, 0};  // 1% of pixels off by 0.1
    compare::Thresholds t;
    t.fail = 0.05;
    t.fail_percent = 0;
    EXPECT_EQ(compare::judge(compare::measure(a, b, t), t), compare::Verdict::fail) << "1% > 0%";
    t.fail_percent = 2;
    EXPECT_EQ(compare::judge(compare::measure(a, b, t), t), compare::Verdict::warn) << "warn 0.004 with 0% allowed";
    t.warn_percent = 2;
    EXPECT_EQ(compare::judge(compare::measure(a, b, t), t), compare::Verdict::pass);
    t.hard_fail = 0.09;
    EXPECT_EQ(compare::judge(compare::measure(a, b, t), t), compare::Verdict::fail) << "0.1 > hard fail 0.09";
}

TEST(CompareMetrics, ImagesOfDifferentSizesAreRefused) {
    EXPECT_THROW(compare::measure(flat(4, 4, {}), flat(4, 5, {}), {}), compare::ImageReadError);
}

TEST(CompareWorstPixels, AreOrderedByErrorThenTopLeftFirst) {
    Image a = flat(5, 5, {0, 0, 0});
    Image b = a;
    b.at(4, 4) = {0.3f, 0, 0};
    b.at(1, 2) = {0, 0.5f, 0};
    b.at(3, 0) = {0, 0, 0.3f};
    auto worst = compare::worst_pixels(a, b, 3);
    ASSERT_EQ(worst.size(), 3u);
    EXPECT_EQ(worst[0].x, 1);
    EXPECT_EQ(worst[0].y, 2);
    EXPECT_EQ(worst[1].x, 3);  // 0.3 at row 0 before 0.3 at row 4
    EXPECT_EQ(worst[2].x, 4);
    EXPECT_NEAR(worst[0].error, 0.5, 1e-7);
}

TEST(CompareHeatMap, UsesAFixedScaleSoErrorsAtTheScaleAreBrightestAndZeroIsDark) {
    Image a = flat(3, 1, {0, 0, 0});
    Image b = a;
    b.at(1, 0) = {0.01f, 0, 0};
    b.at(2, 0) = {0.5f, 0, 0};  // far over the scale: clamped to the brightest
    Image map = compare::error_heat_map(a, b, 0.01);
    auto brightness = [&](int x) { return map.at(x, 0).r + map.at(x, 0).g + map.at(x, 0).b; };
    EXPECT_LT(brightness(0), 0.1f) << "zero error is near black in inferno";
    EXPECT_GT(brightness(1), 2.0f) << "an error at the scale is the brightest colour";
    EXPECT_NEAR(brightness(1), brightness(2), 1e-6);
}

TEST(CompareQuantized, MatchesWhatAnEightBitPngStores) {
    Image image = flat(1, 1, {0.5f, 1.7f, -0.2f});
    Image stored = compare::quantized_8bit(image);
    EXPECT_FLOAT_EQ(stored.at(0, 0).r, 128.0f / 255.0f);
    EXPECT_FLOAT_EQ(stored.at(0, 0).g, 1.0f);
    EXPECT_FLOAT_EQ(stored.at(0, 0).b, 0.0f);
}

TEST(ToleranceManifest, ProjectManifestGivesEveryScenePlausibleThresholds) {
    auto manifest = compare::ToleranceManifest::load(fs::path(TWINRAY_SOURCE_DIR) / "tests" / "tolerances.json");
    compare::SceneTolerances spheres = manifest.for_scene("spheres");
    compare::SceneTolerances unknown = manifest.for_scene("not-a-scene");
    EXPECT_DOUBLE_EQ(spheres.sse.fail_percent, 0.01);
    EXPECT_DOUBLE_EQ(unknown.sse.fail_percent, 0.1) << "scenes without an entry get the defaults";
    EXPECT_DOUBLE_EQ(unknown.sse.fail, 1.0 / 255.0);
    EXPECT_FALSE(spheres.why.empty());
}

TEST(ToleranceManifest, UnknownKeyIsRefusedWithItsPath) {
    fs::path file = fs::path(TWINRAY_TEST_OUTPUT_DIR) / "bad_tolerances.json";
    fs::create_directories(file.parent_path());
    std::ofstream(file) << R"({"scenes": {"csg": {"sse": {"failpercent": 1}}}})";
    try {
        compare::ToleranceManifest::load(file);
        FAIL() << "a misspelt key must be refused";
    } catch (const std::runtime_error& error) {
        EXPECT_NE(std::string(error.what()).find("scenes.csg.sse.failpercent"), std::string::npos) << error.what();
    }
}

TEST(CompareReadImage, ReadsBackWhatWriteImageWrote) {
    fs::path file = fs::path(TWINRAY_TEST_OUTPUT_DIR) / "roundtrip.exr";
    fs::create_directories(file.parent_path());
    Image image = flat(3, 2, {0.25f, 2.5f, -1.0f});
    twinray::write_image(image, file);
    Image back = compare::read_image(file);
    EXPECT_TRUE(back == image);
    EXPECT_THROW(compare::read_image(fs::path(TWINRAY_TEST_OUTPUT_DIR) / "no_such.png"), compare::ImageReadError);
}

fs::path test_image(const std::string& name) {
    return fs::path(TWINRAY_SOURCE_DIR) / "tests" / "data" / "images" / name;
}

std::string refusal_of(const fs::path& file, std::int64_t pixel_limit = twinray::max_image_pixels) {
    try {
        compare::read_image(file, pixel_limit);
    } catch (const compare::ImageReadError& error) {
        return error.what();
    }
    return "";
}

// tests/data/images/ holds small files made with oiiotool (they also seed the image fuzz target).
TEST(CompareReadImage, EightBitPngCornersReadAsTheirColours) {
    Image image = compare::read_image(test_image("rgb8.png"));
    ASSERT_EQ(image.width(), 5);
    ASSERT_EQ(image.height(), 3);
    EXPECT_TRUE((image.at(0, 0) == Rgb{1, 0, 0})) << image.at(0, 0).r << " " << image.at(0, 0).g;
    EXPECT_TRUE((image.at(4, 0) == Rgb{0, 1, 0})) << image.at(4, 0).r << " " << image.at(4, 0).g;
    EXPECT_TRUE((image.at(0, 2) == Rgb{0, 0, 1})) << image.at(0, 2).b;
    EXPECT_TRUE((image.at(4, 2) == Rgb{1, 1, 1})) << image.at(4, 2).r;
}

TEST(CompareReadImage, GreyIsExpandedToThreeEqualChannelsAndAlphaIsDropped) {
    Image grey = compare::read_image(test_image("grey8.png"));
    EXPECT_TRUE((grey.at(0, 0) == Rgb{0, 0, 0}));
    EXPECT_TRUE((grey.at(2, 0) == Rgb{1, 1, 1}));
    Image rgba = compare::read_image(test_image("rgba16.png"));
    EXPECT_NEAR(rgba.at(0, 0).r, 0.2f, 1.0f / 65535) << "16-bit PNG, top row";
    EXPECT_NEAR(rgba.at(0, 0).b, 0.6f, 1.0f / 65535);
}

TEST(CompareReadImage, HalfExrKeepsValuesOutsideZeroToOne) {
    Image image = compare::read_image(test_image("rgb_half.exr"));
    EXPECT_TRUE((image.at(0, 0) == Rgb{0, 0.5f, 1})) << image.at(0, 0).g;
    EXPECT_TRUE((image.at(3, 1) == Rgb{2.5f, -1, 0.25f})) << image.at(3, 1).r << " " << image.at(3, 1).g;
    Image tiled = compare::read_image(test_image("tiled_piz.exr"));
    EXPECT_NEAR(tiled.at(5, 3).b, 0.9f, 1e-3f) << "a 4 x 4-tiled, PIZ-compressed EXR, last pixel of the second tile";
}

TEST(CompareReadImage, AnImageOverThePixelLimitIsRefusedFromItsHeader) {
    std::string refusal = refusal_of(test_image("rgb8.png"), 14);
    EXPECT_NE(refusal.find("5 x 3 is 15 pixels, more than the limit of 14"), std::string::npos) << refusal;
    EXPECT_EQ(refusal_of(test_image("rgb8.png"), 15), "");
}

TEST(CompareReadImage, TheExtensionChoosesTheReaderWithoutFallingBackToOthers) {
    fs::path folder = fs::path(TWINRAY_TEST_OUTPUT_DIR) / "misnamed";
    fs::create_directories(folder);
    fs::copy_file(test_image("rgb8.png"), folder / "png_inside.exr", fs::copy_options::overwrite_existing);
    std::string refusal = refusal_of(folder / "png_inside.exr");
    EXPECT_NE(refusal.find("png_inside.exr"), std::string::npos) << refusal;
    std::ofstream(folder / "notes.txt") << "not an image";
    EXPECT_NE(refusal_of(folder / "notes.txt").find("notes.txt"), std::string::npos);
}

}  // namespace
