// The tracer ABI (include/twinray/tracer.h) from twinray's side: the scene reaches a plug-in whole, a kind it
// lacks is refused by name, its hits come back as the oracle's, and every way of breaking the contract is
// reported with the ray that shows it (tests/plugins/faulty_tracer.c).
#include "plugin/plugin.h"
#include "plugin/conformance.h"
#include "plugin/hand_solved.h"
#include "plugin/plugin_intersector.h"
#include "reference/tracer.h"
#include "scene/loader.h"
#include "scene/placement.h"
#include "sse/cpu.h"
#include "tests/run_twinray.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace twinray {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// A file in this test's own output folder, created on first use (ctest runs each test in a fresh process, in any
// order).
std::string output_file(const std::string& name) {
    const std::filesystem::path folder = std::filesystem::path(TWINRAY_TEST_OUTPUT_DIR) / "plugin";
    std::filesystem::create_directories(folder);
    return (folder / name).string();
}

const plugin::Plugin& example() {
    static const plugin::Plugin loaded(TWINRAY_EXAMPLE_TRACER);
    return loaded;
}

scene::Scene two_spheres_and_a_square() {
    test::SceneBuilder builder;
    builder.object(test::sphere({0, 0, 0}, 1));
    builder.object(test::sphere({4, 0, 0}, 1));
    builder.add(test::mesh({{10, -1, -1}, {10, 1, -1}, {10, 1, 1}, {10, -1, 1}}, {{{0, 1, 2}}, {{0, 2, 3}}}));
    return builder.build();
}

TEST(PluginAbi, TheExampleIntroducesItselfAsItsTableSays) {
    EXPECT_EQ(example().name(), "brute force (C example)");
    EXPECT_EQ(example().version(), "1.0");
    EXPECT_EQ(example().unit_roundoff(), std::ldexp(1.0, -53));
    EXPECT_TRUE(example().thread_safe());
}

// Along the x axis from x = -5: both spheres entered and left, then the square at x = 10, whose triangles run
// counter-clockwise seen from +x: the ray meets their backs and leaves.
TEST(PluginAbi, HitsAlongASegmentComeInOrderWithEachSurfacesEntryAndExit) {
    const scene::Scene scene = two_spheres_and_a_square();
    plugin::BuiltScene built(example(), scene);
    const std::vector<plugin::Hit> hits = built.hits_along({-5, 0, 0.25}, {1, 0, 0}, 0, infinity);
    ASSERT_EQ(hits.size(), 5u);
    const double chord = std::sqrt(1 - 0.25 * 0.25);
    const std::vector<double> t{5 - chord, 5 + chord, 9 - chord, 9 + chord, 15};
    const std::vector<int> leaf{0, 0, 1, 1, 2};
    const std::vector<bool> entering{true, false, true, false, false};
    for (std::size_t i = 0; i < hits.size(); ++i) {
        SCOPED_TRACE("hit " + std::to_string(i));
        EXPECT_NEAR(hits[i].t, t[i], 1e-14);
        EXPECT_EQ(hits[i].leaf, leaf[i]);
        EXPECT_EQ(hits[i].entering, entering[i]);
        EXPECT_EQ(hits[i].instance, -1);
    }
    EXPECT_EQ(hits[4].triangle, 1) << "(10, 0, 0.25) lies above the diagonal from (-1, -1) to (1, 1)";
    EXPECT_NEAR(hits[4].normal.x, 1, 1e-15);
    // The segment's end cuts the list: the second sphere's exit at 9 + chord is left out.
    EXPECT_EQ(built.hits_along({-5, 0, 0.25}, {1, 0, 0}, 0, 9).size(), 3u);
    EXPECT_EQ(built.nearest({-5, 0, 0.25}, {1, 0, 0}, 6, infinity).leaf, 1);
}

// The barycentrics the ABI returns locate the hit on its triangle: (1 - u - v) a + u b + v c.
TEST(PluginAbi, ATrianglesBarycentricsLocateItsHit) {
    const scene::Scene scene = two_spheres_and_a_square();
    plugin::BuiltScene built(example(), scene);
    const plugin::Hit hit = built.nearest({20, 0.5, -0.25}, {-1, 0, 0}, 0, infinity);
    ASSERT_TRUE(hit.hit);
    ASSERT_EQ(hit.triangle, 0);
    // Triangle 0: a = (10, -1, -1), b = (10, 1, -1), c = (10, 1, 1): y = -1 + 2u + 2v, z = -1 + 2v.
    EXPECT_NEAR(hit.v, 0.375, 1e-15);
    EXPECT_NEAR(hit.u, 0.75 - 0.375, 1e-15);
    EXPECT_TRUE(hit.entering);
}

TEST(PluginAbi, ASceneWithAKindTheTracerLacksIsRefusedNamingTheKind) {
    auto refused_kind = [](scene::Object object) {
        test::SceneBuilder builder;
        builder.object(test::sphere({0, 0, 0}, 1));
        builder.object(std::move(object));
        const scene::Scene scene = builder.build();
        try {
            plugin::BuiltScene built(example(), scene);
        } catch (const plugin::UnsupportedKind& refusal) {
            EXPECT_NE(std::string(refusal.what()).find("brute force (C example)"), std::string::npos) << refusal.what();
            return refusal.kind();
        }
        return std::string("(accepted)");
    };
    EXPECT_EQ(refused_kind(test::plane({0, 1, 0}, -1)), "plane");
    EXPECT_EQ(refused_kind(test::cylinder({0, 0, 0}, {0, 1, 0}, 1)), "cylinder");
    EXPECT_EQ(refused_kind(test::box({0, 0, 0}, {1, 1, 1})), "box");
    EXPECT_EQ(refused_kind(test::placed(test::sphere({0, 0, 0}, 1), scene::scaling({1, 2, 3}))),
              "transformed primitive");
    EXPECT_EQ(refused_kind(test::csg(scene::CsgOp::union_, {test::sphere({0, 0, 0}, 1), test::sphere({1, 0, 0}, 1)})),
              "csg");
    const std::vector<std::string> missing =
        plugin::missing_kinds(scene::load_scene(TWINRAY_SOURCE_DIR "/scenes/instances.json"), example().table().kinds);
    EXPECT_NE(std::find(missing.begin(), missing.end(), "instances"), missing.end());
}

// Every pixel's primary ray of scenes/spheres.json: the same object hit or missed as by reference<double>, at a t
// within 64 unit roundoffs of |o|∞ + t (both in double, each with its own rounding of the quadratic).
TEST(PluginAbi, TheExampleAgreesWithTheOracleOnEveryPrimaryRayOfTheSpheresScene) {
    const scene::Scene scene = scene::load_scene(TWINRAY_SOURCE_DIR "/scenes/spheres.json");
    const reference::Tracer<double> oracle(scene);
    plugin::BuiltScene built(example(), scene);
    const int width = 80, height = 60;
    const std::vector<twinray_ray> rays = plugin::primary_rays(oracle, width, height);
    std::vector<std::optional<reference::Hit<double>>> expected;
    for (const twinray_ray& ray : rays) {
        expected.push_back(oracle.intersect({plugin::origin_of(ray), plugin::direction_of(ray)}));
    }
    std::vector<plugin::Hit> hits(rays.size());
    built.intersect(rays, hits);
    double worst = 0;
    int hit_count = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        SCOPED_TRACE("pixel " + std::to_string(i));
        ASSERT_EQ(hits[i].hit, expected[i].has_value());
        if (!hits[i].hit) {
            continue;
        }
        ++hit_count;
        ASSERT_EQ(hits[i].leaf, expected[i]->leaf);
        const double scale = math::max_abs_component(plugin::origin_of(rays[i])) + expected[i]->t;
        worst = std::max(worst, std::fabs(hits[i].t - expected[i]->t) / (scale * example().unit_roundoff()));
    }
    EXPECT_GT(hit_count, width * height / 10);
    EXPECT_LE(worst, 64) << "worst t error, in unit roundoffs of |o| + t";
    RecordProperty("worst_t_error_in_unit_roundoffs", std::to_string(worst));
}

// The reference's shading over the example's hits: the oracle's image, to the bit on spheres (the same formula in
// the same precision) and within one 8-bit level on a mesh lit through a sphere's shadow, where Moller-Trumbore's t
// and the exact test's differ in their last bits.
double worst_pixel_difference(const scene::Scene& scene) {
    RenderOptions options;
    options.width = 96;
    options.height = 72;
    options.threads = 2;
    plugin::BuiltScene built(example(), scene);
    plugin::PluginIntersector intersector(built);
    const RenderResult oracle = reference::render<double>(scene, options);
    const RenderResult judged = reference::render<double>(scene, options, &intersector);
    EXPECT_EQ(judged.tally.rays, oracle.tally.rays) << "the same rays traced, shadow rays included";
    double worst = 0;
    for (int y = 0; y < options.height; ++y) {
        for (int x = 0; x < options.width; ++x) {
            const auto& a = oracle.image.at(x, y);
            const auto& b = judged.image.at(x, y);
            worst = std::max(
                {worst, std::fabs(double(a.r) - b.r), std::fabs(double(a.g) - b.g), std::fabs(double(a.b) - b.b)});
        }
    }
    return worst;
}

TEST(PluginRender, TheExamplesImageOfTheSpheresSceneIsTheOraclesBitForBit) {
    EXPECT_EQ(worst_pixel_difference(scene::load_scene(TWINRAY_SOURCE_DIR "/scenes/spheres.json")), 0);
}

TEST(PluginRender, TheExamplesImageOfAMeshUnderASphereIsTheOraclesWithinOneLevel) {
    test::SceneBuilder builder;
    builder.scene().camera = {{0, 4, 6}, {0, 0, 0}, {0, 1, 0}, 50};
    builder.light({3, 8, 2}).light({-4, 5, 5}, {0.5, 0.5, 0.6});
    scene::Material glass;
    glass.color = {0.9, 0.95, 1};
    glass.transmission = 0.6;
    glass.reflection = 0.2;
    glass.ior = 1.5;
    builder.object(test::sphere({0, 1.2, 0}, 1, builder.material(glass)));
    builder.add(test::mesh({{-4, 0, -4}, {4, 0, -4}, {4, 0, 4}, {-4, 0, 4}, {0, 0.5, 0}},
                           {{{0, 4, 1}}, {{1, 4, 2}}, {{2, 4, 3}}, {{3, 4, 0}}}));
    builder.scene().max_depth = 4;
    const double worst = worst_pixel_difference(builder.build());
    EXPECT_LE(worst, 1.0 / 255) << "worst channel difference";
    RecordProperty("worst_channel_difference", std::to_string(worst));
}

// `twinray render --tracer plugin:PATH`: the statuses of the README's table for a plug-in that does not load and
// for a scene holding a kind it lacks.
TEST(PluginRender, TheRenderCommandRefusesAnUnloadablePluginAndAMissingKindWithTheirOwnStatuses) {
    const std::string output = output_file("render.png");
    test::CommandResult missing = test::run_twinray("render " TWINRAY_SOURCE_DIR
                                                    "/scenes/spheres.json --tracer "
                                                    "plugin:/nonexistent/tracer.so -o " +
                                                    output);
    EXPECT_EQ(missing.exit_status, 7) << missing.output;
    EXPECT_NE(missing.output.find("cannot load the plug-in /nonexistent/tracer.so"), std::string::npos)
        << missing.output;
    test::CommandResult lacking = test::run_twinray(
        "render " TWINRAY_SOURCE_DIR "/scenes/planes.json --tracer plugin:" + std::string(TWINRAY_EXAMPLE_TRACER) +
        " -o " + output);
    EXPECT_EQ(lacking.exit_status, 8) << lacking.output;
    EXPECT_NE(lacking.output.find("the scene holds a plane, which the tracer \"brute force (C example)\" does not "
                                  "intersect"),
              std::string::npos)
        << lacking.output;
    test::CommandResult rendered = test::run_twinray("render " TWINRAY_SOURCE_DIR
                                                     "/scenes/spheres.json --tracer "
                                                     "plugin:" +
                                                     std::string(TWINRAY_EXAMPLE_TRACER) + " --width 40 -o " + output);
    EXPECT_EQ(rendered.exit_status, 0) << rendered.output;
}

// `twinray conform`: a verdict per case, the report and its JUnit XML whole, and the example's known weakness found:
// Moller-Trumbore with inclusive edges counts a ray through a shared edge twice.
TEST(Conform, TheExampleGetsAVerdictPerCaseWithItsFiguresAndAJUnitReport) {
    const std::string junit = output_file("conform_example.xml");
    std::remove(junit.c_str());
    test::CommandResult run =
        test::run_twinray("conform " + std::string(TWINRAY_EXAMPLE_TRACER) + " --watertight-rays 60 --junit " + junit);
    EXPECT_EQ(run.exit_status, 10) << run.output;
    EXPECT_NE(run.output.find("tracer:  brute force (C example) 1.0 (sphere, triangles; unit roundoff 1.11e-16"),
              std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("pass    300 spheres: 3072 rays"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("pass    tessellated sphere moved 1e+07 away"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("fail    grid at 1: 300 rays at shared edges, vertices and faces, sizes 1e-4 to 1e4: 0 "
                              "misses (0 per million), 300 double hits"),
              std::string::npos)
        << run.output;
    std::ifstream file(junit);
    const std::string xml((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    EXPECT_NE(xml.find("<testsuite name=\"primary rays\" tests=\"2\" failures=\"0\" skipped=\"0\">"), std::string::npos)
        << xml;
    EXPECT_NE(xml.find("<testsuite name=\"watertight\" tests=\"16\""), std::string::npos) << xml;
    EXPECT_NE(xml.find("<testcase classname=\"conform.watertight\" name=\"grid at 1\""), std::string::npos) << xml;
}

// The library's hand-solved cases as a tracer intersecting `kinds` meets them in `conform --suite hand-solved`: those
// the ABI's contract decides, those that hold a tie rule of twinray's own (plugin::HandSolvedCase::own_rule), and
// those skipped for a kind the tracer lacks.
struct HandSolvedShare {
    int held_to_the_contract = 0, of_twinrays_own_rule = 0, skipped = 0;
};

HandSolvedShare hand_solved_share(std::uint32_t kinds) {
    HandSolvedShare share;
    for (const plugin::HandSolvedCase& hand_solved : plugin::hand_solved_cases()) {
        if (!plugin::missing_kinds(hand_solved.scene, kinds).empty()) {
            ++share.skipped;
        } else if (!hand_solved.own_rule.empty()) {
            ++share.of_twinrays_own_rule;
        } else {
            ++share.held_to_the_contract;
        }
    }
    return share;
}

// Möller–Trumbore with inclusive edges takes a mesh's outer corner that twinray's tie rule leaves out: that case
// warns, every other one the example intersects (spheres and meshes) passes.
TEST(Conform, TheExamplePassesEveryHandSolvedCaseItIntersectsAndIsSkippedOnTheKindsItLacks) {
    const std::string junit = output_file("conform_example_hand_solved.xml");
    std::remove(junit.c_str());
    const test::CommandResult run =
        test::run_twinray("conform " + std::string(TWINRAY_EXAMPLE_TRACER) + " --suite hand-solved --junit " + junit);
    EXPECT_EQ(run.exit_status, 0) << run.output;
    const HandSolvedShare share = hand_solved_share(example().table().kinds);
    EXPECT_EQ(share.of_twinrays_own_rule, 1);
    EXPECT_GT(share.held_to_the_contract, 10);
    EXPECT_NE(run.output.find(std::to_string(share.held_to_the_contract) + " pass, " +
                              std::to_string(share.of_twinrays_own_rule) + " warn, 0 fail, " +
                              std::to_string(share.skipped) + " skipped"),
              std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("warn    IntersectionMesh.RaysThroughCornersHitOnlyWhereThePerturbedOriginLiesInside: "
                              "ray from (0, 2, 5) along (0, 0, -1): a hit at t = 5, leaf 1, expected a miss"),
              std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("pass    IntersectionSphere.HeadOnHitIsAtTheNearSurfaceWithTheRadialNormal: 1 ray as "
                              "solved by hand, worst error "),
              std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("skipped IntersectionPlane.HitFromTheOutsideEntersWithTheOutwardNormal: the scene holds "
                              "what the tracer does not intersect: plane"),
              std::string::npos)
        << run.output;
    std::ifstream file(junit);
    const std::string xml((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    EXPECT_NE(xml.find("<testsuite name=\"hand-solved\" tests=\"" + std::to_string(plugin::hand_solved_cases().size()) +
                       "\" failures=\"0\" skipped=\"" + std::to_string(share.skipped) + "\">"),
              std::string::npos)
        << xml;
}

TEST(Conform, TheSseTracerCalledDirectlyPassesEveryHandSolvedCase) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    const test::CommandResult run = test::run_twinray("conform sse --suite hand-solved");
    EXPECT_EQ(run.exit_status, 0) << run.output;
    EXPECT_NE(run.output.find(std::to_string(plugin::hand_solved_cases().size()) + " pass, 0 warn, 0 fail, 0 skipped"),
              std::string::npos)
        << run.output;
}

// The extremes suite judges each built-in scene scaled by 1e-4 and 1e6 and seen from 100 and 10 000 times as far:
// the double-precision example agrees with the oracle in all eight, and the faulty tracer's control, a sphere-only
// tracer that answers object 0 at t = 1 for every ray, fails the four of the sphere field (the mesh's are skipped).
TEST(Conform, TheExtremesSuiteJudgesEachSceneAtEachScaleAndDistance) {
    const test::CommandResult example =
        test::run_twinray("conform " + std::string(TWINRAY_EXAMPLE_TRACER) + " --suite extremes");
    EXPECT_EQ(example.exit_status, 0) << example.output;
    EXPECT_NE(example.output.find("8 pass, 0 warn, 0 fail, 0 skipped"), std::string::npos) << example.output;
    for (const char* extreme :
         {"scaled by 1e-4", "scaled by 1e6", "seen from 100 times as far", "seen from 10 000 times as far"}) {
        EXPECT_NE(example.output.find(std::string("pass    300 spheres ") + extreme + ": "), std::string::npos)
            << extreme << "\n"
            << example.output;
    }
    const test::CommandResult wrong = test::run_twinray("conform " + std::string(TWINRAY_FAULTY_TRACER_DIR) +
                                                        "/libfaulty_tracer_none.so --suite extremes");
    EXPECT_EQ(wrong.exit_status, 10) << wrong.output;
    EXPECT_NE(wrong.output.find("0 pass, 0 warn, 4 fail, 4 skipped"), std::string::npos) << wrong.output;
}

// A tracer that keeps the ABI's contract but answers every ray with object 0 at t = 1 (the faulty tracer's control)
// fails every case it can intersect, naming the ray and the figures that differ; one that breaks the contract fails
// with the ray that shows it.
TEST(Conform, AWrongPluginFailsTheHandSolvedSuiteNamingTheRayAndWhatDiffered) {
    const std::string faulty = std::string(TWINRAY_FAULTY_TRACER_DIR) + "/libfaulty_tracer_";
    const test::CommandResult wrong = test::run_twinray("conform " + faulty + "none.so --suite hand-solved");
    EXPECT_EQ(wrong.exit_status, 10) << wrong.output;
    const HandSolvedShare share = hand_solved_share(plugin::Plugin(faulty + "none.so").table().kinds);
    EXPECT_EQ(share.of_twinrays_own_rule, 0) << "a sphere-only tracer meets no tie rule of a mesh's";
    EXPECT_NE(wrong.output.find("0 pass, 0 warn, " + std::to_string(share.held_to_the_contract) + " fail, " +
                                std::to_string(share.skipped) + " skipped"),
              std::string::npos)
        << wrong.output;
    EXPECT_NE(wrong.output.find("fail    IntersectionSphere.HeadOnHitIsAtTheNearSurfaceWithTheRadialNormal: ray from "
                                "(1, -2, 10.5) along (0, 0, -1): t 1 expected 8.5, error 7.5 > 3.05e-05; point (1, -2, "
                                "9.5) expected (1, -2, 2), error 7.5 > 3.05e-05; leaf 0, expected 1\n"),
              std::string::npos)
        << wrong.output;
    const test::CommandResult broken = test::run_twinray("conform " + faulty + "unknown_object.so --suite hand-solved");
    EXPECT_EQ(broken.exit_status, 10) << broken.output;
    EXPECT_NE(
        broken.output.find("fail    IntersectionSphere.HeadOnHitIsAtTheNearSurfaceWithTheRadialNormal: the tracer "
                           "\"faulty\" returned object 1000 of 2 for the ray from (1, -2, 10.5) along (0, 0, -1)"),
        std::string::npos)
        << broken.output;
}

// Embree through the ABI, as its documentation describes it: the default mode lets rays through shared edges of a
// closed mesh near the origin, the robust mode none (both count a ray through an edge on both of its triangles).
TEST(Conform, EmbreesRobustModeLetsNoRayThroughASharedEdgeNearTheOriginAndItsDefaultModeDoes) {
#ifndef TWINRAY_EMBREE_TRACER_ROBUST
    GTEST_SKIP() << "Embree 3 is not installed (libembree-dev)";
#else
    auto sphere_at_1 = [](const std::string& library) {
        test::CommandResult run = test::run_twinray("conform " + library + " --suite watertight --watertight-rays 400");
        EXPECT_EQ(run.exit_status, 10) << run.output;
        const std::size_t line = run.output.find("sphere at 1: ");
        EXPECT_NE(line, std::string::npos) << run.output;
        return run.output.substr(line, run.output.find('\n', line) - line);
    };
    const std::string robust = sphere_at_1(TWINRAY_EMBREE_TRACER_ROBUST);
    EXPECT_NE(robust.find(": 0 misses (0 per million)"), std::string::npos) << robust;
    const std::string by_default = sphere_at_1(TWINRAY_EMBREE_TRACER_DEFAULT);
    EXPECT_EQ(by_default.find(": 0 misses"), std::string::npos) << by_default;
#endif
}

// A tracer that crashes, hangs or ends the process costs its case a verdict, never twinray its report.
TEST(Conform, ACrashingHangingOrExitingPluginGetsAVerdictAndTheReportIsWhole) {
    const std::vector<std::pair<std::string, std::string>> faults{
        {"crashes", "the tracer crashed (Segmentation fault, signal 11)"},
        {"hangs", "the tracer gave no answer within 0.5 s (killed: it hangs, or is that slow)"},
        {"exits", "the tracer ended the process (exit status 3) before answering"}};
    for (const auto& [fault, verdict] : faults) {
        SCOPED_TRACE(fault);
        test::CommandResult run =
            test::run_twinray("conform " + std::string(TWINRAY_FAULTY_TRACER_DIR) + "/libfaulty_tracer_" + fault +
                              ".so --suite primary --time-limit 0.5");
        EXPECT_EQ(run.exit_status, 10) << run.output;
        EXPECT_NE(run.output.find("fail    300 spheres: " + verdict), std::string::npos) << run.output;
        EXPECT_NE(run.output.find("0 pass, 0 warn, 1 fail, 1 skipped"), std::string::npos) << run.output;
    }
    test::CommandResult unloadable =
        test::run_twinray("conform " + std::string(TWINRAY_FAULTY_TRACER_DIR) + "/libfaulty_tracer_other_version.so");
    EXPECT_EQ(unloadable.exit_status, 7) << unloadable.output;
    EXPECT_NE(unloadable.output.find("speaks the tracer ABI version 2"), std::string::npos) << unloadable.output;
}

// One way to break the contract per library (tests/plugins/faulty_tracer.c), and what twinray says of it.
struct Fault {
    std::string name;     // the library: libfaulty_tracer_NAME.so
    std::string stage;    // where it shows: "load", "build", "nearest", "hits_along", or "none"
    std::string message;  // a part of the verdict
};

void PrintTo(const Fault& fault, std::ostream* out) {
    *out << fault.name;
}

class BadPlugin : public ::testing::TestWithParam<Fault> {};

TEST_P(BadPlugin, IsReportedWithWhatItBrokeAndTheRayThatShowsIt) {
    const Fault& fault = GetParam();
    const std::string path = std::string(TWINRAY_FAULTY_TRACER_DIR) + "/libfaulty_tracer_" + fault.name + ".so";
    test::SceneBuilder builder;
    builder.object(test::sphere({0, 0, 0}, 1));
    const scene::Scene scene = builder.build();
    std::string stage = "none", message;
    try {
        stage = "load";
        plugin::Plugin loaded(path);
        stage = "build";
        plugin::BuiltScene built(loaded, scene);
        stage = "nearest";
        built.nearest({0, 0, 5}, {0, 0, -1}, 0, 10);
        stage = "hits_along";
        built.hits_along({0, 0, 5}, {0, 0, -1}, 0, 10);
        stage = "none";
    } catch (const plugin::PluginUnusable& unusable) {
        message = unusable.what();
        EXPECT_TRUE(stage == "load" || stage == "build") << stage << ": " << message;
    } catch (const plugin::PluginFault& wrong) {
        message = wrong.what();
        EXPECT_NE(message.find("for the ray from (0, 0, 5) along (0, 0, -1), t in (0, 10)"), std::string::npos)
            << message;
    }
    EXPECT_EQ(stage, fault.stage) << message;
    EXPECT_NE(message.find(fault.message), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    EveryFault, BadPlugin,
    ::testing::Values(Fault{"none", "none", ""}, Fault{"no_entry", "load", "exports no twinray_tracer_entry"},
                      Fault{"other_version", "load", "speaks the tracer ABI version 2; this twinray speaks version 1"},
                      Fault{"build_fails", "build", "could not build the scene: no room for the scene"},
                      Fault{"nan_t", "nearest", "returned t = nan, outside the ray's range"},
                      Fault{"negative_t", "nearest", "returned t = -1, outside the ray's range"},
                      Fault{"t_beyond_range", "nearest", "returned t = 1.0000000000000001e+300, outside"},
                      Fault{"wrong_count", "nearest", "wrote 0 hits for a batch of 1 rays"},
                      Fault{"unknown_object", "nearest", "returned object 1000 of 1"},
                      Fault{"hits_out_of_order", "hits_along", "out of order (t = 2"},
                      Fault{"call_fails", "nearest", "failed (status 3: the device was lost)"}),
    [](const ::testing::TestParamInfo<Fault>& fault) { return fault.param.name; });

}  // namespace
}  // namespace twinray
