// The stages of `twinray probe` on their own, without the binary: the command line turned into the pixel
// or ray to trace (probe_arguments), and the JSON written from two hand-made trees (probe_json). The
// binary's output as a whole is probe_test.cpp's.
#include "cli/probe_arguments.h"
#include "cli/probe_json.h"
#include "cli/probe_tracing.h"
#include "scene/scene.h"

#include <gtest/gtest.h>

#include <string>

namespace {

using namespace twinray;
using namespace twinray::cli;

probe::Arguments ray_arguments(const std::string& ray) {
    probe::Arguments arguments;
    arguments.ray = ray;
    return arguments;
}

probe::Arguments pixel_arguments(const std::string& pixel, int width = 0, int height = 0) {
    probe::Arguments arguments;
    arguments.pixel = pixel;
    arguments.width = width;
    arguments.height = height;
    return arguments;
}

// The message of the UsageError `parse` throws, or "" when it throws none.
template <typename Parse>
std::string usage_error_of(Parse parse) {
    try {
        parse();
    } catch (const probe::UsageError& error) {
        return error.what();
    }
    return "";
}

TEST(ProbeArguments, ARayDirectionIsNormalisedWithoutOverflowOrUnderflowAtAnyMagnitude) {
    for (const char* ray : {"1,2,3,3,0,4", "1,2,3,3e300,0,4e300", "1,2,3,3e-300,0,4e-300", "+1,2,3,+3,0,4"}) {
        SCOPED_TRACE(ray);
        probe::Target target = probe::parse_target(ray_arguments(ray));
        EXPECT_FALSE(target.is_pixel);
        EXPECT_EQ(target.origin, (Vec3d{1, 2, 3}));
        EXPECT_DOUBLE_EQ(target.direction[0], 0.6);
        EXPECT_EQ(target.direction[1], 0.0);
        EXPECT_DOUBLE_EQ(target.direction[2], 0.8);
    }
}

TEST(ProbeArguments, APixelIsTwoIntegersPlacedInTheImageRenderWouldMake) {
    scene::Scene scene;  // 320 x 240
    probe::Arguments arguments = pixel_arguments("10,+20", 160);
    probe::Target target = probe::parse_target(arguments);
    probe::place_pixel(scene, arguments, target);
    EXPECT_TRUE(target.is_pixel);
    EXPECT_EQ(target.x, 10);
    EXPECT_EQ(target.y, 20);
    EXPECT_EQ(target.width, 160);
    EXPECT_EQ(target.height, 120) << "the scene's aspect ratio, as render keeps it";
}

TEST(ProbeArguments, EveryRefusalIsAUsageErrorSayingWhatIsWrong) {
    const std::pair<probe::Arguments, std::string> refused[] = {
        {probe::Arguments{}, "exactly one of"},
        {probe::Arguments{"scene.json", "1,1", "0,0,0,0,0,1"}, "exactly one of"},
        {pixel_arguments("1"), "--pixel wants X,Y"},
        {pixel_arguments("1,2,3"), "--pixel wants X,Y"},
        {pixel_arguments("1, 2"), "--pixel wants X,Y"},
        {ray_arguments("0,0,0,1,0"), "six numbers"},
        {ray_arguments("0,0,0,1,0,inf"), "finite"},
        {ray_arguments("0,0,0,1,0,x"), "six numbers"},
        {ray_arguments("0,0,-4e38,1,0,0"), "single precision"},
        {ray_arguments("0,0,0,0,-0,0"), "must not be zero"},
    };
    for (const auto& [refused_arguments, message] : refused) {
        const probe::Arguments& arguments = refused_arguments;  // clang 14 lets no lambda capture a structured binding
        SCOPED_TRACE(arguments.pixel + " / " + arguments.ray);
        std::string error = usage_error_of([&] { probe::parse_target(arguments); });
        EXPECT_NE(error.find(message), std::string::npos) << error;
    }
    probe::Arguments with_size = ray_arguments("0,0,0,0,0,1");
    with_size.height = 10;
    EXPECT_NE(usage_error_of([&] { probe::parse_target(with_size); }).find("--width and --height"), std::string::npos);
}

TEST(ProbeArguments, APixelOutsideItsImageIsRefusedWithTheImagesBounds) {
    scene::Scene scene;
    probe::Arguments arguments = pixel_arguments("320,5");
    probe::Target target = probe::parse_target(arguments);
    EXPECT_EQ(usage_error_of([&] { probe::place_pixel(scene, arguments, target); }),
              "pixel 320,5 is outside the 320 x 240 image (x from 0 to 319, y from 0 to 239)");
}

// A hit primary ray with one refracted child that misses, as a tracer records it.
RayTree two_ray_tree() {
    RayTree tree;
    int primary = tree.add(RayKind::primary, 1, -1, {0, 0, 5}, {0, 0, -1});
    RayNode& hit = tree.nodes[static_cast<std::size_t>(primary)];
    hit.hit = true;
    hit.leaf = 0;
    hit.t = 4;
    hit.point = {0, 0, 1};
    hit.normal = {0, 0, 1};
    hit.entering = true;
    hit.lights = {LightVisibility{-0.5, true, 0, {}, {}}};
    hit.total = {0.25, 0.5, 1};
    tree.add(RayKind::refracted, 2, primary, {0, 0, 1}, {0, 0, -1});
    return tree;
}

scene::Scene one_sphere_scene() {
    scene::Scene scene;
    scene.leaf_paths.push_back("objects[0]");
    scene.leaf_materials = {0};
    return scene;
}

TEST(ProbeJson, NodesCarryHitFieldsOnlyWhenTheyHitAndNameTheirChildren) {
    probe::Findings findings{{"reference<double>", two_ray_tree()}, std::nullopt, "sse not run: no SSE4.1", {}, {}, {}};
    probe::Target target = probe::parse_target(ray_arguments("0,0,5,0,0,-1"));
    probe::Json json = probe::report_json(one_sphere_scene(), "one.json", target, findings);
    const probe::Json& tree = json.at("reference").at("tree");
    ASSERT_EQ(tree.size(), 2u);
    EXPECT_EQ(tree[0].at("object"), "objects[0]");
    EXPECT_EQ(tree[0].at("material"), "(default)");
    EXPECT_EQ(tree[0].at("lights")[0].dump(), R"({"light":"lights[0]","n_dot_l":-0.5,"faces_away":true})")
        << "a light facing away has no shadow ray";
    EXPECT_EQ(tree[0].at("children").dump(), "[1]");
    EXPECT_FALSE(tree[1].at("hit").get<bool>());
    EXPECT_FALSE(tree[1].contains("t")) << "a miss has no hit fields";
    EXPECT_EQ(json.at("reference").at("hit").at("t"), 4.0);
    EXPECT_EQ(json.at("reference").at("color").dump(), "[0.25,0.5,1.0]") << "the first node's total";
}

TEST(ProbeJson, WithoutTheSseTreeItIsNullWithTheReasonAndNothingDiverges) {
    probe::Findings findings{{"reference<double>", two_ray_tree()}, std::nullopt, "sse not run: no SSE4.1", {}, {}, {}};
    probe::Target target = probe::parse_target(ray_arguments("0,0,5,0,0,-1"));
    probe::Json json = probe::report_json(one_sphere_scene(), "one.json", target, findings);
    EXPECT_TRUE(json.at("sse").is_null());
    EXPECT_EQ(json.at("sse_unavailable"), "sse not run: no SSE4.1");
    EXPECT_TRUE(json.at("divergence").is_null());
    EXPECT_TRUE(json.at("divergences").empty());
    EXPECT_EQ(json.at("ray").dump(), R"({"origin":[0.0,0.0,5.0],"direction":[0.0,0.0,-1.0]})");
}

TEST(ProbeJson, ADivergenceNamesBothNodesBothValuesAndItsAmountAgainstTheThreshold) {
    RayTree sse_tree = two_ray_tree();
    sse_tree.nodes[0].t = 4.5;
    probe::Findings findings{
        {"reference<double>", two_ray_tree()}, probe::TracedTree{"sse", sse_tree, "sse", 0x1p-24}, "", {}, {}, {}};
    findings.divergences = find_divergences(findings.reference.tree, sse_tree, findings.limits);
    ASSERT_FALSE(findings.divergences.empty());
    probe::Target target = probe::parse_target(ray_arguments("0,0,5,0,0,-1"));
    probe::Json json = probe::report_json(one_sphere_scene(), "one.json", target, findings);
    const probe::Json& first = json.at("divergence");
    EXPECT_EQ(first.at("what"), "t");
    EXPECT_EQ(first.at("reference_node"), 0);
    EXPECT_EQ(first.at("sse_node"), 0);
    EXPECT_EQ(first.at("reference"), 4.0);
    EXPECT_EQ(first.at("sse"), 4.5);
    EXPECT_GT(first.at("amount").get<double>(), first.at("threshold").get<double>());
    EXPECT_EQ(json.at("divergences")[0], first);
}

}  // namespace
