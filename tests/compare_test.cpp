// The comparison library (metrics, verdicts, worst pixels, heat maps, failing clusters, tolerance manifest)
// on images made by hand, so every expected number is known.
#include "compare/failing_clusters.h"
#include "compare/image_compare.h"
#include "compare/tolerances.h"
#include "image/image_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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

TEST(CompareHeatMap, LinearScaleIsFixedSoErrorsAtTheScaleAreBrightestAndZeroIsDark) {
    Image a = flat(3, 1, {0, 0, 0});
    Image b = a;
    b.at(1, 0) = {0.01f, 0, 0};
    b.at(2, 0) = {0.5f, 0, 0};  // far over the scale: clamped to the brightest
    Image map = compare::error_heat_map(a, b, compare::HeatMapScale::linear(0.01));
    auto brightness = [&](int x) { return map.at(x, 0).r + map.at(x, 0).g + map.at(x, 0).b; };
    EXPECT_LT(brightness(0), 0.1f) << "zero error is near black in inferno";
    EXPECT_GT(brightness(1), 2.0f) << "an error at the scale is the brightest colour";
    EXPECT_NEAR(brightness(1), brightness(2), 1e-6);
}

// The report's scale: each decade from 1e-7 to 1 an eighth of the colour map, the lowest eighth kept for 0.
TEST(CompareHeatMap, LogarithmicScaleGivesEachDecadeAnEighthAndZeroAloneIsBlack) {
    const auto scale = compare::HeatMapScale::logarithmic(1e-7, 1);
    EXPECT_EQ(scale.level(0), 0.0);
    EXPECT_DOUBLE_EQ(scale.level(1e-9), 0.125) << "below 1e-7: the darkest colour, still not black";
    EXPECT_DOUBLE_EQ(scale.level(1e-7), 0.125);
    EXPECT_NEAR(scale.level(1e-4), 0.5, 1e-12);
    EXPECT_DOUBLE_EQ(scale.level(1), 1.0);
    EXPECT_DOUBLE_EQ(scale.level(3), 1.0);
    EXPECT_DOUBLE_EQ(scale.level(std::nan("")), 1.0) << "a NaN error is shown brightest, never hidden";

    Image a = flat(4, 1, {0, 0, 0});
    Image b = a;
    b.at(1, 0) = {0, 1e-7f, 0};
    b.at(2, 0) = {0, 0, 1e-4f};
    b.at(3, 0) = {1, 0, 0};
    Image map = compare::error_heat_map(a, b, scale);
    auto brightness = [&](int x) { return map.at(x, 0).r + map.at(x, 0).g + map.at(x, 0).b; };
    EXPECT_LT(brightness(0), 0.05f) << "no difference: black";
    EXPECT_GT(brightness(1), brightness(0) + 0.1f) << "1e-7 is dark but not black";
    EXPECT_GT(brightness(2), brightness(1) + 0.3f) << "1e-4, black on the old 4/255 scale, is visible";
    EXPECT_GT(brightness(3), 2.0f) << "1 is the brightest colour";
}

TEST(CompareHeatMap, LogarithmicLegendRunsFrom1e7To1WithATickPerDecade) {
    const auto scale = compare::HeatMapScale::logarithmic(1e-7, 1);
    std::vector<compare::LegendTick> ticks = compare::legend_ticks(scale);
    ASSERT_EQ(ticks.size(), 8u);
    for (std::size_t decade = 0; decade < ticks.size(); ++decade) {
        EXPECT_NEAR(ticks[decade].error, std::pow(10.0, static_cast<double>(decade) - 7), 1e-15) << decade;
        EXPECT_NEAR(ticks[decade].position, static_cast<double>(decade) / 7, 1e-12) << decade;
    }
    Image legend = compare::heat_map_legend(scale, 8, 1);
    Image zero = flat(1, 1, {0, 0, 0});
    auto map_colour = [&](float error) {
        return compare::error_heat_map(zero, flat(1, 1, {error, 0, 0}), scale).at(0, 0);
    };
    EXPECT_NEAR(legend.at(0, 0).r, map_colour(1e-7f).r, 1e-3) << "the bar starts at 1e-7's colour, not black";
    EXPECT_NEAR(legend.at(0, 0).b, map_colour(1e-7f).b, 1e-3);
    EXPECT_NEAR(legend.at(7, 0).g, map_colour(1.0f).g, 1e-6) << "and ends at 1's";
}

TEST(CompareClusters, TwoSeparateBlobsGiveTwoBoxesWithTheirBoundsLargestFirst) {
    Image a = flat(40, 30, {0.5f, 0.5f, 0.5f});
    Image b = a;
    for (int y = 3; y <= 5; ++y)
        for (int x = 2; x <= 6; ++x)
            b.at(x, y).r = 0.6f;  // 15 pixels
    for (int y = 20; y <= 27; ++y)
        for (int x = 30; x <= 33; ++x)
            b.at(x, y).g = 0.6f;  // 32 pixels
    b.at(32, 25).g = 0.9f;        // the worst pixel
    b.at(20, 12).b = 0.501f;      // under the threshold: in no cluster
    auto clusters = compare::failing_clusters(a, b, 0.01, 4, 20);
    ASSERT_EQ(clusters.size(), 2u);
    EXPECT_EQ(clusters[0].pixels, 32);
    EXPECT_EQ(clusters[0].left, 30);
    EXPECT_EQ(clusters[0].top, 20);
    EXPECT_EQ(clusters[0].right, 33);
    EXPECT_EQ(clusters[0].bottom, 27);
    EXPECT_EQ(clusters[0].worst.x, 32);
    EXPECT_EQ(clusters[0].worst.y, 25);
    EXPECT_NEAR(clusters[0].worst.error, 0.4, 1e-6);
    EXPECT_EQ(clusters[1].pixels, 15);
    EXPECT_EQ(clusters[1].left, 2);
    EXPECT_EQ(clusters[1].top, 3);
    EXPECT_EQ(clusters[1].right, 6);
    EXPECT_EQ(clusters[1].bottom, 5);
    EXPECT_EQ(clusters[1].worst.x, 2) << "ties: the top-left pixel";
    EXPECT_EQ(clusters[1].worst.y, 3);
    auto again = compare::failing_clusters(a, b, 0.01, 4, 20);
    ASSERT_EQ(again.size(), clusters.size());
    for (std::size_t i = 0; i < again.size(); ++i) {
        EXPECT_EQ(again[i].left, clusters[i].left);
        EXPECT_EQ(again[i].top, clusters[i].top);
        EXPECT_EQ(again[i].pixels, clusters[i].pixels);
    }
}

TEST(CompareClusters, PixelsWithinTheGapMergeAndOnlyTheLargestClustersAreKept) {
    Image a = flat(60, 10, {0, 0, 0});
    Image b = a;
    b.at(10, 5).r = 1;  // three pixels between it and the next
    b.at(14, 5).r = 1;
    b.at(40, 2).r = 1;  // alone, far away
    EXPECT_EQ(compare::failing_clusters(a, b, 0.5, 3, 20).size(), 2u) << "gap 3: 10 and 14 are one cluster";
    auto apart = compare::failing_clusters(a, b, 0.5, 2, 20);
    ASSERT_EQ(apart.size(), 3u) << "gap 2: three clusters";
    EXPECT_EQ(apart[0].left, 40) << "equal sizes: the top box first";
    auto capped = compare::failing_clusters(a, b, 0.5, 3, 1);
    ASSERT_EQ(capped.size(), 1u);
    EXPECT_EQ(capped[0].pixels, 2);
    EXPECT_EQ(capped[0].left, 10);
    EXPECT_EQ(capped[0].right, 14);
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

fs::path image_fuzz_input(const std::string& name) {
    return fs::path(TWINRAY_SOURCE_DIR) / "tests" / "data" / "fuzz_regressions" / "image_loader" / name;
}

// OpenEXR 3.1 allocates what a header claims before checking it; these two inputs of image_loader_fuzz
// took 1.9 GB and 2.8 s (an attribute's size), and 4.8 GB and 25 s (tiles of a 6 x 4 image).
TEST(CompareReadImage, AnExrHeaderClaimingMoreThanTheFileOrThePixelLimitIsRefusedBeforeOpenExrReadsIt) {
    std::string attribute = refusal_of(image_fuzz_input("oom-1f202565788a64b832ca8687341cb5b043d96d8e.exr"));
    EXPECT_NE(attribute.find("attribute '"), std::string::npos) << attribute;
    EXPECT_NE(attribute.find("more than the"), std::string::npos) << attribute;
    EXPECT_NE(attribute.find("left in the file"), std::string::npos) << attribute;
    std::string tiles = refusal_of(image_fuzz_input("timeout-b9bcfae68bc5ff045c9e60695eb570cb7f983661.exr"));
    EXPECT_NE(tiles.find("its header claims tiles of 4 x 67108864 pixels; allowed: 1 to " +
                         std::to_string(twinray::max_image_pixels) + " pixels"),
              std::string::npos)
        << tiles;
    std::string window = refusal_of(test_image("tiled_piz.exr"), 23);
    EXPECT_NE(window.find("its header claims a data window of 6 x 4 pixels; allowed: 1 to 23 pixels"),
              std::string::npos)
        << window;
    EXPECT_EQ(refusal_of(test_image("tiled_piz.exr"), 24), "") << "6 x 4 in tiles of 4 x 4 at the limit";
}

// An 860-byte tiled file of image_loader_fuzz whose header lacks the attributes OpenEXR requires (its data
// window, compression, tiles, ...): OpenEXR 3.1 and oiiotool went on with defaults for over 30 s.
TEST(CompareReadImage, AnExrHeaderLackingARequiredAttributeIsRefusedBeforeOpenExrReadsIt) {
    std::string refusal = refusal_of(image_fuzz_input("slow-unit-c5df5a6058f8d10dc2887d4372a528c964cce1e4.exr"));
    EXPECT_NE(refusal.find("its header lacks the attribute 'compression', which OpenEXR requires"), std::string::npos)
        << refusal;
    EXPECT_EQ(refusal_of(test_image("tiled_piz.exr")), "") << "a tiled file with every required attribute";
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
