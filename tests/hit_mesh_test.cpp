// A mesh's first hits, worked out by hand from the triangles' geometry (tests/hit_expectations.h runs each
// against every tracer and knob): which triangle, its side, the tie-break rules, and that degenerate
// triangles are never hit.
#include "tests/hit_expectations.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using V = twinray::reference::Vec3<double>;
namespace test = twinray::test;
namespace scene = twinray::scene;

TWINRAY_HIT_EXPECTATION_SUITE(IntersectionMesh);

// The square [0, 2]² of z = 0 as two triangles, counter-clockwise seen from +z (its front): triangle 0 below
// the diagonal x = y, triangle 1 above it. Leaf 1, after a far-away decoy sphere.
scene::Mesh square(double z = 0) {
    return test::mesh({{0, 0, z}, {2, 0, z}, {2, 2, z}, {0, 2, z}}, {{{0, 1, 2}}, {{0, 2, 3}}});
}

scene::Scene scene_with(scene::Mesh mesh) {
    test::SceneBuilder builder;
    builder.object(test::sphere({-1000, 1000, 1000}, 1));
    builder.add(std::move(mesh));
    return builder.build();
}

TEST_P(IntersectionMesh, RayOntoTheFrontEntersTheTriangleUnderIt) {
    auto scene = scene_with(square());
    EXPECT_HIT(scene, V(1.5, 0.5, 5), V(0, 0, -1), {5, {1.5, 0.5, 0}, {0, 0, 1}, 1, true, 0});
    EXPECT_HIT(scene, V(0.5, 1.5, 5), V(0, 0, -1), {5, {0.5, 1.5, 0}, {0, 0, 1}, 1, true, 1});
}

TEST_P(IntersectionMesh, RayOntoTheBackLeavesWithTheNormalTurnedToTheRay) {
    auto scene = scene_with(square());
    EXPECT_HIT(scene, V(0.5, 1.5, -3), V(0, 0, 1), {3, {0.5, 1.5, 0}, {0, 0, -1}, 1, false, 1});
}

// (3, 4, 12)/13 from (1.5 − 3, 0.5 − 4, 12): t = 13, landing on (1.5, 0.5, 0) in triangle 0.
TEST_P(IntersectionMesh, ObliqueRayHitsAtTheDistanceSolvedByHand) {
    auto scene = scene_with(square());
    EXPECT_HIT(scene, V(-1.5, -3.5, 12), V(3, 4, -12), {13, {1.5, 0.5, 0}, {0, 0, 1}, 1, true, 0});
}

TEST_P(IntersectionMesh, RaysBesideTheSquareOrAwayFromItMiss) {
    auto scene = scene_with(square());
    EXPECT_MISS(scene, V(2.5, 1, 5), V(0, 0, -1));
    EXPECT_MISS(scene, V(1, -0.5, 5), V(0, 0, -1));
    EXPECT_MISS(scene, V(1, 1, 5), V(0, 0, 1));
    EXPECT_MISS(scene, V(1, 1, 5), V(1, 0, 0));
}

// Straight down at (1, 1), on the shared diagonal: the origin perturbed by (ε, ε²) in x and y (Simulation of
// Simplicity, reference/triangle.h) lies below the diagonal, in triangle 0, and in triangle 0 alone.
TEST_P(IntersectionMesh, RayThroughTheSharedEdgeHitsTheTriangleTheTieRuleGivesIt) {
    auto scene = scene_with(square());
    EXPECT_HIT(scene, V(1, 1, 5), V(0, 0, -1), {5, {1, 1, 0}, {0, 0, 1}, 1, true, 0});
    EXPECT_HIT(scene, V(1.25, 1.25, 5), V(0, 0, -1), {5, {1.25, 1.25, 0}, {0, 0, 1}, 1, true, 0});
}

// At a corner of the square shared by both triangles, (0, 0), and at the one triangle 1 alone has, (0, 2):
// the perturbed origin (ε, ε²) lies inside the square at (0, 0), in triangle 0 (below the diagonal), and
// outside it at (0, 2) (y = 2 + ε² > 2): a miss, as for the same ray beside the square.
TEST_P(IntersectionMesh, RaysThroughCornersHitOnlyWhereThePerturbedOriginLiesInside) {
    if (GetParam().precision.moller_trumbore ||
        (GetParam().kind == test::TracerKind::plugin && GetParam().plugin != &test::sse_plugin())) {
        GTEST_SKIP() << "the tie rule is twinray's watertight test's, not the tracer ABI's; Moller-Trumbore takes "
                        "every edge and corner (its leaks: twinray watertight)";
    }
    auto scene = scene_with(square());
    EXPECT_HIT(scene, V(0, 0, 5), V(0, 0, -1), {5, {0, 0, 0}, {0, 0, 1}, 1, true, 0});
    EXPECT_MISS(scene, V(0, 2, 5), V(0, 0, -1));
}

TEST_P(IntersectionMesh, DegenerateTrianglesAreNeverHit) {
    auto mesh = test::mesh({{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {1, 1, 0}}, {{{0, 1, 1}}, {{0, 3, 2}}, {{0, 1, 2}}});
    auto data = std::make_shared<scene::MeshData>(*mesh.data);
    data->degenerate = {0, 1};  // a repeated index; three collinear vertices
    mesh.data = data;
    auto scene = scene_with(mesh);
    EXPECT_HIT(scene, V(1.5, 0.5, 5), V(0, 0, -1), {5, {1.5, 0.5, 0}, {0, 0, 1}, 1, true, 2});
    EXPECT_MISS(scene, V(0.5, 1.5, 5), V(0, 0, -1));
}

// Two copies of the square at the same place: the earlier mesh (leaf 1) takes the hit at equal t.
TEST_P(IntersectionMesh, AtEqualDistanceTheEarlierMeshWins) {
    test::SceneBuilder builder;
    builder.object(test::sphere({-1000, 1000, 1000}, 1));
    builder.add(square());
    builder.add(square());
    auto scene = builder.build();
    EXPECT_HIT(scene, V(1.5, 0.5, 5), V(0, 0, -1), {5, {1.5, 0.5, 0}, {0, 0, 1}, 1, true, 0});
}

// A mesh holding the square twice (triangles 2 and 3 repeat 0 and 1): the lower triangle wins at equal t.
TEST_P(IntersectionMesh, AtEqualDistanceTheLowerTriangleOfOneMeshWins) {
    auto mesh =
        test::mesh({{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}}, {{{0, 2, 3}}, {{0, 1, 2}}, {{0, 2, 3}}, {{0, 1, 2}}});
    auto scene = scene_with(mesh);
    EXPECT_HIT(scene, V(1.5, 0.5, 5), V(0, 0, -1), {5, {1.5, 0.5, 0}, {0, 0, 1}, 1, true, 1});
    EXPECT_HIT(scene, V(0.5, 1.5, 5), V(0, 0, -1), {5, {0.5, 1.5, 0}, {0, 0, 1}, 1, true, 0});
}

// A sphere in front of the square takes the hit; one behind it does not.
TEST_P(IntersectionMesh, TheNearestSurfaceWinsBetweenAMeshAndOtherPrimitives) {
    test::SceneBuilder builder;
    builder.add(square());
    builder.object(test::sphere({1.5, 0.5, 2}, 1));
    builder.object(test::sphere({0.5, 1.5, -2}, 1));
    auto scene = builder.build();
    EXPECT_HIT(scene, V(1.5, 0.5, 5), V(0, 0, -1), {2, {1.5, 0.5, 3}, {0, 0, 1}, 1, true});
    EXPECT_HIT(scene, V(0.5, 1.5, 5), V(0, 0, -1), {5, {0.5, 1.5, 0}, {0, 0, 1}, 0, true, 1});
}

}  // namespace
