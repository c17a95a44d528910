// Every hand-solved case (src/plugin/hand_solved.h) against every tracer (tests/hit_expectations.h), a test for each
// case and tracer, named after the case's property: EveryTracer/IntersectionPlane.HitFromTheOutside.../ReferenceFloat.
// Then what the cases' own data must hold, and the one check that goes beyond a hit.
#include "tests/hit_expectations.h"

#include "plugin/hand_solved.h"
#include "scene/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace twinray::test {
namespace {

class HandSolvedExpectation : public ::testing::Test {
public:
    HandSolvedExpectation(const plugin::HandSolvedCase& hand_solved, TracerUnderTest tracer)
        : case_(hand_solved), tracer_(std::move(tracer)) {}

protected:
    void SetUp() override {
        if (std::optional<std::string> why = why_skipped(tracer_, case_)) {
            GTEST_SKIP() << *why;
        }
    }

    // Each ray's first hit as solved: t, point and normal within the tracer's tolerance, the normal of unit length
    // and facing the ray, the leaf, triangle and side; or a miss.
    void TestBody() override {
        const double tolerance = tolerance_of(tracer_);
        for (const plugin::HandSolvedRay& ray : case_.rays) {
            SCOPED_TRACE(plugin::ray_name(ray));
            const plugin::RayCheck check =
                plugin::check_first_hit(ray, first_hit(tracer_, case_.scene, ray.origin, ray.direction), tolerance);
            EXPECT_TRUE(check.differences.empty()) << plugin::differences_text(check);
            if (check.worst_error) {
                worst_error_ = std::max(worst_error_.value_or(0), *check.worst_error);
            }
        }
    }

    // The largest error of the test's hits, against its tolerance, in the XML report (--gtest_output=xml).
    void TearDown() override {
        if (worst_error_) {
            std::ostringstream measured;
            measured << *worst_error_ << " of " << tolerance_of(tracer_);
            RecordProperty("worst_error", measured.str());
        }
    }

private:
    const plugin::HandSolvedCase& case_;
    TracerUnderTest tracer_;
    std::optional<double> worst_error_;  // none measured yet
};

// Registered before main runs, as TEST_P's are.
const bool every_case_registered = [] {
    for (const plugin::HandSolvedCase& hand_solved : plugin::hand_solved_cases()) {
        for (const TracerUnderTest& tracer : every_tracer()) {
            ::testing::RegisterTest(("EveryTracer/" + hand_solved.suite).c_str(),
                                    (hand_solved.name + "/" + tracer.name).c_str(), nullptr, nullptr, __FILE__,
                                    __LINE__, [&hand_solved, tracer]() -> HandSolvedExpectation* {
                                        return new HandSolvedExpectation(hand_solved, tracer);
                                    });
        }
    }
    return true;
}();

const plugin::HandSolvedCase* find_case(const std::string& suite, const std::string& name) {
    const std::vector<plugin::HandSolvedCase>& cases = plugin::hand_solved_cases();
    auto found = std::find_if(cases.begin(), cases.end(), [&](const plugin::HandSolvedCase& hand_solved) {
        return hand_solved.suite == suite && hand_solved.name == name;
    });
    return found == cases.end() ? nullptr : &*found;
}

// ---------------------------------------------------------------------------------------------------
// The cases' data.

// Test names, and `conform`'s case names, are the cases' own.
TEST(HandSolvedCases, EachIsNamedOnce) {
    std::set<std::string> names;
    for (const plugin::HandSolvedCase& hand_solved : plugin::hand_solved_cases()) {
        EXPECT_TRUE(names.insert(hand_solved.suite + "." + hand_solved.name).second) << hand_solved.name;
        EXPECT_FALSE(hand_solved.rays.empty()) << hand_solved.name;
    }
}

TEST(HandSolvedCases, EveryExpectedHitLiesWithinTheSizeScaleTheToleranceAssumes) {
    for (const plugin::HandSolvedCase& hand_solved : plugin::hand_solved_cases()) {
        for (const plugin::HandSolvedRay& ray : hand_solved.rays) {
            if (ray.expected) {
                EXPECT_LE(reference::max_abs_component(ray.origin) + ray.expected->t + 4,
                          plugin::hand_solved_size_scale)
                    << hand_solved.suite << "." << hand_solved.name << ", " << plugin::ray_name(ray);
            }
        }
    }
}

// The oblique ray into the dent meets material where it leaves the subtracted sphere only if that point lies inside
// the cube, below its top face z = 2.
TEST(HandSolvedCases, TheFarWallOfTheCavityLiesInsideTheCube) {
    const plugin::HandSolvedCase* cavity =
        find_case("CsgDifference", "ObliqueRayThroughTheCavityMouthHitsTheFarWallOfTheCavity");
    ASSERT_NE(cavity, nullptr);
    EXPECT_LT(cavity->rays.front().expected.value().point.z, 2.0);
}

// An unevenly scaled sphere is an ellipsoid for the tracers, not a sphere of its own kind.
TEST(HandSolvedCases, TheEllipsoidsArePlacedAsTransformedSpheres) {
    int ellipsoids = 0;
    for (const plugin::HandSolvedCase& hand_solved : plugin::hand_solved_cases()) {
        if (hand_solved.suite == "IntersectionTransformed" && hand_solved.name.find("Ellipsoid") != std::string::npos) {
            ++ellipsoids;
            EXPECT_TRUE(
                std::holds_alternative<scene::Transformed<scene::Sphere>>(hand_solved.scene.objects.at(1).shape))
                << hand_solved.name;
        }
    }
    EXPECT_EQ(ellipsoids, 4);
}

// ---------------------------------------------------------------------------------------------------
// Beyond the hit: the oblique sphere hit's cosine of incidence, 0.8 as worked out beside the case.

class IntersectionSphereIncidence : public ::testing::TestWithParam<TracerUnderTest> {};

TEST_P(IntersectionSphereIncidence, ObliqueHitMeetsTheSurfaceAtTheCosineWorkedOutByHand) {
    const plugin::HandSolvedCase* oblique =
        find_case("IntersectionSphere", "ObliqueHitIsAtTheChordEntryAtTheAngleWorkedOutByHand");
    ASSERT_NE(oblique, nullptr);
    if (std::optional<std::string> why = why_skipped(GetParam(), *oblique)) {
        GTEST_SKIP() << *why;
    }
    const plugin::HandSolvedRay& ray = oblique->rays.front();  // along a unit vector
    const std::optional<plugin::FirstHit> hit = first_hit(GetParam(), oblique->scene, ray.origin, ray.direction);
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(-reference::dot(hit->normal, ray.direction), 0.8, tolerance_of(GetParam())) << "cosine of incidence";
}

std::string tracer_test_name(const ::testing::TestParamInfo<TracerUnderTest>& tracer) {
    return tracer.param.name;
}

INSTANTIATE_TEST_SUITE_P(EveryTracer, IntersectionSphereIncidence, ::testing::ValuesIn(every_tracer()),
                         tracer_test_name);

}  // namespace
}  // namespace twinray::test
