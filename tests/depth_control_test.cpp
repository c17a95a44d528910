// Adaptive depth control (scene/depth_control.h): the proven cutoff keeps every pixel within its tolerance,
// reaches that tolerance where a scene sits at the bound's edge, drops the same rays in both tracers, and
// the ray budget ends every legal scene's tree.
#include "scene/depth_control.h"
#include "compare/image_compare.h"
#include "reference/tracer.h"
#include "scene/loader.h"
#include "scene_builder.h"
#include "scene_files.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace {

namespace fs = std::filesystem;
using namespace twinray;
using scene::DepthControl;

constexpr double tolerance = DepthControl::pixel_tolerance;

struct NamedRenderer {
    std::string name;
    std::function<RenderResult(const scene::Scene&, const RenderOptions&)> render;
};

std::vector<NamedRenderer> renderers() {
    std::vector<NamedRenderer> all = {
        {"reference", [](const scene::Scene& s, const RenderOptions& o) { return reference::render<double>(s, o); }}};
    if (sse::cpu_supports_sse41()) {
        all.push_back({"sse", [](const scene::Scene& s, const RenderOptions& o) { return sse::render(s, o); }});
    }
    return all;
}

// The largest per-channel difference, and the largest difference of the PNG levels (image_file.h's
// quantize_8bit), between two images of one size.
struct ImageDifference {
    double largest = 0;
    int largest_levels = 0;
};

ImageDifference difference(const Image& a, const Image& b) {
    double levels = 255 * compare::measure(compare::quantized_8bit(a), compare::quantized_8bit(b), {}).max_error;
    return {compare::measure(a, b, {}).max_error, static_cast<int>(std::lround(levels))};
}

scene::Scene without_cutoff(scene::Scene scene) {
    scene.min_weight = 0.0;
    return scene;
}

// A camera inside a closed box of glowing mirrors (ambient 1, reflection 0.8, no lights): every ray hits and
// returns exactly 1 + 0.8 + 0.8² + … to the depth limit, the radiance bound itself. The cutoff drops one ray
// per pixel, the first whose bound fits in the tolerance; the one before did not fit, and its bound was
// 1/0.8 of this one's (less 0.8⁶⁴·5, negligible), so what a pixel loses is between 0.8 and 1 tolerance.
scene::Scene hall_of_glowing_mirrors() {
    test::SceneBuilder builder;
    scene::Material mirror;
    mirror.ambient = 1;
    mirror.diffuse = 0;
    mirror.reflection = 0.8;
    int material = builder.material(mirror);
    builder.object(test::box({-2, -1.5, -3}, {2, 1.5, 3}, material));
    builder.scene().camera.eye = {0.3, 0.2, 2};
    builder.scene().camera.look_at = {-0.4, -0.1, -1};
    builder.scene().max_depth = 64;
    builder.scene().width = 48;
    builder.scene().height = 36;
    return builder.build();
}

scene::Scene nested_glass(int max_depth) {
    scene::Scene scene =
        scene::load_scene(fs::path(TWINRAY_SOURCE_DIR) / "tests" / "data" / "depth" / "nested_glass.json");
    scene.max_depth = max_depth;
    return scene;
}

TEST(DepthControl, RadianceBoundSumsTheLargestLocalValueOverTheLevelsLeft) {
    scene::Scene scene = hall_of_glowing_mirrors();
    scene.max_depth = 3;
    DepthControl control(scene);
    const double margin = 1.0 + 1.0 / 1024;
    EXPECT_NEAR(control.radiance_bound(3), 1.0 * margin, 1e-15);
    EXPECT_NEAR(control.radiance_bound(2), 1.8 * margin, 1e-15);
    EXPECT_NEAR(control.radiance_bound(1), 2.44 * margin, 1e-15);
}

TEST(DepthControl, TransmissionAboveOneLeavesNoRayProvablyNegligible) {
    test::SceneBuilder builder;
    scene::Material amplifier;
    amplifier.transmission = 1.5;
    builder.object(test::sphere({0, 0, 0}, 1, builder.material(amplifier))).light({0, 5, 5});
    for (int i = 0; i < 1000; ++i) {  // 1.5^(2·1001) overflows a double
        builder.object(test::sphere({3.0 + i, 0, 0}, 0.4, 1));
    }
    DepthControl control(builder.build());
    EXPECT_TRUE(std::isinf(control.radiance_bound(2))) << control.radiance_bound(2);
    scene::PixelLedger ledger;
    EXPECT_EQ(control.decide({1e-300, 10}, 2, ledger), scene::DropReason::traced);
    EXPECT_EQ(control.bailout_weight(), 0.0);
}

TEST(DepthControl, RaysAreSharedInProportionToTheCoefficientsAndLeftoversGoToTheReflection) {
    test::SceneBuilder builder;
    scene::Material glass;
    glass.reflection = 0.25;
    glass.transmission = 0.75;
    int material = builder.material(glass);
    builder.object(test::sphere({0, 0, 0}, 1, material));
    DepthControl control(builder.build());
    scene::RayShare parent{0.5, 101};
    scene::RayShare refracted = control.refracted(parent, material);
    EXPECT_EQ(refracted.allowance, 75);
    EXPECT_DOUBLE_EQ(refracted.weight, 0.375);
    scene::RayShare reflected = control.reflected(parent, material, false, 30);
    EXPECT_EQ(reflected.allowance, 70);
    EXPECT_DOUBLE_EQ(reflected.weight, 0.125);
    scene::RayShare total_internal = control.reflected(parent, material, true, 0);
    EXPECT_EQ(total_internal.allowance, 100);
    EXPECT_DOUBLE_EQ(total_internal.weight, 0.5);
}

TEST(DepthControl, MinWeightDropsExactlyTheRaysBelowIt) {
    scene::Scene scene = hall_of_glowing_mirrors();
    scene.min_weight = 0.2;  // weights 1, 0.8, 0.64, …, 0.8⁷ = 0.210, 0.8⁸ = 0.168
    reference::Tracer<double> tracer(scene);
    RayTree tree;
    TraceTally tally;
    tracer.trace(tracer.primary_ray(10, 10, scene.width, scene.height), 1, &tally, &tree);
    ASSERT_EQ(tree.dropped.size(), 1u);
    EXPECT_EQ(tree.nodes.size(), 8u);
    EXPECT_EQ(tree.dropped[0].depth, 9);
    EXPECT_NEAR(tree.dropped[0].weight, std::pow(0.8, 8), 1e-15);
    EXPECT_FALSE(tree.dropped[0].for_budget);
    EXPECT_EQ(tally.dropped_rays, 1u);
}

// Every scene of scenes/, both tracers: the proven cutoff against no cutoff at all.
TEST(DepthControl, ProvenCutoffMovesNoPixelOfAnySceneBeyondItsTolerance) {
    RenderOptions options;
    options.width = 160;
    options.threads = 2;
    for (const fs::path& path : test::scene_files()) {
        scene::Scene scene = scene::load_scene(path);
        for (const NamedRenderer& renderer : renderers()) {
            RenderResult cut = renderer.render(scene, options);
            RenderResult full = renderer.render(without_cutoff(scene), options);
            ImageDifference d = difference(cut.image, full.image);
            std::printf(
                "[ measured ] %s %s: %llu of %llu rays left out, largest change %.3g (%.2f of the tolerance), "
                "%d PNG level%s\n",
                path.stem().c_str(), renderer.name.c_str(), static_cast<unsigned long long>(cut.tally.dropped_rays),
                static_cast<unsigned long long>(full.tally.rays), d.largest, d.largest / tolerance, d.largest_levels,
                d.largest_levels == 1 ? "" : "s");
            EXPECT_LE(d.largest, tolerance) << path.stem() << " " << renderer.name;
            EXPECT_LE(d.largest_levels, 1) << path.stem() << " " << renderer.name;
            EXPECT_EQ(cut.tally.pixels_over_budget, 0u) << path.stem() << " " << renderer.name;
            EXPECT_EQ(full.tally.pixels_over_budget, 0u) << path.stem() << " " << renderer.name;
            EXPECT_EQ(full.tally.dropped_rays, 0u) << path.stem() << " " << renderer.name;
            EXPECT_LE(cut.tally.rays, full.tally.rays) << path.stem() << " " << renderer.name;
        }
    }
}

// Where every ray returns exactly its bound, the cutoff loses between 0.8 and 1 times the tolerance: the
// bound is neither loose nor broken.
TEST(DepthControl, CutoffLossReachesItsToleranceWhereRaysReturnTheirBound) {
    scene::Scene scene = hall_of_glowing_mirrors();
    RenderOptions options;
    options.threads = 2;
    for (const NamedRenderer& renderer : renderers()) {
        RenderResult cut = renderer.render(scene, options);
        RenderResult full = renderer.render(without_cutoff(scene), options);
        ImageDifference d = difference(cut.image, full.image);
        std::printf(
            "[ measured ] hall of glowing mirrors, %s: largest loss %.6g = %.4f of the tolerance; %llu rays "
            "instead of %llu\n",
            renderer.name.c_str(), d.largest, d.largest / tolerance, static_cast<unsigned long long>(cut.tally.rays),
            static_cast<unsigned long long>(full.tally.rays));
        EXPECT_LE(d.largest, tolerance) << renderer.name;
        EXPECT_GE(d.largest, 0.8 * tolerance) << renderer.name;
        EXPECT_EQ(cut.tally.dropped_rays, static_cast<std::uint64_t>(scene.width * scene.height)) << renderer.name;
    }
}

// Where the two tracers' trees agree ray for ray, they leave out the same rays with the same weights.
TEST(DepthControl, BothTracersLeaveOutTheSameRays) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    int compared = 0, with_drops = 0, differing_trees = 0;
    for (const scene::Scene& scene :
         {nested_glass(12), scene::load_scene(fs::path(TWINRAY_SOURCE_DIR) / "scenes" / "showcase.json")}) {
        reference::Tracer<double> reference(scene);
        sse::Tracer fast(scene);
        for (int y = 0; y < scene.height; y += 3) {
            for (int x = 0; x < scene.width; x += 3) {
                RayTree a, b;
                reference.trace(reference.primary_ray(x, y, scene.width, scene.height), 1, nullptr, &a);
                fast.trace(fast.primary_ray(x, y, scene.width, scene.height), 1, nullptr, &b);
                bool same_tree = a.nodes.size() == b.nodes.size();
                for (std::size_t i = 0; same_tree && i < a.nodes.size(); ++i) {
                    same_tree = a.nodes[i].kind == b.nodes[i].kind && a.nodes[i].parent == b.nodes[i].parent &&
                                a.nodes[i].leaf == b.nodes[i].leaf;
                }
                if (!same_tree) {
                    ++differing_trees;
                    continue;
                }
                ++compared;
                with_drops += a.dropped.empty() ? 0 : 1;
                ASSERT_EQ(a.dropped.size(), b.dropped.size()) << "pixel " << x << "," << y;
                for (std::size_t i = 0; i < a.dropped.size(); ++i) {
                    EXPECT_EQ(a.dropped[i].parent, b.dropped[i].parent);
                    EXPECT_EQ(a.dropped[i].kind, b.dropped[i].kind);
                    EXPECT_EQ(a.dropped[i].weight, b.dropped[i].weight);
                    EXPECT_EQ(a.dropped[i].bound, b.dropped[i].bound);
                    EXPECT_EQ(a.dropped[i].for_budget, b.dropped[i].for_budget);
                }
            }
        }
    }
    std::printf(
        "[ measured ] %d pixels with the same tree in both tracers (%d of them with rays left out); %d "
        "pixels whose trees differ\n",
        compared, with_drops, differing_trees);
    EXPECT_GT(with_drops, 200);
    EXPECT_LT(differing_trees, compared / 10);
}

// Reflection 0.9 and transmission 0.9: weights grow with depth, so no cutoff can end the tree; the budget does.
TEST(DepthControl, RayBudgetEndsATreeWhoseWeightsNeverShrink) {
    scene::Scene scene = nested_glass(64);
    for (scene::Material& material : scene.materials) {
        if (material.transmission > 0) {
            material.reflection = 0.9;
            material.transmission = 0.9;
        }
    }
    reference::Tracer<double> tracer(scene);
    std::uint64_t most = 0;
    int over_budget = 0;
    const std::uint64_t limit =
        static_cast<std::uint64_t>(DepthControl::ray_budget) * (1 + static_cast<std::uint64_t>(scene.lights.size()));
    for (int y = 0; y < scene.height; y += 4) {
        for (int x = 0; x < scene.width; x += 4) {
            TraceTally tally;
            tracer.trace(tracer.primary_ray(x, y, scene.width, scene.height), 1, &tally);
            most = std::max(most, tally.rays);
            over_budget += static_cast<int>(tally.pixels_over_budget);
        }
    }
    std::printf("[ measured ] at most %llu rays in one pixel (limit %llu); %d sampled pixels over budget\n",
                static_cast<unsigned long long>(most), static_cast<unsigned long long>(limit), over_budget);
    EXPECT_LE(most, limit);
    EXPECT_GT(over_budget, 0);
}

}  // namespace
