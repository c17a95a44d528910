// Parallel, near-parallel and bad rays through the per-ray API of every tracer (docs/numerics.md), and
// `twinray probe --ray` at the edges of what it accepts. A bad ray (a NaN or infinite component, a zero or
// unnormalised direction) is a miss and sees the background; no NaN may escape into a hit.
#include "reference/tracer.h"
#include "scene/loader.h"
#include "sse/cpu.h"
#include "sse/tracer.h"
#include "tests/run_twinray.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace {

namespace scene = twinray::scene;
namespace test = twinray::test;

struct Outcome {
    bool hit = false;
    double t = 0;
    std::array<double, 3> point{}, normal{}, color{};
};

bool all_finite(const std::array<double, 3>& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

// intersect() and trace() of one ray, in each tracer's own types (the ray's origin rounded to the tracer's
// scalar, then widened where the ray holds it in double, as the SSE tracer's does).
template <typename Tracer, typename Ray, typename Vec>
Outcome run(const Tracer& tracer, std::array<double, 6> ray) {
    using Scalar = decltype(Vec{}.x);
    auto s = [](double v) { return static_cast<Scalar>(v); };
    Ray r{decltype(Ray::origin)(Vec{s(ray[0]), s(ray[1]), s(ray[2])}), Vec{s(ray[3]), s(ray[4]), s(ray[5])}};
    Outcome outcome;
    auto hit = tracer.intersect(r);
    auto color = tracer.trace(r, 1);
    outcome.color = {static_cast<double>(color.x), static_cast<double>(color.y), static_cast<double>(color.z)};
    if (hit) {
        outcome.hit = true;
        outcome.t = static_cast<double>(hit->t);
        outcome.point = {static_cast<double>(hit->point.x), static_cast<double>(hit->point.y),
                         static_cast<double>(hit->point.z)};
        outcome.normal = {static_cast<double>(hit->normal.x), static_cast<double>(hit->normal.y),
                          static_cast<double>(hit->normal.z)};
    }
    return outcome;
}

// The same ray through reference<double>, reference<float> and (where the CPU has SSE4.1) sse.
std::vector<std::pair<std::string, Outcome>> run_all(const scene::Scene& scene, std::array<double, 6> ray) {
    std::vector<std::pair<std::string, Outcome>> outcomes;
    twinray::reference::Tracer<double> reference(scene);
    twinray::reference::Tracer<float> reference_float(scene);
    outcomes.emplace_back(
        "reference",
        run<decltype(reference), twinray::reference::Ray<double>, twinray::reference::Vec3<double>>(reference, ray));
    outcomes.emplace_back(
        "reference-float",
        run<decltype(reference_float), twinray::reference::Ray<float>, twinray::reference::Vec3<float>>(reference_float,
                                                                                                        ray));
    if (twinray::sse::cpu_supports_sse41()) {
        twinray::sse::Tracer sse(scene);
        outcomes.emplace_back("sse", run<twinray::sse::Tracer, twinray::sse::Ray, twinray::sse::Vec3>(sse, ray));
    }
    return outcomes;
}

std::string describe(std::array<double, 6> ray) {
    char text[200];
    std::snprintf(text, sizeof text, "ray (%g, %g, %g) -> (%g, %g, %g)", ray[0], ray[1], ray[2], ray[3], ray[4],
                  ray[5]);
    return text;
}

scene::Scene showcase() {
    return scene::load_scene(std::string(TWINRAY_SOURCE_DIR) + "/scenes/showcase.json");
}

TEST(ExtremesRays, BadRaysThroughThePerRayApiAreMissesThatSeeTheBackground) {
    scene::Scene scene = showcase();
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    constexpr double inf = std::numeric_limits<double>::infinity();
    // Each of these would hit the glass sphere (centre (0, 1.2, 0.8)) if it were a ray.
    const std::array<double, 6> bad[] = {
        {nan, 1.2, 10, 0, 0, -1},   {0, nan, 10, 0, 0, -1},
        {0, 1.2, nan, 0, 0, -1},    {0, 1.2, 10, nan, 0, -1},
        {0, 1.2, 10, 0, nan, -1},   {0, 1.2, 10, 0, 0, nan},
        {inf, 1.2, 10, 0, 0, -1},   {0, 1.2, -inf, 0, 0, -1},
        {0, 1.2, 10, 0, 0, -inf},   {0, 1.2, 10, inf, 0, -inf},
        {0, 1.2, 10, 0, 0, 0},      {0, 1.2, 10, 0, 0, -2},
        {0, 1.2, 10, 0, 0, -1e-40}, {0, 1.2, 10, 1e-45, 1e-45, -1e-45},
    };
    for (const auto& ray : bad) {
        for (const auto& [tracer, outcome] : run_all(scene, ray)) {
            EXPECT_FALSE(outcome.hit) << tracer << ": " << describe(ray) << " hit at t = " << outcome.t;
            std::array<double, 3> background = tracer == "reference" ? std::array<double, 3>{0.35, 0.45, 0.65}
                                                                     : std::array<double, 3>{0.35f, 0.45f, 0.65f};
            EXPECT_EQ(outcome.color, background) << tracer << ": " << describe(ray) << " did not see the background";
        }
    }
}

// Legal but extreme rays are traced: denormal direction components (their squares vanish, the direction
// is still unit) and origins at ±FLT_MAX, where every product overflows. The result must be defined:
// finite when hit, a finite colour either way.
TEST(ExtremesRays, DenormalComponentsAndOriginsAtTheLimitOfFloatGiveFiniteResults) {
    scene::Scene scene = showcase();
    const std::array<double, 6> extreme[] = {
        {0, 1.2, 10, 1e-40, 1e-39, -1},        {0, 1.2, 10, -1e-44, 0, -1},    {FLT_MAX, 1.2, 0.8, -1, 0, 0},
        {-FLT_MAX, 1.2, 0.8, 1, 0, 0},         {0, FLT_MAX, 0.8, 0, -1, 0},    {0, 1.2, -FLT_MAX, 0, 0, 1},
        {FLT_MAX, FLT_MAX, FLT_MAX, -1, 0, 0}, {0, 1.2, 10, 0.6, 1e-38, -0.8},
    };
    for (const auto& ray : extreme) {
        for (const auto& [tracer, outcome] : run_all(scene, ray)) {
            EXPECT_TRUE(all_finite(outcome.color)) << tracer << ": " << describe(ray);
            if (outcome.hit) {
                EXPECT_TRUE(std::isfinite(outcome.t) && all_finite(outcome.point) && all_finite(outcome.normal))
                    << tracer << ": " << describe(ray) << " hit with a non-finite t, point or normal";
            }
        }
    }
    // Denormal components change nothing: the ray hits the glass sphere's front at z = 2, 8 away.
    for (const auto& [tracer, outcome] : run_all(scene, {0, 1.2, 10, 1e-40, 1e-39, -1})) {
        ASSERT_TRUE(outcome.hit) << tracer;
        EXPECT_NEAR(outcome.t, 8.0, 1e-5) << tracer;
    }
}

struct ParallelCase {
    const char* what;
    std::array<double, 6> ray;
    std::optional<double> t;       // the exact first hit; nullopt: a miss
    std::array<double, 3> normal;  // its normal line; zero at a box corner, where any of its three faces' will do
};

// Rays parallel to a plane, to box faces, along a box's edges and through its corner, along a cylinder's
// axis and within its cap plane: the exact answers follow from the boundary rule (a ray running exactly
// within a face is not inside) and are met exactly or within a few ulps; no NaN anywhere.
TEST(ExtremesRays, ParallelRaysToPlanesBoxFacesAndCylinderAxesGiveTheExactAnswerWithoutNaN) {
    test::SceneBuilder builder;
    builder.object(test::plane({0, 1, 0}, -2));                  // y = -2
    builder.object(test::box({-1, -1, -1}, {1, 1, 1}));          // the unit box
    builder.object(test::cylinder({4, -1, 0}, {4, 1, 0}, 0.5));  // axis along y through x = 4
    scene::Scene scene = builder.build();
    const ParallelCase cases[] = {
        {"just above the plane, parallel", {-10, -1.999, 5, 1, 0, 0}, std::nullopt, {}},
        {"exactly within the plane", {-10, -2, 5, 1, 0, 0}, std::nullopt, {}},
        {"just below the plane, parallel (inside its half-space)", {-10, -2.001, 5, 1, 0, 0}, std::nullopt, {}},
        {"towards the plane at a slope of 2^-30",
         {0, -1.5, 5, 1, -std::ldexp(1.0, -30), 0},
         std::ldexp(1.0, 29),
         {0, 1, 0}},
        {"within the box's face plane y = 1", {-10, 1, 0, 1, 0, 0}, std::nullopt, {}},
        {"along the box's edge y = 1, z = 1", {-10, 1, 1, 1, 0, 0}, std::nullopt, {}},
        {"just inside the face plane y = 1", {-10, 0.999, 0, 1, 0, 0}, 9.0, {-1, 0, 0}},
        {"through the box's corner (1, 1, 1)",
         {3, 3, 3, -1 / std::sqrt(3.0), -1 / std::sqrt(3.0), -1 / std::sqrt(3.0)},
         2 * std::sqrt(3.0),
         {0, 0, 0}},
        {"along the cylinder's axis", {4, 10, 0, 0, -1, 0}, 9.0, {0, 1, 0}},
        {"along the cylinder's side line: past it, onto the plane", {4.5, 10, 0, 0, -1, 0}, 12.0, {0, 1, 0}},
        {"just inside the side line, along the axis", {4.499, 10, 0, 0, -1, 0}, 9.0, {0, 1, 0}},
        {"within the cylinder's cap plane y = 1", {10, 1, 0, -1, 0, 0}, std::nullopt, {}},
        {"just below the cap plane", {10, 0.999, 0, -1, 0, 0}, 5.5, {1, 0, 0}},
    };
    for (const ParallelCase& c : cases) {
        for (const auto& [tracer, outcome] : run_all(scene, c.ray)) {
            SCOPED_TRACE(tracer + ": " + c.what);
            EXPECT_TRUE(all_finite(outcome.color));
            ASSERT_EQ(outcome.hit, c.t.has_value()) << "t = " << outcome.t;
            if (!c.t) {
                continue;
            }
            double tolerance = (tracer == "reference" ? 1e-12 : 1e-6) * (1 + *c.t);
            EXPECT_NEAR(outcome.t, *c.t, tolerance);
            ASSERT_TRUE(all_finite(outcome.point) && all_finite(outcome.normal));
            const std::array<double, 3>& n = outcome.normal;
            double alignment = c.normal == std::array<double, 3>{0, 0, 0}
                                   ? std::max({std::fabs(n[0]), std::fabs(n[1]), std::fabs(n[2])})
                                   : std::fabs(n[0] * c.normal[0] + n[1] * c.normal[1] + n[2] * c.normal[2]);
            EXPECT_NEAR(alignment, 1.0, 1e-6) << "normal (" << n[0] << ", " << n[1] << ", " << n[2] << ")";
        }
    }
}

// `twinray probe --ray` prints what happened with the rays at the edge of what it accepts (the refusals
// of NaN, infinity, a zero direction and origins beyond float are ProbeTest.BadInput...).
TEST(ExtremesRays, ProbeTracesOriginsAtFltMaxAndDenormalDirectionsAndPrintsNoNaN) {
    const std::string showcase_path = std::string(TWINRAY_SOURCE_DIR) + "/scenes/showcase.json";
    for (const char* ray : {"3.4028234e38,1.2,0.8,-1,0,0", "-3.4028234e38,1.2,0.8,1,0,0", "0,1.2,10,1e-40,1e-39,-1",
                            "0,1.2,10,1e-310,0,-1e-310"}) {
        SCOPED_TRACE(ray);
        test::CommandResult result = test::run_twinray("probe " + showcase_path + " --ray " + ray);
        EXPECT_EQ(result.exit_status, 0) << result.output;
        EXPECT_EQ(result.output.find("nan"), std::string::npos) << result.output;
        EXPECT_NE(result.output.find("reference"), std::string::npos) << result.output;
    }
}

}  // namespace
