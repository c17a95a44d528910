// reference::render on a small scene with reflection, refraction, shadows through glass and CSG: the
// image and the ray count do not depend on the thread count, each pixel is the traced primary ray, and
// render<float> stays close to the render<double> oracle.
#include "reference/tracer.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <utility>

namespace {

using twinray::Image;
using twinray::RenderOptions;
using twinray::RenderResult;
using twinray::scene::CsgOp;
using twinray::scene::Material;
namespace reference = twinray::reference;
namespace test = twinray::test;

// A slightly reflective floor, a glass ball, a chrome ball, a cube with a spherical bite out of it,
// a lens (intersection) and a glass cylinder, under two lights.
twinray::scene::Scene busy_scene() {
    test::SceneBuilder builder;
    auto& scene = builder.scene();
    scene.width = 96;
    scene.height = 72;
    scene.camera = {{0, 2.5, 8}, {0, 0.8, 0}, {0, 1, 0}, 55};
    scene.background = {0.1, 0.15, 0.3};
    scene.ambient_light = {0.9, 0.9, 1};
    scene.max_depth = 6;

    Material floor;
    floor.color = {0.8, 0.75, 0.7};
    floor.diffuse = 0.7;
    floor.reflection = 0.2;
    Material glass;
    glass.color = {1, 1, 1};
    glass.ambient = 0;
    glass.diffuse = 0.05;
    glass.phong = 0.9;
    glass.phong_size = 80;
    glass.reflection = 0.1;
    glass.transmission = 0.85;
    glass.ior = 1.5;
    Material chrome;
    chrome.color = {0.9, 0.9, 0.95};
    chrome.diffuse = 0.1;
    chrome.phong = 0.6;
    chrome.reflection = 0.8;
    Material clay;
    clay.color = {0.8, 0.3, 0.2};
    clay.phong = 0.3;
    clay.phong_size = 20;
    Material jade;
    jade.color = {0.2, 0.8, 0.4};
    jade.transmission = 0.4;
    jade.ior = 1.3;

    int floor_id = builder.material(floor);
    int glass_id = builder.material(glass);
    int chrome_id = builder.material(chrome);
    int clay_id = builder.material(clay);
    int jade_id = builder.material(jade);

    builder.object(test::plane({0, 1, 0}, 0, floor_id));
    builder.object(test::sphere({0, 1, 0}, 1, glass_id));
    builder.object(test::sphere({2.2, 0.8, -1}, 0.8, chrome_id));
    builder.object(test::csg(CsgOp::difference,
                             {test::box({-3.2, 0, -1.5}, {-1.6, 1.6, 0.1}), test::sphere({-2.4, 1.6, 0.1}, 0.9)},
                             clay_id));
    builder.object(test::csg(CsgOp::intersection,
                             {test::sphere({1.2, 0.6, 1.8}, 0.7), test::sphere({1.8, 0.6, 1.8}, 0.7)}, jade_id));
    builder.object(test::cylinder({-1, 0, 2}, {-0.6, 1.4, 2.3}, 0.35, glass_id));
    builder.light({5, 8, 6}, {0.8, 0.8, 0.8});
    builder.light({-6, 5, 3}, {0.4, 0.45, 0.5});
    return builder.build();
}

RenderResult render_double(int threads) {
    RenderOptions options;
    options.threads = threads;
    return reference::render<double>(busy_scene(), options);
}

TEST(ReferenceRender, RenderIsBitIdenticalForOneTwoAndThreeThreads) {
    RenderResult one = render_double(1);
    ASSERT_EQ(one.image.width(), 96);
    ASSERT_EQ(one.image.height(), 72);
    for (int threads : {2, 3}) {
        SCOPED_TRACE(testing::Message() << threads << " threads");
        RenderResult other = render_double(threads);
        EXPECT_TRUE(other.image == one.image);
    }
}

TEST(ReferenceRender, RayCountIsTheSameForAnyThreadCount) {
    std::uint64_t one = render_double(1).tally.rays;
    // Primary rays alone are 96·72; the scene's shadows, mirrors and glass add many more.
    EXPECT_GT(one, 2u * 96u * 72u);
    EXPECT_EQ(render_double(2).tally.rays, one);
    EXPECT_EQ(render_double(3).tally.rays, one);
}

// The render is the tracer run per pixel: pixel (x, y) holds trace(primary_ray(x, y)) at depth 1,
// rounded to float; the rays it reports are those trace() counts.
TEST(ReferenceRender, EveryPixelIsTheTracedPrimaryRayOfThatPixel) {
    twinray::scene::Scene scene = busy_scene();
    RenderResult result = render_double(2);
    reference::Tracer<double> tracer(scene);
    twinray::TraceTally tally;
    int mismatches = 0;
    for (int y = 0; y < 72; ++y) {
        for (int x = 0; x < 96; ++x) {
            auto c = tracer.trace(tracer.primary_ray(x, y, 96, 72), 1, &tally);
            twinray::Rgb expected{static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
            if (!(result.image.at(x, y) == expected) && ++mismatches <= 5) {
                ADD_FAILURE() << "pixel (" << x << ", " << y << ") is " << result.image.at(x, y).r << ", "
                              << result.image.at(x, y).g << ", " << result.image.at(x, y).b << "; traced " << expected.r
                              << ", " << expected.g << ", " << expected.b;
            }
        }
    }
    EXPECT_EQ(mismatches, 0);
    EXPECT_EQ(result.tally.rays, tally.rays);
}

TEST(ReferenceRender, SizeInTheOptionsReplacesTheScenesKeepingItsAspectRatio) {
    RenderOptions options;
    options.threads = 2;
    options.width = 48;
    RenderResult half = reference::render<double>(busy_scene(), options);
    EXPECT_EQ(half.image.width(), 48);
    EXPECT_EQ(half.image.height(), 36);
}

// Single precision runs the same code; its error grows along a path (refraction, a phong_size 80
// highlight) and is largest on a few pixels where a float ray grazes a different surface. Stated bounds
// per pixel (largest channel difference), measured at 96 × 72: mean below 1e-5 (measured 5e-6); at most
// 1% of the pixels above 1e-4 (0.5%); at most 0.2% above 1e-3, a quarter of an 8-bit level (4 pixels,
// 0.06%); none above 0.05 (largest 0.012).
TEST(ReferenceRender, FloatRenderIsCloseToTheDoubleRender) {
    twinray::scene::Scene scene = busy_scene();
    RenderOptions options;
    options.threads = 2;
    Image d = reference::render<double>(scene, options).image;
    Image f = reference::render<float>(scene, options).image;
    ASSERT_EQ(f.width(), d.width());
    ASSERT_EQ(f.height(), d.height());
    double max_error = 0;
    double sum = 0;
    std::size_t above_1e4 = 0;
    std::size_t above_1e3 = 0;
    const std::size_t pixels = d.pixels().size();
    for (std::size_t i = 0; i < pixels; ++i) {
        const twinray::Rgb& a = d.pixels()[i];
        const twinray::Rgb& b = f.pixels()[i];
        double error = std::max({std::fabs(static_cast<double>(a.r) - static_cast<double>(b.r)),
                                 std::fabs(static_cast<double>(a.g) - static_cast<double>(b.g)),
                                 std::fabs(static_cast<double>(a.b) - static_cast<double>(b.b))});
        max_error = std::max(max_error, error);
        sum += error;
        above_1e4 += error > 1e-4;
        above_1e3 += error > 1e-3;
    }
    double mean = sum / static_cast<double>(pixels);
    double share_1e4 = static_cast<double>(above_1e4) / static_cast<double>(pixels);
    double share_1e3 = static_cast<double>(above_1e3) / static_cast<double>(pixels);
    std::printf("float vs double: max error %.3g, mean error %.3g, pixels > 1e-4: %.3f%%, > 1e-3: %.3f%%\n", max_error,
                mean, 100 * share_1e4, 100 * share_1e3);
    RecordProperty("max_error", std::to_string(max_error));
    RecordProperty("mean_error", std::to_string(mean));
    EXPECT_LT(mean, 1e-5);
    EXPECT_LE(share_1e4, 0.01);
    EXPECT_LE(share_1e3, 0.002);
    EXPECT_LT(max_error, 0.05);
}

}  // namespace
