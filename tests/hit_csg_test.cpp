// CSG: the first hit through union, intersection and difference (nested, from outside and inside, with a
// half-space) and the tie rule, worked out by hand from the operands' geometry, against every tracer
// (tests/hit_expectations.h).
#include "tests/hit_expectations.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using twinray::reference::normalize;
using twinray::scene::CsgOp;
using V = twinray::reference::Vec3<double>;
namespace test = twinray::test;

TWINRAY_HIT_EXPECTATION_SUITE(CsgDifference);
TWINRAY_HIT_EXPECTATION_SUITE(CsgIntersection);
TWINRAY_HIT_EXPECTATION_SUITE(CsgUnion);
TWINRAY_HIT_EXPECTATION_SUITE(CsgNesting);
TWINRAY_HIT_EXPECTATION_SUITE(CsgTieRule);

twinray::scene::Scene scene_of(twinray::scene::Object object) {
    test::SceneBuilder builder;
    builder.object(std::move(object));
    return builder.build();
}

// ---------------------------------------------------------------------------------------------------
// Difference: the cube [−2,2]³ (leaf 0) minus the unit sphere at (0,0,2) (leaf 1), a dent in the top
// (+z) face whose surface faces into the cavity.

twinray::scene::Scene dented_cube() {
    return scene_of(test::csg(CsgOp::difference, {test::box({-2, -2, -2}, {2, 2, 2}), test::sphere({0, 0, 2}, 1)}));
}

TEST_P(CsgDifference, RayIntoTheCavityHitsTheSubtractedSphereWithNormalFacingIntoTheCavity) {
    auto scene = dented_cube();
    EXPECT_HIT(scene, V(0, 0, 10), V(0, 0, -1), {9, {0, 0, 1}, {0, 0, 1}, 1, true});
}

TEST_P(CsgDifference, RayBesideTheCavityHitsTheMinuendsFace) {
    auto scene = dented_cube();
    EXPECT_HIT(scene, V(1.5, 0, 10), V(0, 0, -1), {8, {1.5, 0, 2}, {0, 0, 1}, 0, true});
}

// From (0,0,5) along (0.2,0,−1)/√1.04 the line enters the sphere above the cube (z ≈ 2.9), crosses the
// cube's top inside the dent, and meets material where it leaves the sphere: the far root of
// t² + 2bt + c = 0 with f = (0,0,3), b = f·d, c = |f|² − 1. The normal there points to the centre.
TEST_P(CsgDifference, ObliqueRayThroughTheCavityMouthHitsTheFarWallOfTheCavity) {
    auto scene = dented_cube();
    V origin(0, 0, 5);
    V d = normalize(V(0.2, 0, -1));
    double b = dot(V(0, 0, 3), d);
    double t = -b + std::sqrt(b * b - 8);
    V point = origin + t * d;
    ASSERT_LT(point.z, 2.0) << "the expected point must lie inside the cube";
    EXPECT_HIT(scene, origin, d, {t, point, V(0, 0, 2) - point, 1, true});
}

TEST_P(CsgDifference, RayStartingInTheSolidLeavesIntoTheCavityThroughTheSphere) {
    auto scene = dented_cube();
    EXPECT_HIT(scene, V(0, 0, -1), V(0, 0, 1), {2, {0, 0, 1}, {0, 0, -1}, 1, false});
}

TEST_P(CsgDifference, RayStartingInTheCavityEntersTheSolidThroughTheSphere) {
    auto scene = dented_cube();
    EXPECT_HIT(scene, V(0, 0, 1.5), V(0, 0, -1), {0.5, {0, 0, 1}, {0, 0, 1}, 1, true});
}

// The part of the cube's top face over the dent was removed: a ray out of the dent meets nothing.
TEST_P(CsgDifference, RayLeavingTheCavityThroughItsMouthMisses) {
    auto scene = dented_cube();
    EXPECT_MISS(scene, V(0, 0, 1.5), V(0, 0, 1));
    EXPECT_MISS(scene, V(0, 0, 1.5), V(0.3, 0.2, 1));
}

// The cube minus two spheres, one denting the top, one the bottom: difference is the first child
// minus all the others.
TEST_P(CsgDifference, DifferenceOfThreeChildrenRemovesEverySubtrahend) {
    auto scene = scene_of(test::csg(CsgOp::difference, {test::box({-2, -2, -2}, {2, 2, 2}), test::sphere({0, 0, 2}, 1),
                                                        test::sphere({0, 0, -2}, 1)}));
    EXPECT_HIT(scene, V(0, 0, 10), V(0, 0, -1), {9, {0, 0, 1}, {0, 0, 1}, 1, true});
    EXPECT_HIT(scene, V(0, 0, -10), V(0, 0, 1), {9, {0, 0, -1}, {0, 0, -1}, 2, true});
    EXPECT_HIT(scene, V(0, 0, 0), V(0, 0, 1), {1, {0, 0, 1}, {0, 0, -1}, 1, false});
    EXPECT_HIT(scene, V(0, 0, 0), V(0, 0, -1), {1, {0, 0, -1}, {0, 0, 1}, 2, false});
}

// Cube [−1,1]³ (leaf 0) minus the half-space y < 0 (leaf 1): the upper half is left, and the cut face
// y = 0 faces down, out of the remaining solid.
twinray::scene::Scene cube_cut_by_plane() {
    return scene_of(test::csg(CsgOp::difference, {test::box({-1, -1, -1}, {1, 1, 1}), test::plane({0, 1, 0}, 0)}));
}

TEST_P(CsgDifference, HalfSpaceCutFaceIsHitFromTheRemovedSideWithTheFlippedPlaneNormal) {
    auto scene = cube_cut_by_plane();
    EXPECT_HIT(scene, V(0.2, -5, 0.3), V(0, 1, 0), {5, {0.2, 0, 0.3}, {0, -1, 0}, 1, true});
    // Oblique: from (−0.5,−3,0.5) along (1,3,0)/√10 the line reaches y = 0 at (0.5,0,0.5), t = √10,
    // having crossed the cube's bottom face (y = −1) inside the removed half.
    EXPECT_HIT(scene, V(-0.5, -3, 0.5), V(1, 3, 0), {std::sqrt(10.0), {0.5, 0, 0.5}, {0, -1, 0}, 1, true});
}

TEST_P(CsgDifference, HalfSpaceCutKeepsTheMinuendsFacesOnTheOtherSide) {
    auto scene = cube_cut_by_plane();
    EXPECT_HIT(scene, V(0, 5, 0), V(0, -1, 0), {4, {0, 1, 0}, {0, 1, 0}, 0, true});
    EXPECT_HIT(scene, V(0.5, 0.5, 5), V(0, 0, -1), {4, {0.5, 0.5, 1}, {0, 0, 1}, 0, true});
    EXPECT_MISS(scene, V(0, -0.5, 5), V(0, 0, -1));
}

TEST_P(CsgDifference, RayStartingInsideAHalfSpaceCutSolidLeavesThroughTheCutFace) {
    auto scene = cube_cut_by_plane();
    EXPECT_HIT(scene, V(0, 0.5, 0), V(0, -1, 0), {0.5, {0, 0, 0}, {0, 1, 0}, 1, false});
}

// From the removed lower half of the cube: upwards the cut face is entered; downwards the cube's
// bottom face lies in the removed half and is no surface of the solid.
TEST_P(CsgDifference, RayStartingInTheRemovedHalfSeesOnlyTheCutFace) {
    auto scene = cube_cut_by_plane();
    EXPECT_HIT(scene, V(0, -0.5, 0), V(0, 1, 0), {0.5, {0, 0, 0}, {0, -1, 0}, 1, true});
    EXPECT_MISS(scene, V(0, -0.5, 0), V(0, -1, 0));
}

// The cube [−1,1]³ minus the box [0,1]×[−2,2]² shares the face x = 1 with it: the two faces cancel
// (no zero-thickness skin is left), and the first surface is the subtrahend's face x = 0.
TEST_P(CsgDifference, SubtrahendSharingAFaceLeavesNoSkinOnThatFace) {
    auto scene =
        scene_of(test::csg(CsgOp::difference, {test::box({-1, -1, -1}, {1, 1, 1}), test::box({0, -2, -2}, {1, 2, 2})}));
    EXPECT_HIT(scene, V(5, 0.2, 0.3), V(-1, 0, 0), {5, {0, 0.2, 0.3}, {1, 0, 0}, 1, true});
}

// ---------------------------------------------------------------------------------------------------
// Intersection: two unit spheres at (∓0.5,0,0) (leaves 0 and 1) make a lens spanning x in [−0.5,0.5]
// on the x axis; its −x face is sphere 1's surface, its +x face sphere 0's.

twinray::scene::Scene lens() {
    return scene_of(test::csg(CsgOp::intersection, {test::sphere({-0.5, 0, 0}, 1), test::sphere({0.5, 0, 0}, 1)}));
}

TEST_P(CsgIntersection, LensIsEnteredThroughTheSphereEnteredLast) {
    auto scene = lens();
    EXPECT_HIT(scene, V(-5, 0, 0), V(1, 0, 0), {4.5, {-0.5, 0, 0}, {-1, 0, 0}, 1, true});
    EXPECT_HIT(scene, V(5, 0, 0), V(-1, 0, 0), {4.5, {0.5, 0, 0}, {1, 0, 0}, 0, true});
}

// At height 0.95 the spheres' chords are x in [−0.812,−0.188] and [0.188,0.812]: disjoint.
TEST_P(CsgIntersection, RaysThroughOnlyOneOperandMiss) {
    auto scene = lens();
    EXPECT_MISS(scene, V(-5, 0.95, 0), V(1, 0, 0));
    EXPECT_MISS(scene, V(-1.2, 0, 5), V(0, 0, -1));
    EXPECT_MISS(scene, V(1.2, 0, 5), V(0, 0, -1));
}

TEST_P(CsgIntersection, RayStartingInsideTheLensLeavesThroughTheSphereLeftFirst) {
    auto scene = lens();
    EXPECT_HIT(scene, V(0, 0, 0), V(1, 0, 0), {0.5, {0.5, 0, 0}, {-1, 0, 0}, 0, false});
    EXPECT_HIT(scene, V(0, 0, 0), V(-1, 0, 0), {0.5, {-0.5, 0, 0}, {1, 0, 0}, 1, false});
}

// Along −z at x = 0 both spheres are entered at exactly the same t (the same arithmetic, mirrored):
// z = √0.75 on the lens's rim. The tie goes to the earlier primitive, sphere 0, whose normal there is
// (0.5, 0, √0.75) — sphere 1's would be (−0.5, 0, √0.75).
TEST_P(CsgIntersection, LensRimWhereBothSpheresMeetAtTheSameTReportsTheEarlierSphere) {
    auto scene = lens();
    double z = std::sqrt(0.75);
    EXPECT_HIT(scene, V(0, 0, 5), V(0, 0, -1), {5 - z, {0, 0, z}, {0.5, 0, z}, 0, true});
}

TEST_P(CsgIntersection, CoincidentEntryFacesReportTheEarlierChildWhicheverOrder) {
    auto first = scene_of(
        test::csg(CsgOp::intersection, {test::box({-1, -1, -1}, {1, 1, 1}), test::box({-2, -2, -2}, {1, 2, 2})}));
    auto second = scene_of(
        test::csg(CsgOp::intersection, {test::box({-2, -2, -2}, {1, 2, 2}), test::box({-1, -1, -1}, {1, 1, 1})}));
    EXPECT_HIT(first, V(5, 0.1, 0.2), V(-1, 0, 0), {4, {1, 0.1, 0.2}, {1, 0, 0}, 0, true});
    EXPECT_HIT(second, V(5, 0.1, 0.2), V(-1, 0, 0), {4, {1, 0.1, 0.2}, {1, 0, 0}, 0, true});
}

// The unit ball (leaf 0) cut to its lower half by the half-space y < 0 (leaf 1).
TEST_P(CsgIntersection, BallIntersectedWithAHalfSpaceShowsTheFlatCutFromAbove) {
    auto scene = scene_of(test::csg(CsgOp::intersection, {test::sphere({0, 0, 0}, 1), test::plane({0, 1, 0}, 0)}));
    EXPECT_HIT(scene, V(0.2, 5, 0.1), V(0, -1, 0), {5, {0.2, 0, 0.1}, {0, 1, 0}, 1, true});
    EXPECT_HIT(scene, V(0, -5, 0), V(0, 1, 0), {4, {0, -1, 0}, {0, -1, 0}, 0, true});
    EXPECT_MISS(scene, V(0, 0.5, 5), V(0, 0, -1));
}

// ---------------------------------------------------------------------------------------------------
// Union: the same two overlapping unit spheres.

twinray::scene::Scene two_balls() {
    return scene_of(test::csg(CsgOp::union_, {test::sphere({-0.5, 0, 0}, 1), test::sphere({0.5, 0, 0}, 1)}));
}

TEST_P(CsgUnion, RayFromOutsideEntersThroughTheNearerSphere) {
    auto scene = two_balls();
    EXPECT_HIT(scene, V(-5, 0, 0), V(1, 0, 0), {3.5, {-1.5, 0, 0}, {-1, 0, 0}, 0, true});
    EXPECT_HIT(scene, V(5, 0, 0), V(-1, 0, 0), {3.5, {1.5, 0, 0}, {1, 0, 0}, 1, true});
}

// From inside sphere 0 at x = −1 the ray passes sphere 0's surface at x = 0.5 inside sphere 1: no seam
// there; it leaves at sphere 1's far surface x = 1.5.
TEST_P(CsgUnion, RayFromInsideOneSphereCrossesTheOverlapWithoutASeam) {
    auto scene = two_balls();
    EXPECT_HIT(scene, V(-1, 0, 0), V(1, 0, 0), {2.5, {1.5, 0, 0}, {-1, 0, 0}, 1, false});
    EXPECT_HIT(scene, V(0, 0, 0), V(-1, 0, 0), {1.5, {-1.5, 0, 0}, {1, 0, 0}, 0, false});
}

// Spheres at x = ∓3: from the origin the first piece is behind the ray, the second is ahead.
TEST_P(CsgUnion, DisjointPieceBehindTheRayIsSkippedForThePieceAhead) {
    auto scene = scene_of(test::csg(CsgOp::union_, {test::sphere({-3, 0, 0}, 1), test::sphere({3, 0, 0}, 1)}));
    EXPECT_HIT(scene, V(0, 0, 0), V(1, 0, 0), {2, {2, 0, 0}, {-1, 0, 0}, 1, true});
    EXPECT_HIT(scene, V(-5, 0, 0), V(1, 0, 0), {1, {-4, 0, 0}, {-1, 0, 0}, 0, true});
}

TEST_P(CsgUnion, UnionOfTwoIdenticalSpheresReportsTheFirstChildFromOutsideAndInside) {
    auto scene = scene_of(test::csg(CsgOp::union_, {test::sphere({0, 1, 0}, 1), test::sphere({0, 1, 0}, 1)}));
    EXPECT_HIT(scene, V(0, 1, 5), V(0, 0, -1), {4, {0, 1, 1}, {0, 0, 1}, 0, true});
    EXPECT_HIT(scene, V(0, 1, 0), V(0, 0, -1), {1, {0, 1, -1}, {0, 0, 1}, 0, false});
}

// The half-space y < 0 (leaf 0) united with the unit ball (leaf 1): a ray from deep inside the
// half-space passes the plane inside the ball and leaves through the ball's top.
TEST_P(CsgUnion, RayFromInsideAHalfSpaceUnionLeavesWhereItIsInNeitherOperand) {
    auto scene = scene_of(test::csg(CsgOp::union_, {test::plane({0, 1, 0}, 0), test::sphere({0, 0, 0}, 1)}));
    EXPECT_HIT(scene, V(0, -5, 0), V(0, 1, 0), {6, {0, 1, 0}, {0, -1, 0}, 1, false});
    EXPECT_HIT(scene, V(3, -5, 0), V(0, 1, 0), {5, {3, 0, 0}, {0, -1, 0}, 0, false});
    EXPECT_HIT(scene, V(0, 5, 0), V(0, -1, 0), {4, {0, 1, 0}, {0, 1, 0}, 1, true});
}

// ---------------------------------------------------------------------------------------------------
// Nesting.

// The cube [−2,2]³ (leaf 0) minus the lens of spheres 1 and 2: a lens-shaped cavity, x in [−0.5,0.5]
// on the axis; its −x wall is sphere 2's surface, its +x wall sphere 1's.
twinray::scene::Scene cube_with_lens_cavity() {
    return scene_of(test::csg(CsgOp::difference, {test::box({-2, -2, -2}, {2, 2, 2}),
                                                  test::csg(CsgOp::intersection, {test::sphere({-0.5, 0, 0}, 1),
                                                                                  test::sphere({0.5, 0, 0}, 1)})}));
}

TEST_P(CsgNesting, CubeMinusLensIsLeftIntoTheCavityThroughTheLensFace) {
    auto scene = cube_with_lens_cavity();
    EXPECT_HIT(scene, V(-5, 0, 0), V(1, 0, 0), {3, {-2, 0, 0}, {-1, 0, 0}, 0, true});
    EXPECT_HIT(scene, V(-1, 0, 0), V(1, 0, 0), {0.5, {-0.5, 0, 0}, {-1, 0, 0}, 2, false});
}

TEST_P(CsgNesting, RayInsideALensCavityEntersTheSolidThroughTheFarLensFace) {
    auto scene = cube_with_lens_cavity();
    EXPECT_HIT(scene, V(0, 0, 0), V(1, 0, 0), {0.5, {0.5, 0, 0}, {-1, 0, 0}, 1, true});
    EXPECT_HIT(scene, V(0, 0, 0), V(-1, 0, 0), {0.5, {-0.5, 0, 0}, {1, 0, 0}, 2, true});
}

// The two overlapping balls (leaves 0, 1) cut to the slab |y| ≤ 0.25 (leaf 2).
TEST_P(CsgNesting, UnionCutBySlabShowsTheSlabFacesAndTheBallsSides) {
    auto scene = scene_of(test::csg(
        CsgOp::intersection, {test::csg(CsgOp::union_, {test::sphere({-0.5, 0, 0}, 1), test::sphere({0.5, 0, 0}, 1)}),
                              test::box({-3, -0.25, -3}, {3, 0.25, 3})}));
    EXPECT_HIT(scene, V(0, 5, 0), V(0, -1, 0), {4.75, {0, 0.25, 0}, {0, 1, 0}, 2, true});
    EXPECT_HIT(scene, V(-5, 0, 0), V(1, 0, 0), {3.5, {-1.5, 0, 0}, {-1, 0, 0}, 0, true});
    EXPECT_HIT(scene, V(0, 0, 0), V(1, 0, 0), {1.5, {1.5, 0, 0}, {-1, 0, 0}, 1, false});
    // At height 0.5 the line is in the balls but above the slab.
    EXPECT_MISS(scene, V(-5, 0.5, 0), V(1, 0, 0));
}

// ---------------------------------------------------------------------------------------------------
// The tie rule at top level: at exactly the same t the object earlier in `objects` wins.

TEST_P(CsgTieRule, TwoIdenticalSpheresReportTheFirstOnesLeaf) {
    test::SceneBuilder builder;
    builder.object(test::sphere({100, 100, 100}, 1));  // leaf 0, never hit: the twins are leaves 1 and 2
    builder.object(test::sphere({0, 0, 0}, 1));
    builder.object(test::sphere({0, 0, 0}, 1));
    auto scene = builder.build();
    EXPECT_HIT(scene, V(0, 0, 5), V(0, 0, -1), {4, {0, 0, 1}, {0, 0, 1}, 1, true});
    double y = std::sqrt(0.91);  // where the line x = 0.3 leaves the unit sphere
    EXPECT_HIT(scene, V(0.3, 0, 0), V(0, 1, 0), {y, {0.3, y, 0}, {-0.3, -y, 0}, 1, false});
}

// A box's top face and a plane at y = 0 are met at exactly the same t (both −o_y/d_y): the earlier
// object wins, whichever kind it is.
TEST_P(CsgTieRule, CoincidentPlaneAndBoxFaceReportTheEarlierObjectWhicheverKindItIs) {
    V origin(0.1, 3, 0.2);
    V direction(0.2, -1, 0.1);  // y = 0 after 3 of these steps, at (0.7, 0, 0.5)
    V point(0.7, 0, 0.5);
    double t = 3 * length(direction);
    {
        test::SceneBuilder builder;
        builder.object(test::plane({0, 1, 0}, 0)).object(test::box({-1, -1, -1}, {1, 0, 1}));
        EXPECT_HIT(builder.build(), origin, direction, {t, point, {0, 1, 0}, 0, true});
    }
    {
        test::SceneBuilder builder;
        builder.object(test::box({-1, -1, -1}, {1, 0, 1})).object(test::plane({0, 1, 0}, 0));
        EXPECT_HIT(builder.build(), origin, direction, {t, point, {0, 1, 0}, 0, true});
    }
}

}  // namespace
