// Meshes at the extremes: slivers of aspect ratio 1e6, rays grazing a grid down to 1e-6 rad, and rays
// lying in a triangle's plane, for the oracle and the exact SSE tracer. A ray that must cross the surface
// once is counted by how many triangles each tracer reports along it (as the watertightness suite does).
#include "reference/tracer.h"
#include "scene/portable_random.h"
#include "sse/cpu.h"
#include "sse/tracer.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace {

namespace scene = twinray::scene;
namespace test = twinray::test;
using V = scene::Vec3;

// Crossings along (origin, unit direction) within `length`: the oracle's, then the exact SSE tracer's.
struct Crossings {
    int oracle, sse;
};

class MeshExtremes : public ::testing::Test {
protected:
    void SetUp() override {
        if (!twinray::sse::cpu_supports_sse41()) {
            GTEST_SKIP() << twinray::sse::missing_sse41_message();
        }
    }

    static scene::Scene scene_of(const scene::Mesh& mesh, V eye) {
        test::SceneBuilder builder;
        builder.add(mesh);
        builder.scene().camera.eye = eye;
        builder.scene().camera.look_at = eye + V{0, 0, -1};
        return builder.build();
    }
};

Crossings crossings(const twinray::reference::Tracer<double>& oracle, const twinray::sse::Tracer& tracer, V origin,
                    V direction, double length) {
    V unit = twinray::math::normalize(direction);
    return {oracle.mesh_crossings({origin, unit}, length),
            tracer.mesh_crossings({origin, twinray::sse::Vec3(unit)}, static_cast<float>(length))};
}

// A fan of 16 slivers around the origin, each 1 long and 1e-6 wide at its rim (aspect ratio 1e6): rays from
// above at the shared spokes' points and at the centre cross it once.
TEST_F(MeshExtremes, SliversOfAspectRatioAMillionStayWatertight) {
    std::vector<V> vertices{{0, 0, 0}};
    std::vector<std::array<std::uint32_t, 3>> triangles;
    constexpr int slivers = 16;
    const double width = 1e-6;
    for (int i = 0; i <= slivers; ++i) {
        double angle = width * i;
        vertices.push_back({std::cos(angle), std::sin(angle), 0});
    }
    for (std::uint32_t i = 0; i < slivers; ++i) {
        triangles.push_back({0, 1 + i, 2 + i});
    }
    scene::Scene scene = scene_of(test::mesh(vertices, triangles), {0.5, 0, 1});
    twinray::reference::Tracer<double> oracle(scene);
    twinray::sse::Tracer tracer(scene);
    twinray::SplitMix64 random(7);
    int oracle_failures = 0, sse_failures = 0, rays = 0;
    for (int k = 0; k < 4000; ++k) {
        // A point on an inner spoke (1..slivers-1), from above at a random tilt.
        int spoke = 1 + static_cast<int>(random.next() % (slivers - 1));
        V target = random.uniform(0.01, 0.99) * vertices[static_cast<std::size_t>(1 + spoke)];
        V origin = target + V{random.uniform(-0.5, 0.5), random.uniform(-0.5, 0.5), 1};
        Crossings c = crossings(oracle, tracer, origin, target - origin, 3);
        ++rays;
        oracle_failures += c.oracle != 1 ? 1 : 0;
        sse_failures += c.sse != 1 ? 1 : 0;
    }
    EXPECT_EQ(oracle_failures, 0) << "of " << rays << " rays at the slivers' shared edges";
    EXPECT_EQ(sse_failures, 0) << "of " << rays << " rays at the slivers' shared edges";
}

// An 8 × 8 grid of split squares in z = 0, rays from far to the side at 1e-2 to 1e-6 rad above its plane,
// aimed at its inner vertices and edge midpoints: each crosses it once.
TEST_F(MeshExtremes, GrazingRaysDownToAMicroradianCrossAGridOnce) {
    std::vector<V> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    constexpr int cells = 8;
    for (int j = 0; j <= cells; ++j) {
        for (int i = 0; i <= cells; ++i) {
            vertices.push_back({i - cells / 2.0, j - cells / 2.0, 0});
        }
    }
    auto at = [](int i, int j) { return static_cast<std::uint32_t>(j * (cells + 1) + i); };
    for (int j = 0; j < cells; ++j) {
        for (int i = 0; i < cells; ++i) {
            triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
    scene::Scene scene = scene_of(test::mesh(vertices, triangles), {0, 0, 1});
    twinray::reference::Tracer<double> oracle(scene);
    twinray::sse::Tracer tracer(scene);
    twinray::SplitMix64 random(11);
    int oracle_failures = 0, sse_failures = 0, rays = 0;
    for (double angle : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
        for (int k = 0; k < 800; ++k) {
            int i = 2 + static_cast<int>(random.next() % (2 * cells - 3));
            int j = 2 + static_cast<int>(random.next() % (2 * cells - 3));
            V target{0.5 * i - cells / 2.0, 0.5 * j - cells / 2.0, 0};
            double azimuth = random.uniform(0, 2 * std::numbers::pi);
            V towards{std::cos(azimuth) * std::cos(angle), std::sin(azimuth) * std::cos(angle), -std::sin(angle)};
            V origin = target - 0.5 * towards;
            Crossings c = crossings(oracle, tracer, origin, target - origin, 1);
            ++rays;
            oracle_failures += c.oracle != 1 ? 1 : 0;
            sse_failures += c.sse != 1 ? 1 : 0;
        }
    }
    EXPECT_EQ(oracle_failures, 0) << "of " << rays << " grazing rays";
    EXPECT_EQ(sse_failures, 0) << "of " << rays << " grazing rays";
}

// A ray lying exactly in a triangle's plane (z = 0, its direction's z exactly 0) meets it along a segment,
// not at a crossing: neither tracer reports it. The oracle's three edge signs sum to exactly 0; the SSE
// tracer's frame puts every vertex on one line (one sheared coordinate exactly 0), so its edge functions are
// exactly 0 and the tie rule's signs sum to 0 around the triangle.
TEST_F(MeshExtremes, RaysExactlyInATrianglesPlaneAreNotCrossings) {
    V a{0, 0, 0}, b{3, 0.4, 0}, c{0.7, 2, 0};
    scene::Scene scene = scene_of(test::mesh({a, b, c}, {{{0, 1, 2}}}), {1, 1, 3});
    twinray::reference::Tracer<double> oracle(scene);
    twinray::sse::Tracer tracer(scene);
    twinray::SplitMix64 random(13);
    int oracle_hits = 0, sse_hits = 0, rays = 0;
    for (int k = 0; k < 4000; ++k) {
        V inside = a + random.uniform(0.05, 0.45) * (b - a) + random.uniform(0.05, 0.45) * (c - a);
        double azimuth = random.uniform(0, 2 * std::numbers::pi);
        V direction{std::cos(azimuth), std::sin(azimuth), 0};
        Crossings crossed = crossings(oracle, tracer, inside - 5.0 * direction, direction, 20);
        ++rays;
        oracle_hits += crossed.oracle;
        sse_hits += crossed.sse;
    }
    EXPECT_EQ(oracle_hits, 0) << "of " << rays << " rays in the plane";
    EXPECT_EQ(sse_hits, 0) << "of " << rays << " rays in the plane";
}

}  // namespace

// A reflection that left the scene along a plane started a ray at 1e240, heading away from a small mesh near the
// origin. When the exact edge test's products overflowed past 2^339, brute force reported it crossing a triangle
// 6e238 along it while the BVH culled the mesh (found by the BVH differential fuzz target, its input now a seed). The
// predicates are exact for every finite input now (long double beyond double's reach): the ray meets nothing, in both
// walks.
TEST(MeshAtTheEdgesOfDouble, ARayFromTenToThe240MeetsNoTriangleBehindItWithTheBvhOrWithout) {
    test::SceneBuilder builder;
    builder.add(test::mesh({{0, 4, 1}, {4, 3, -3}, {-3, 4, 2}, {4, -4, 0}, {2, 1, 3}},
                           {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}}));
    scene::Scene scene = builder.build();
    const twinray::reference::Ray<double> ray{
        {-7.8125000000000001e237, -1.0078125000000001e240, 1.6783449630075636e225},
        {-0.0051678033854410449, -0.66664663672189484, 0.7453559924999299}};
    for (twinray::Accel accel : {twinray::Accel::none, twinray::Accel::bvh}) {
        twinray::reference::Tracer<double> oracle(scene, accel);
        std::optional<twinray::reference::Hit<double>> hit = oracle.intersect(ray);
        EXPECT_FALSE(hit.has_value()) << "accel " << static_cast<int>(accel) << ": t " << hit->t << ", triangle "
                                      << hit->triangle;
    }
}

// A vertex at 1e300 is a point like any other to the oracle, whose predicates are exact for every finite input: a ray
// straight down through the triangle reaching out to it meets it at t = 5, with the BVH and without. Float rounds the
// vertex to infinity, and the float tracers (the reference in float, the exact SSE tracer) leave the triangle out;
// the triangle beside it, within float's range, all three meet.
TEST(MeshAtTheEdgesOfDouble, ATriangleReachingBeyondFloatIsHitByTheOracleAndLeftOutByTheFloatTracers) {
    if (!twinray::sse::cpu_supports_sse41()) {
        GTEST_SKIP() << twinray::sse::missing_sse41_message();
    }
    test::SceneBuilder builder;
    // Triangle 0 reaches out to 1e300 along x; triangle 1, a unit square's half, lies beside it along -x.
    builder.add(test::mesh({{0, 0, 0}, {1e300, 0, 0}, {0, 1, 0}, {-1, 0, 0}}, {{0, 1, 2}, {0, 2, 3}}));
    builder.scene().camera.eye = {0, 0, 5};
    builder.scene().camera.look_at = {0, 0, 0};
    const scene::Scene scene = builder.build();
    for (twinray::Accel accel : {twinray::Accel::none, twinray::Accel::bvh}) {
        const std::string walk = accel == twinray::Accel::bvh ? "with the BVH" : "without";
        twinray::reference::Tracer<double> oracle(scene, accel);
        twinray::reference::Tracer<float> in_float(scene, accel);
        twinray::sse::Tracer tracer(scene, {}, accel);
        std::optional<twinray::reference::Hit<double>> far = oracle.intersect({{0.25, 0.25, 5}, {0, 0, -1}});
        ASSERT_TRUE(far.has_value()) << walk;
        EXPECT_EQ(far->triangle, 0) << walk;
        EXPECT_EQ(far->t, 5.0) << walk;
        EXPECT_FALSE(in_float.intersect({{0.25f, 0.25f, 5}, {0, 0, -1}}).has_value()) << walk;
        EXPECT_FALSE(tracer.intersect({{0.25f, 0.25f, 5}, {0, 0, -1}}).has_value()) << walk;
        std::optional<twinray::reference::Hit<double>> beside = oracle.intersect({{-0.25, 0.25, 5}, {0, 0, -1}});
        std::optional<twinray::reference::Hit<float>> beside_in_float =
            in_float.intersect({{-0.25f, 0.25f, 5}, {0, 0, -1}});
        std::optional<twinray::sse::Hit> sse_beside = tracer.intersect({{-0.25f, 0.25f, 5}, {0, 0, -1}});
        ASSERT_TRUE(beside.has_value() && beside_in_float.has_value() && sse_beside.has_value()) << walk;
        EXPECT_EQ(beside->triangle, 1) << walk;
        EXPECT_EQ(beside_in_float->triangle, 1) << walk;
        EXPECT_EQ(sse_beside->triangle, 1) << walk;
        EXPECT_EQ(sse_beside->t, 5.0f) << walk;
    }
}
