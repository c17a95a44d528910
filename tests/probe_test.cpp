// twinray probe: the ray trees both tracers record, the JSON a script reads, and the divergence finder.
#include "reference/tracer.h"
#include "render/ray_tree.h"
#include "scene/loader.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace twinray;
using Json = nlohmann::json;

struct CommandResult {
    int exit_status;
    std::string output;      // stdout only: the JSON, or the table
    std::string everything;  // stdout, then stderr
};

// Runs the binary once: stdout through the pipe, stderr into a file of this process's own (tests run
// in parallel, and two ctest runs may share a build tree).
CommandResult run_twinray(const std::string& arguments, const std::string& environment = "") {
    std::filesystem::path folder = std::filesystem::path(TWINRAY_TEST_OUTPUT_DIR) / "probe";
    std::filesystem::create_directories(folder);
    std::filesystem::path errors = folder / ("stderr-" + std::to_string(::getpid()) + ".txt");
    std::string command = environment + " " + std::string(TWINRAY_BINARY) + " " + arguments + " 2>" + errors.string();
    FILE* pipe = ::popen(command.c_str(), "r");
    if (pipe == nullptr) {
        return {-1, "", "popen failed"};
    }
    std::string output;
    std::array<char, 4096> buffer{};
    while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe) != nullptr) {
        output += buffer.data();
    }
    int status = ::pclose(pipe);
    std::ifstream file(errors);
    std::string error_text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    file.close();
    std::filesystem::remove(errors);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output, output + error_text};
}

std::string scene_path(const std::string& name) {
    return std::string(TWINRAY_SOURCE_DIR) + "/scenes/" + name;
}

Json probe_json(const std::string& arguments) {
    CommandResult result = run_twinray("probe " + arguments + " --json");
    EXPECT_EQ(result.exit_status, 0) << result.everything;
    return Json::parse(result.output, nullptr, /*allow_exceptions=*/false);
}

std::array<double, 3> triple(const Json& json) {
    return {json.at(0).get<double>(), json.at(1).get<double>(), json.at(2).get<double>()};
}

template <typename V>
std::array<double, 3> triple_of(const V& v) {
    return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}

// The JSON's first hit is exactly what the tracer's own intersect() says (the SSE's floats widen
// exactly to double, and JSON numbers round-trip).
template <typename HitT>
void expect_same_hit(const Json& json, const std::optional<HitT>& hit, const scene::Scene& scene) {
    ASSERT_EQ(json.at("hit").get<bool>(), hit.has_value()) << json.dump();
    if (!hit) {
        EXPECT_EQ(json.size(), 1u) << "a miss is {\"hit\": false}: " << json.dump();
        return;
    }
    EXPECT_EQ(json.at("object").get<std::string>(), scene.leaf_paths[static_cast<std::size_t>(hit->leaf)]);
    EXPECT_EQ(json.at("t").get<double>(), static_cast<double>(hit->t));
    EXPECT_EQ(triple(json.at("point")), triple_of(hit->point));
    EXPECT_EQ(triple(json.at("normal")), triple_of(hit->normal));
}

struct PixelCase {
    const char* scene;
    int x, y;
};

TEST(ProbeTest, FirstHitInTheJsonIsEachTracersIntersectOfThePixelsPrimaryRay) {
    const PixelCase cases[] = {
        {"showcase.json", 240, 140}, {"showcase.json", 270, 99},  {"showcase.json", 100, 200},
        {"showcase.json", 400, 60},  {"showcase.json", 360, 150}, {"csg.json", 100, 100},
        {"csg.json", 160, 120},      {"csg.json", 245, 110},      {"csg.json", 245, 125},
        {"csg.json", 305, 110},      {"csg.json", 320, 125},      {"csg.json", 200, 150},
    };
    for (const PixelCase& c : cases) {
        SCOPED_TRACE(std::string(c.scene) + " pixel " + std::to_string(c.x) + "," + std::to_string(c.y));
        scene::Scene scene = scene::load_scene(scene_path(c.scene));
        Json json = probe_json(scene_path(c.scene) + " --pixel " + std::to_string(c.x) + "," + std::to_string(c.y));
        ASSERT_TRUE(json.is_object());
        reference::Tracer<double> reference(scene);
        expect_same_hit(json.at("reference").at("hit"),
                        reference.intersect(reference.primary_ray(c.x, c.y, scene.width, scene.height)), scene);
        if (sse::cpu_supports_sse41()) {
            sse::Tracer fast(scene);
            expect_same_hit(json.at("sse").at("hit"),
                            fast.intersect(fast.primary_ray(c.x, c.y, scene.width, scene.height)), scene);
        }
    }
}

TEST(ProbeTest, APixelThroughTheGlassSphereHasARefractedChildInBothTrees) {
    Json json = probe_json(scene_path("showcase.json") + " --pixel 240,140");
    for (const char* tracer : {"reference", "sse"}) {
        SCOPED_TRACE(tracer);
        if (json.at(tracer).is_null()) {
            GTEST_SKIP() << "this CPU lacks SSE4.1";
        }
        const Json& tree = json.at(tracer).at("tree");
        ASSERT_GE(tree.size(), 2u);
        EXPECT_EQ(tree.at(0).at("object"), "objects[2]");
        EXPECT_EQ(tree.at(0).at("material"), "glass");
        bool refracted = false;
        for (const Json& child : tree.at(0).at("children")) {
            const Json& node = tree.at(child.get<std::size_t>());
            EXPECT_EQ(node.at("parent"), 0);
            EXPECT_EQ(node.at("depth"), 2);
            refracted = refracted || node.at("kind") == "refracted";
        }
        EXPECT_TRUE(refracted) << tree.at(0).dump(2);
    }
}

TEST(ProbeTest, ARayThatMeetsNothingGivesHitFalse) {
    Json json = probe_json(scene_path("showcase.json") + " --ray 0,3,9.5,0,1,0");
    EXPECT_EQ(json.at("reference").at("hit"), Json({{"hit", false}}));
    if (!json.at("sse").is_null()) {
        EXPECT_EQ(json.at("sse").at("hit"), Json({{"hit", false}}));
    }
    EXPECT_EQ(triple(json.at("reference").at("color")), (std::array<double, 3>{0.35, 0.45, 0.65}));
}

TEST(ProbeTest, AnUnnormalisedRayDirectionIsNormalisedSoTIsADistance) {
    // Towards the glass sphere (centre (0, 1.2, 0.8), radius 1.2) along -z: its front is at z = 2, 8 away.
    Json json = probe_json(scene_path("showcase.json") + " --ray 0,1.2,10,0,0,-5");
    EXPECT_EQ(triple(json.at("ray").at("direction")), (std::array<double, 3>{0, 0, -1}));
    for (const char* tracer : {"reference", "sse"}) {
        SCOPED_TRACE(tracer);
        if (json.at(tracer).is_null()) {
            continue;
        }
        const Json& hit = json.at(tracer).at("hit");
        ASSERT_TRUE(hit.at("hit").get<bool>());
        EXPECT_EQ(hit.at("object"), "objects[2]");
        EXPECT_NEAR(hit.at("t").get<double>(), 8.0, 1e-5);
        EXPECT_NEAR(hit.at("point").at(2).get<double>(), 2.0, 1e-5);
        EXPECT_NEAR(hit.at("normal").at(2).get<double>(), 1.0, 1e-6);
    }
}

// A unit square of two triangles in z = 0, split along its diagonal from (0, 0) to (1, 1); rays straight down.
// Below the diagonal the point (x, y) has weights (1 − x, x − y, y) in triangle 0, above it (1 − y, x, y − x)
// in triangle 1: exact in binary for quarters, in both tracers, whose hit points are exact here.
TEST(ProbeTest, AMeshHitNamesItsTriangleAndTheBarycentricsOfItsPoint) {
    std::filesystem::path folder = std::filesystem::path(TWINRAY_TEST_OUTPUT_DIR) / "probe";
    std::filesystem::create_directories(folder);
    std::filesystem::path file = folder / "square.json";
    std::ofstream(file) << R"({"format": "twinray-scene/1", "camera": {"eye": [0.5, 0.5, 4], "look_at": [0.5, 0.5, 0]},
        "lights": [{"position": [0, 0, 5]}],
        "objects": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
                     "triangles": [[0, 1, 2], [0, 2, 3]]}]})";
    struct Case {
        const char* ray;
        int triangle;
        std::array<double, 3> barycentrics;
    };
    const Case cases[] = {{"0.75,0.25,4,0,0,-1", 0, {0.25, 0.5, 0.25}},
                          {"0.25,0.75,4,0,0,-1", 1, {0.25, 0.25, 0.5}},
                          {"0.5,0.125,4,0,0,-1", 0, {0.5, 0.375, 0.125}}};
    for (const Case& c : cases) {
        Json json = probe_json(file.string() + " --ray " + c.ray);
        for (const char* tracer : {"reference", "sse"}) {
            SCOPED_TRACE(std::string(tracer) + " ray " + c.ray);
            if (json.at(tracer).is_null()) {
                continue;
            }
            for (const Json& hit : {json.at(tracer).at("hit"), json.at(tracer).at("tree").at(0)}) {
                ASSERT_TRUE(hit.at("hit").get<bool>()) << hit.dump();
                EXPECT_EQ(hit.at("object"), "objects[0]");
                EXPECT_EQ(hit.at("triangle"), c.triangle);
                EXPECT_EQ(triple(hit.at("barycentrics")), c.barycentrics) << hit.dump();
            }
        }
    }
}

TEST(ProbeTest, AHitOnAnythingButAMeshHasNoTriangle) {
    Json json = probe_json(scene_path("showcase.json") + " --ray 0,1.2,10,0,0,-1");
    const Json& hit = json.at("reference").at("hit");
    ASSERT_TRUE(hit.at("hit").get<bool>());
    EXPECT_FALSE(hit.contains("triangle")) << hit.dump();
    EXPECT_FALSE(hit.contains("barycentrics")) << hit.dump();
}

TEST(ProbeTest, BadInputIsAUsageErrorAndABadSceneAnInvalidScene) {
    const std::string showcase = scene_path("showcase.json");
    const std::pair<std::string, std::string> refused[] = {
        {showcase + " --pixel 480,0", "outside the 480 x 270 image"},
        {showcase + " --pixel 0,270", "outside"},
        {showcase + " --pixel=-1,5", "outside"},
        {showcase + " --pixel 150,10 --width 100", "outside the 100 x 56 image"},
        {showcase + " --pixel 12", "--pixel wants X,Y"},
        {showcase + " --pixel 1.5,2", "--pixel wants X,Y"},
        {showcase + " --ray 0,0,0,1,0", "six numbers"},
        {showcase + " --ray 0,0,0,1,0,x", "six numbers"},
        {showcase + " --ray 0,0,0,0,0,0", "must not be zero"},
        {showcase + " --ray 0,0,nan,0,0,1", "finite"},
        {showcase + " --ray 0,0,0,inf,0,1", "finite"},
        {showcase + " --ray 0,0,1e39,0,0,1", "single precision"},
        {showcase + " --ray 0,0,0,0,0,1 --width 100", "--width and --height"},
        {showcase + " --pixel 1,1 --ray 0,0,0,0,0,1", "exactly one of"},
        {showcase, "exactly one of"},
    };
    for (const auto& [arguments, message] : refused) {
        SCOPED_TRACE(arguments);
        CommandResult result = run_twinray("probe " + arguments);
        EXPECT_EQ(result.exit_status, 1) << result.everything;
        EXPECT_NE(result.everything.find(message), std::string::npos) << result.everything;
        EXPECT_EQ(result.output, "") << "nothing on stdout when refused";
    }
    CommandResult missing = run_twinray("probe " + scene_path("no-such-scene.json") + " --pixel 1,1");
    EXPECT_EQ(missing.exit_status, 2) << missing.everything;
    EXPECT_NE(missing.everything.find("invalid scene"), std::string::npos) << missing.everything;
}

TEST(ProbeTest, WithoutSse41TheReferenceTreeIsShownWithANote) {
    CommandResult text =
        run_twinray("probe " + scene_path("showcase.json") + " --pixel 240,140", "TWINRAY_SIMULATE_NO_SSE41=1");
    EXPECT_EQ(text.exit_status, 0) << text.everything;
    EXPECT_NE(text.output.find("SSE4.1"), std::string::npos) << text.output;
    EXPECT_NE(text.output.find("reference<double>"), std::string::npos) << text.output;
    CommandResult json =
        run_twinray("probe " + scene_path("showcase.json") + " --pixel 240,140 --json", "TWINRAY_SIMULATE_NO_SSE41=1");
    ASSERT_EQ(json.exit_status, 0) << json.everything;
    Json parsed = Json::parse(json.output);
    EXPECT_TRUE(parsed.at("sse").is_null());
    EXPECT_TRUE(parsed.at("divergence").is_null());
    EXPECT_NE(parsed.at("sse_unavailable").get<std::string>().find("SSE4.1"), std::string::npos);
    EXPECT_EQ(parsed.at("reference").at("hit").at("object"), "objects[2]");
}

TEST(ProbeTest, TheTextTableShowsBothTracersAndTheVerdict) {
    CommandResult result = run_twinray("probe " + scene_path("showcase.json") + " --pixel 240,140");
    ASSERT_EQ(result.exit_status, 0) << result.everything;
    for (const char* text : {"reference<double>", "sse", "depth 2: refracted ray", "lights[1]", "local colour",
                             "total colour", "objects[2] (glass), entering"}) {
        EXPECT_NE(result.output.find(text), std::string::npos) << text << " missing from:\n" << result.output;
    }
    if (sse::cpu_supports_sse41()) {
        EXPECT_TRUE(result.output.find("no divergence") != std::string::npos ||
                    result.output.find("first divergence") != std::string::npos)
            << result.output;
    }
}

// --tracer plugin:PATH sets the plug-in's tree beside the reference's. The C example intersects in double and the
// reference shades its hits, so the two trees agree to double's roundoff and no row diverges.
TEST(ProbeTest, APluginsTreeStandsBesideTheReferencesAndAgreesWithItInDouble) {
    const std::string plugin = std::string(" --tracer plugin:") + TWINRAY_EXAMPLE_TRACER;
    Json json = probe_json(scene_path("spheres.json") + " --pixel 160,120" + plugin);
    ASSERT_TRUE(json.is_object());
    EXPECT_NE(json.at("sse").at("tracer").get<std::string>().find("plugin brute force"), std::string::npos)
        << json.at("sse").at("tracer");
    const Json& expected = json.at("reference").at("hit");
    const Json& actual = json.at("sse").at("hit");
    ASSERT_TRUE(expected.at("hit").get<bool>());
    EXPECT_EQ(actual.at("object"), expected.at("object"));
    const double t = expected.at("t").get<double>();
    EXPECT_LE(std::fabs(actual.at("t").get<double>() - t), 1e-12 * t)
        << "reference t " << t << ", plug-in t " << actual.at("t").get<double>();
    EXPECT_TRUE(json.at("divergences").empty()) << json.at("divergences").dump(2);
    CommandResult text = run_twinray("probe " + scene_path("spheres.json") + " --pixel 160,120" + plugin);
    ASSERT_EQ(text.exit_status, 0) << text.everything;
    EXPECT_NE(text.output.find("(reference #0, plugin #0)"), std::string::npos) << text.output;
    EXPECT_NE(text.output.find("no divergence"), std::string::npos) << text.output;
}

// A kind the plug-in lacks is refused as render refuses it: status 8 and the kind named (README).
TEST(ProbeTest, APluginThatLacksAKindOfTheSceneIsRefusedWithStatusEight) {
    CommandResult result = run_twinray("probe " + scene_path("csg.json") +
                                       " --pixel 16,12 --tracer plugin:" + std::string(TWINRAY_EXAMPLE_TRACER));
    EXPECT_EQ(result.exit_status, 8) << result.everything;
    EXPECT_NE(result.everything.find("holds a plane"), std::string::npos) << result.everything;
}

// Recording must not change what is traced: with and without a tree, the same colour bit for bit, the
// same ray count, and the tree's first node holds that colour.
TEST(ProbeTest, RecordingATreeChangesNeitherTheColourNorTheRayCount) {
    for (const char* name : {"showcase.json", "csg.json", "complete2.json"}) {
        SCOPED_TRACE(name);
        scene::Scene scene = scene::load_scene(scene_path(name));
        reference::Tracer<double> reference(scene);
        std::optional<sse::Tracer> fast;
        if (sse::cpu_supports_sse41()) {
            fast.emplace(scene);
        }
        for (int y = 3; y < scene.height; y += 17) {
            for (int x = 5; x < scene.width; x += 23) {
                SCOPED_TRACE("pixel " + std::to_string(x) + "," + std::to_string(y));
                reference::Ray<double> ray = reference.primary_ray(x, y, scene.width, scene.height);
                TraceTally plain_rays, recorded_rays;
                RayTree tree;
                reference::Color<double> plain = reference.trace(ray, 1, &plain_rays);
                reference::Color<double> recorded = reference.trace(ray, 1, &recorded_rays, &tree);
                EXPECT_EQ(plain, recorded);
                EXPECT_EQ(plain_rays.rays, recorded_rays.rays);
                ASSERT_FALSE(tree.nodes.empty());
                EXPECT_EQ(triple_of(tree.nodes[0].total), triple_of(plain));
                if (fast) {
                    sse::Ray sse_ray = fast->primary_ray(x, y, scene.width, scene.height);
                    TraceTally sse_plain_rays, sse_recorded_rays;
                    RayTree sse_tree;
                    sse::Color sse_plain = fast->trace(sse_ray, 1, &sse_plain_rays);
                    sse::Color sse_recorded = fast->trace(sse_ray, 1, &sse_recorded_rays, &sse_tree);
                    EXPECT_EQ(triple_of(sse_plain), triple_of(sse_recorded));
                    EXPECT_EQ(sse_plain_rays.rays, sse_recorded_rays.rays);
                    ASSERT_FALSE(sse_tree.nodes.empty());
                    EXPECT_EQ(triple_of(sse_tree.nodes[0].total), triple_of(sse_plain));
                }
            }
        }
    }
}

// Every ray counted is in the tree, shadow rays as lights that do not face away.
TEST(ProbeTest, TheTreeHoldsEveryRayTheTracerCounts) {
    scene::Scene scene = scene::load_scene(scene_path("showcase.json"));
    reference::Tracer<double> reference(scene);
    TraceTally tally;
    RayTree tree;
    reference.trace(reference.primary_ray(240, 140, scene.width, scene.height), 1, &tally, &tree);
    std::uint64_t recorded = 0;
    for (const RayNode& node : tree.nodes) {
        ++recorded;
        for (const LightVisibility& light : node.lights) {
            recorded += light.faces_away ? 0 : 1;
        }
        EXPECT_EQ(node.lights.size(), node.hit ? scene.lights.size() : 0u);
    }
    EXPECT_EQ(recorded, tally.rays);
}

// ---------------------------------------------------------------------------------------------------
// The divergence finder on hand-made trees.

RayNode hand_made_node(RayKind kind, int depth, int parent, int leaf, double t) {
    RayNode node;
    node.kind = kind;
    node.depth = depth;
    node.parent = parent;
    node.origin = {0, 1, 5};
    node.direction = {0, 0, -1};
    node.hit = true;
    node.leaf = leaf;
    node.t = t;
    node.point = {0, 1, 5 - t};
    node.normal = {0, 0, 1};
    node.entering = true;
    LightVisibility visible{0.5, false, 1.0, {0, 1, 5 - t}, {0, 0.6, 0.8}};
    node.lights = {visible, visible};
    node.local = {0.2, 0.2, 0.2};
    node.total = {0.3, 0.3, 0.3};
    return node;
}

// primary (depth 1) → refracted (depth 2) → reflected (depth 3), and primary → reflected (depth 2).
RayTree hand_made_tree() {
    RayTree tree;
    tree.nodes.push_back(hand_made_node(RayKind::primary, 1, -1, 2, 4.0));
    tree.nodes.push_back(hand_made_node(RayKind::refracted, 2, 0, 2, 2.0));
    tree.nodes.push_back(hand_made_node(RayKind::reflected, 3, 1, 5, 3.0));
    tree.nodes.push_back(hand_made_node(RayKind::reflected, 2, 0, 7, 1.5));
    return tree;
}

TEST(ProbeTest, IdenticalTreesDoNotDiverge) {
    EXPECT_FALSE(first_divergence(hand_made_tree(), hand_made_tree()).has_value());
    EXPECT_TRUE(find_divergences(RayTree{}, RayTree{}).empty());
}

TEST(ProbeTest, TheFinderReportsALightBlockedAtDepthTwoInOneTreeOnly) {
    RayTree reference = hand_made_tree();
    RayTree other = hand_made_tree();
    other.nodes[3].lights[1].transmittance = 0;  // blocked in one tree: primary → reflected, depth 2
    other.nodes[3].total = {0.25, 0.25, 0.25};   // and its colour follows (found after, not first)
    other.nodes[0].total = {0.29, 0.29, 0.29};
    std::optional<Divergence> first = first_divergence(reference, other);
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->first, 3);
    EXPECT_EQ(first->second, 3);
    EXPECT_EQ(first->what, "lights[1]");
    EXPECT_EQ(reference.nodes[static_cast<std::size_t>(first->first)].depth, 2);
    EXPECT_DOUBLE_EQ(first->amount, 1.0);
    std::vector<Divergence> all = find_divergences(reference, other);
    ASSERT_EQ(all.size(), 3u);
    EXPECT_EQ(all[1].what, "total colour");
    EXPECT_EQ(all[1].first, 3);
    EXPECT_EQ(all[2].what, "total colour");
    EXPECT_EQ(all[2].first, 0);
}

TEST(ProbeTest, TheFinderReportsTheFirstDifferenceInTracingOrder) {
    RayTree reference = hand_made_tree();
    // A different object at depth 3 comes before a different t at depth 2 in the later sibling.
    RayTree other = hand_made_tree();
    other.nodes[2].leaf = 6;
    other.nodes[3].t = 1.7;
    std::vector<Divergence> all = find_divergences(reference, other);
    ASSERT_EQ(all.size(), 2u);
    EXPECT_EQ(all[0].what, "object");
    EXPECT_EQ(all[0].first, 2);
    EXPECT_EQ(all[1].what, "t");
    EXPECT_EQ(all[1].first, 3);
    // |Δt|·|cos θ| = 0.2 over S = |origin|∞ + t_parent + t = 5 + 4 + 1.5.
    EXPECT_DOUBLE_EQ(all[1].amount, 0.2 / 10.5);
    EXPECT_DOUBLE_EQ(all[1].threshold, DivergenceThresholds{}.position);
}

TEST(ProbeTest, TheFinderReportsARayTracedByOneTreeOnly) {
    RayTree reference = hand_made_tree();
    RayTree other = hand_made_tree();
    other.nodes.erase(other.nodes.begin() + 2);  // no reflected ray under the refracted one
    other.nodes[2].parent = 0;
    std::optional<Divergence> first = first_divergence(reference, other);
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->what, "ray");
    EXPECT_EQ(first->first, 2);
    EXPECT_EQ(first->second, -1);
}

TEST(ProbeTest, DifferencesWithinTheThresholdsAreNotDivergences) {
    RayTree reference = hand_made_tree();
    RayTree other = hand_made_tree();
    other.nodes[1].t += 1e-6;
    other.nodes[1].normal = {0, 1e-4, 1};  // about 1e-4 rad
    other.nodes[2].local[0] += 1e-3;
    other.nodes[3].lights[0].transmittance = 0.9999;
    EXPECT_FALSE(first_divergence(reference, other).has_value());
}

}  // namespace
