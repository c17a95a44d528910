// twinray's SSE tracer through the tracer ABI (src/peers/sse_tracer.cpp) against the same tracer called directly
// (plugin/direct_sse.h): the ABI carries everything the judges need if every ray gets the same hit both ways, and
// every conformance case the same verdict and figures.
#include "accuracy/watertight.h"
#include "numerics/numerics.h"
#include "plugin/conformance.h"
#include "plugin/direct_sse.h"
#include "plugin/hand_solved.h"
#include "plugin/plugin.h"
#include "reference/tracer.h"
#include "scene/loader.h"
#include "sse/cpu.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

namespace {

using namespace twinray;

class SseThroughAbi : public ::testing::Test {
protected:
    void SetUp() override {
        if (!sse::cpu_supports_sse41()) {
            GTEST_SKIP() << sse::missing_sse41_message();
        }
    }
    const plugin::Plugin& through_abi() {
        static const plugin::Plugin loaded(TWINRAY_SSE_TRACER);
        return loaded;
    }
};

// Every scene the ABI carries: the built-in conformance pair and one of every kind (transformed primitives,
// a mesh, instances, one of them mirrored), each also moved 1e5 and 1e7 away.
std::vector<plugin::NamedScene> scenes_carried() {
    std::vector<plugin::NamedScene> scenes = plugin::built_in_conformance_scenes();
    scenes.push_back({"every kind", scene::load_scene(TWINRAY_SOURCE_DIR "/tests/data/abi/every_kind.json")});
    const std::size_t near = scenes.size();
    for (std::size_t i = 0; i < near; ++i) {
        for (double shift : {1e5, 1e7}) {
            std::ostringstream name;
            name << scenes[i].name << " moved " << shift << " away";
            scenes.push_back({name.str(), numerics::transformed(scenes[i].scene, 1, shift)});
        }
    }
    return scenes;
}

std::string differences(const plugin::Hit& direct, const plugin::Hit& abi) {
    std::string text;
    auto check = [&](bool same, const std::string& what) { text += same ? "" : " " + what; };
    check(direct.hit == abi.hit, "hit");
    if (direct.hit && abi.hit) {
        check(direct.leaf == abi.leaf, "leaf " + std::to_string(direct.leaf) + " vs " + std::to_string(abi.leaf));
        check(direct.triangle == abi.triangle, "triangle");
        check(direct.instance == abi.instance, "instance");
        check(direct.t == abi.t, "t " + std::to_string(direct.t) + " vs " + std::to_string(abi.t));
        check(direct.normal == abi.normal, "normal");
        check(direct.entering == abi.entering, "entering");
    }
    return text;
}

TEST_F(SseThroughAbi, EveryPrimaryRayAndEveryCrossingAlongItIsTheDirectTracersBitForBit) {
    const plugin::DirectSse direct;
    for (const plugin::NamedScene& named : scenes_carried()) {
        ASSERT_TRUE(through_abi().missing_kinds(named.scene).empty()) << named.name;
        const reference::Tracer<double> oracle(named.scene);
        const std::unique_ptr<plugin::JudgedScene> direct_scene = direct.build(named.scene);
        const std::unique_ptr<plugin::JudgedScene> abi_scene = through_abi().build(named.scene);
        const std::vector<twinray_ray> rays = plugin::primary_rays(oracle, 48, 36);
        std::vector<plugin::Hit> direct_hits(rays.size()), abi_hits(rays.size());
        direct_scene->intersect(rays, direct_hits);
        abi_scene->intersect(rays, abi_hits);
        int hits = 0, crossings = 0, differing = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const std::string nearest = differences(direct_hits[i], abi_hits[i]);
            differing += nearest.empty() ? 0 : 1;
            EXPECT_EQ(nearest, "") << named.name << ", ray " << i;
            hits += direct_hits[i].hit ? 1 : 0;
            const scene::Vec3 origin = plugin::origin_of(rays[i]), direction = plugin::direction_of(rays[i]);
            const std::vector<plugin::Hit> direct_along =
                direct_scene->hits_along(origin, direction, 0, std::numeric_limits<double>::infinity());
            const std::vector<plugin::Hit> abi_along =
                abi_scene->hits_along(origin, direction, 0, std::numeric_limits<double>::infinity());
            ASSERT_EQ(direct_along.size(), abi_along.size()) << named.name << ", ray " << i;
            for (std::size_t k = 0; k < direct_along.size(); ++k) {
                EXPECT_EQ(differences(direct_along[k], abi_along[k]), "")
                    << named.name << ", ray " << i << ", crossing " << k;
            }
            crossings += static_cast<int>(direct_along.size());
        }
        EXPECT_GT(hits, 0) << named.name;
        std::cout << named.name << ": " << rays.size() << " rays, " << hits << " hits, " << crossings << " crossings, "
                  << differing << " differing\n";
    }
}

// The watertightness rays count crossings through hits_along: the same count for every ray both ways.
TEST_F(SseThroughAbi, EveryWatertightnessRayCrossesAsManyTrianglesThroughTheAbiAsDirectly) {
    const plugin::DirectSse direct;
    for (const std::string& family : accuracy::watertight_families()) {
        for (double distance : accuracy::watertight_distances()) {
            for (double size : accuracy::watertight_sizes()) {
                const accuracy::WatertightCase watertight = accuracy::make_watertight_case(family, distance, size, 40);
                const std::unique_ptr<plugin::JudgedScene> direct_scene = direct.build(watertight.scene);
                const std::unique_ptr<plugin::JudgedScene> abi_scene = through_abi().build(watertight.scene);
                accuracy::count_watertightness(watertight, [&](const accuracy::WatertightProbe& probe) {
                    const auto direct_hits = direct_scene->hits_along(probe.origin, probe.direction, 0, probe.length);
                    const auto abi_hits = abi_scene->hits_along(probe.origin, probe.direction, 0, probe.length);
                    EXPECT_EQ(direct_hits.size(), abi_hits.size()) << family << " at " << distance << ", size " << size;
                    return static_cast<int>(direct_hits.size());
                });
            }
        }
    }
}

TEST_F(SseThroughAbi, EveryConformanceCaseGetsTheSameVerdictAndFiguresThroughTheAbiAsDirectly) {
    const plugin::DirectSse direct;
    std::vector<plugin::NamedScene> scenes = plugin::built_in_conformance_scenes();
    scenes.push_back({"every kind", scene::load_scene(TWINRAY_SOURCE_DIR "/tests/data/abi/every_kind.json")});
    int cases = 0, csg_cases = 0;
    for (const plugin::ConformCase& conform_case : plugin::conformance_cases(scenes, 40, 30, 60)) {
        const plugin::CaseResult direct_result = conform_case.run(direct);
        const plugin::CaseResult abi_result = conform_case.run(through_abi());
        ++cases;
        EXPECT_NE(direct_result.verdict, plugin::Verdict::skipped) << conform_case.name << ": " << direct_result.detail;
        // The ABI carries no CSG: only a hand-solved case on a CSG scene is judged directly alone.
        if (abi_result.verdict == plugin::Verdict::skipped) {
            EXPECT_EQ(conform_case.suite, "hand-solved") << conform_case.name;
            EXPECT_EQ(abi_result.detail, "the scene holds what the tracer does not intersect: csg")
                << conform_case.name;
            ++csg_cases;
            continue;
        }
        EXPECT_EQ(plugin::verdict_name(direct_result.verdict), plugin::verdict_name(abi_result.verdict))
            << conform_case.suite << ", " << conform_case.name;
        EXPECT_EQ(direct_result.detail, abi_result.detail) << conform_case.suite << ", " << conform_case.name;
    }
    const std::vector<plugin::HandSolvedCase>& hand_solved = plugin::hand_solved_cases();
    // Three scenes, each judged as it is, at three distances and at four extremes; 16 watertight cases.
    EXPECT_EQ(cases, static_cast<int>(hand_solved.size()) + 3 * (1 + 3 + 4) + 16);
    EXPECT_EQ(csg_cases, std::count_if(hand_solved.begin(), hand_solved.end(), [](const plugin::HandSolvedCase& each) {
                  return std::any_of(
                      each.scene.objects.begin(), each.scene.objects.end(),
                      [](const scene::Object& object) { return std::holds_alternative<scene::Csg>(object.shape); });
              }));
}

}  // namespace
