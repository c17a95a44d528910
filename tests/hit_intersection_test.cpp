// Each primitive's first hit, with every expectation (t, hit point, normal, leaf, entering) worked out by
// hand from the primitive's geometry, never by running a tracer's formulas; every expectation runs
// against every tracer (tests/hit_expectations.h).
#include "reference/tracer.h"
#include "tests/hit_expectations.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using twinray::reference::normalize;
using V = twinray::reference::Vec3<double>;
namespace test = twinray::test;

TWINRAY_HIT_EXPECTATION_SUITE(IntersectionPlane);
TWINRAY_HIT_EXPECTATION_SUITE(IntersectionSphere);
TWINRAY_HIT_EXPECTATION_SUITE(IntersectionCylinder);
TWINRAY_HIT_EXPECTATION_SUITE(IntersectionBox);
TWINRAY_HIT_EXPECTATION_SUITE(IntersectionScene);

// Every scene starts with a far-away decoy sphere that no ray below comes near, so the primitive under
// test is leaf 1: a tracer that reports leaf 0 by default, or the wrong leaf, fails.
twinray::scene::Scene scene_with(twinray::scene::Object object) {
    test::SceneBuilder builder;
    builder.object(test::sphere({-1000, 1000, 1000}, 1));
    builder.object(std::move(object));
    return builder.build();
}

// ---------------------------------------------------------------------------------------------------
// Plane: the surface n·p = d, solid on the side n·p < d.

TEST_P(IntersectionPlane, HitFromTheOutsideEntersWithTheOutwardNormal) {
    auto scene = scene_with(test::plane({0, 1, 0}, 1));
    EXPECT_HIT(scene, V(0.5, 5, -2), V(0, -1, 0), {4, {0.5, 1, -2}, {0, 1, 0}, 1, true});
}

TEST_P(IntersectionPlane, HitFromTheSolidSideLeavesWithNormalFacingTheRay) {
    auto scene = scene_with(test::plane({0, 1, 0}, 1));
    EXPECT_HIT(scene, V(0.5, -2, -2), V(0, 1, 0), {3, {0.5, 1, -2}, {0, -1, 0}, 1, false});
}

// n = (1,2,2)/3, d = 3. From o = (4,4,4) (n·o = 20/3) along (−1,−2,0)/√5 (n·dir = −5/(3√5)):
// t = (3 − 20/3)/(−5/(3√5)) = 11√5/5, landing on (4,4,4) + 11/5·(−1,−2,0) = (1.8, −0.4, 4), n·p = 3.
TEST_P(IntersectionPlane, ObliqueHitFromTheOutsideIsAtTheDistanceSolvedByHand) {
    auto scene = scene_with(test::plane({1, 2, 2}, 3));
    V n(1.0 / 3, 2.0 / 3, 2.0 / 3);
    EXPECT_HIT(scene, V(4, 4, 4), V(-1, -2, 0), {11 * std::sqrt(5.0) / 5, {1.8, -0.4, 4}, n, 1, true});
}

// The same plane from its solid side: o = (−1,−1,0) (n·o = −1) along (1,1,1)/√3:
// t = (3 + 1)/(5/(3√3)) = 12√3/5, landing on (−1,−1,0) + 12/5·(1,1,1) = (1.4, 1.4, 2.4).
TEST_P(IntersectionPlane, ObliqueHitFromTheSolidSideLeavesWithTheNormalTurnedToTheRay) {
    auto scene = scene_with(test::plane({1, 2, 2}, 3));
    V n(1.0 / 3, 2.0 / 3, 2.0 / 3);
    EXPECT_HIT(scene, V(-1, -1, 0), V(1, 1, 1), {12 * std::sqrt(3.0) / 5, {1.4, 1.4, 2.4}, -n, 1, false});
}

TEST_P(IntersectionPlane, RayParallelToThePlaneMissesOnEitherSide) {
    auto scene = scene_with(test::plane({0, 1, 0}, 1));
    EXPECT_MISS(scene, V(0, 5, 0), V(1, 0, 0));
    EXPECT_MISS(scene, V(0, -5, 0), V(1, 0, 1));
}

TEST_P(IntersectionPlane, RayHeadingAwayFromThePlaneMissesOnEitherSide) {
    auto scene = scene_with(test::plane({0, 1, 0}, 1));
    EXPECT_MISS(scene, V(0, 5, 0), V(0.3, 1, 0));
    EXPECT_MISS(scene, V(0, -5, 0), V(0, -1, 0.3));
}

// ---------------------------------------------------------------------------------------------------
// Sphere. A ray along unit d passing the centre c at perpendicular offset h·e (e ⟂ d, unit), starting
// s before the point of closest approach, meets the sphere at t = s ∓ √(r² − h²).

const V sphere_center(1, -2, 0.5);
constexpr double sphere_radius = 1.5;
const V along(2.0 / 3, -1.0 / 3, 2.0 / 3);   // unit
const V across(2.0 / 3, 2.0 / 3, -1.0 / 3);  // unit, ⟂ along

twinray::scene::Scene sphere_scene() {
    return scene_with(test::sphere({1, -2, 0.5}, sphere_radius));
}

TEST_P(IntersectionSphere, HeadOnHitIsAtTheNearSurfaceWithTheRadialNormal) {
    auto scene = sphere_scene();
    EXPECT_HIT(scene, V(1, -2, 10.5), V(0, 0, -1), {8.5, {1, -2, 2}, {0, 0, 1}, 1, true});
}

// h = 0.9, s = 6: t = 6 − √(2.25 − 0.81) = 4.8, at c + 0.9e − 1.2d with normal (0.9e − 1.2d)/1.5, so
// the ray meets the surface at the angle acos(0.8) from the normal.
TEST_P(IntersectionSphere, ObliqueHitIsAtTheChordEntryAtTheAngleWorkedOutByHand) {
    auto scene = sphere_scene();
    V origin = sphere_center - 6.0 * along + 0.9 * across;
    V normal = 0.6 * across - 0.8 * along;
    EXPECT_HIT(scene, origin, along, {4.8, sphere_center + 1.5 * normal, normal, 1, true});
    EXPECT_NEAR(-dot(first_hit(scene, origin, along).value().normal, along), 0.8, tolerance()) << "cosine of incidence";
}

// From c + 0.5e along d the ray leaves at t = √(r² − 0.25) = √2 through c + 0.5e + √2·d, where the
// outward normal (0.5e + √2d)/1.5 points along the ray: the reported normal is its opposite.
TEST_P(IntersectionSphere, HitFromInsideReportsLeavingWithNormalFacingTheRay) {
    auto scene = sphere_scene();
    V origin = sphere_center + 0.5 * across;
    V outward = (0.5 * across + std::sqrt(2.0) * along) / 1.5;
    EXPECT_HIT(scene, origin, along, {std::sqrt(2.0), sphere_center + 1.5 * outward, -outward, 1, false});
}

TEST_P(IntersectionSphere, HitFromTheCentreLeavesAtTheRadius) {
    auto scene = sphere_scene();
    EXPECT_HIT(scene, sphere_center, -across, {1.5, sphere_center - 1.5 * across, across, 1, false});
}

TEST_P(IntersectionSphere, SphereBehindTheRayOriginIsMissed) {
    auto scene = sphere_scene();
    EXPECT_MISS(scene, V(sphere_center + 5.0 * along + 0.3 * across), along);
}

TEST_P(IntersectionSphere, RayPassingFartherThanTheRadiusMisses) {
    auto scene = sphere_scene();
    EXPECT_MISS(scene, V(sphere_center - 6.0 * along + 1.6 * across), along);
}

// ---------------------------------------------------------------------------------------------------
// Cylinder, axis-aligned: base (1,−1,2), cap (1,1,2), radius 1. Points are written base + (x, y, z).

const V cyl_base(1, -1, 2);

twinray::scene::Scene upright_cylinder_scene() {
    return scene_with(test::cylinder({1, -1, 2}, {1, 1, 2}, 1));
}

// At height 0 the ray along +x, 0.6 off the axis in z, meets x² + 0.36 = 1 at x = −0.8.
TEST_P(IntersectionCylinder, SideHitPerpendicularToTheAxisHasTheRadialNormal) {
    auto scene = upright_cylinder_scene();
    EXPECT_HIT(scene, cyl_base + V(-6, 1, 0.6), V(1, 0, 0), {5.2, cyl_base + V(-0.8, 1, 0.6), {-0.8, 0, 0.6}, 1, true});
}

// Along (1,−1,0)/√2 from (−3,3,0): the side x = −1 at t = 2√2, at height 1 — below the cap (height 2),
// although the ray started above it.
TEST_P(IntersectionCylinder, ObliqueRayFromAboveTheCapHitsTheSideBelowTheRim) {
    auto scene = upright_cylinder_scene();
    EXPECT_HIT(scene, cyl_base + V(-3, 3, 0), V(1, -1, 0),
               {2 * std::sqrt(2.0), cyl_base + V(-1, 1, 0), {-1, 0, 0}, 1, true});
}

// Along (1,−1,0)/√2 from (−1.5,3.5,0): the cap plane y = 2 at t = 1.5√2, at x = 0 inside the rim.
TEST_P(IntersectionCylinder, ObliqueRayHitsTheCapInsideTheRim) {
    auto scene = upright_cylinder_scene();
    EXPECT_HIT(scene, cyl_base + V(-1.5, 3.5, 0), V(1, -1, 0),
               {1.5 * std::sqrt(2.0), cyl_base + V(0, 2, 0), {0, 1, 0}, 1, true});
}

TEST_P(IntersectionCylinder, RaysParallelToTheAxisHitEitherCapWithTheAxialNormal) {
    auto scene = upright_cylinder_scene();
    EXPECT_HIT(scene, cyl_base + V(0.3, 5, 0.2), V(0, -1, 0), {3, cyl_base + V(0.3, 2, 0.2), {0, 1, 0}, 1, true});
    EXPECT_HIT(scene, cyl_base + V(0.3, -5, 0.2), V(0, 1, 0), {5, cyl_base + V(0.3, 0, 0.2), {0, -1, 0}, 1, true});
}

TEST_P(IntersectionCylinder, RayAlongTheAxisEntersThroughTheBaseCap) {
    auto scene = upright_cylinder_scene();
    EXPECT_HIT(scene, cyl_base + V(0, -3, 0), V(0, 1, 0), {3, cyl_base, {0, -1, 0}, 1, true});
    EXPECT_HIT(scene, cyl_base + V(0, 7, 0), V(0, -1, 0), {5, cyl_base + V(0, 2, 0), {0, 1, 0}, 1, true});
}

TEST_P(IntersectionCylinder, RayAlongTheAxisFromInsideLeavesThroughTheCapAheadWithNormalFacingTheRay) {
    auto scene = upright_cylinder_scene();
    EXPECT_HIT(scene, cyl_base + V(0, 0.5, 0), V(0, 1, 0), {1.5, cyl_base + V(0, 2, 0), {0, -1, 0}, 1, false});
    EXPECT_HIT(scene, cyl_base + V(0, 0.5, 0), V(0, -1, 0), {0.5, cyl_base, {0, 1, 0}, 1, false});
}

// From the axis at height 1 along (1,0,1)/√2: the side at radial distance 1, t = 1.
TEST_P(IntersectionCylinder, SideHitFromInsideLeavesWithNormalFacingTheRay) {
    auto scene = upright_cylinder_scene();
    double h = 1 / std::sqrt(2.0);
    EXPECT_HIT(scene, cyl_base + V(0, 1, 0), V(1, 0, 1), {1, cyl_base + V(h, 1, h), {-h, 0, -h}, 1, false});
}

TEST_P(IntersectionCylinder, RayParallelToTheAxisOutsideTheRadiusMisses) {
    auto scene = upright_cylinder_scene();
    EXPECT_MISS(scene, V(cyl_base + V(1.5, -3, 0)), V(0, 1, 0));
    EXPECT_MISS(scene, V(cyl_base + V(0.8, -3, 0.8)), V(0, 1, 0));
}

TEST_P(IntersectionCylinder, RayPassingAboveTheCapOrBehindTheOriginMisses) {
    auto scene = upright_cylinder_scene();
    EXPECT_MISS(scene, V(cyl_base + V(-5, 2.5, 0)), V(1, 0, 0));
    EXPECT_MISS(scene, V(cyl_base + V(5, 1, 0)), V(1, 0, 0));
    EXPECT_MISS(scene, V(cyl_base + V(0, 4, 0)), V(0, 1, 0));
}

// Cylinder on an oblique axis: base (1,1,1), cap (2,3,3) = base + 3a with a = (1,2,2)/3, radius 0.5.
// u and w complete the orthonormal frame (w = a × u).
const V obl_base(1, 1, 1);
const V obl_cap(2, 3, 3);
const V obl_a(1.0 / 3, 2.0 / 3, 2.0 / 3);
const V obl_u(2.0 / 3, 1.0 / 3, -2.0 / 3);
const V obl_w(-2.0 / 3, 2.0 / 3, -1.0 / 3);

twinray::scene::Scene oblique_cylinder_scene() {
    return scene_with(test::cylinder({1, 1, 1}, {2, 3, 3}, 0.5));
}

TEST_P(IntersectionCylinder, ObliqueAxisSideHitsAreRadialInTheAxisFrame) {
    auto scene = oblique_cylinder_scene();
    EXPECT_HIT(scene, obl_base + 1.5 * obl_a + 5.0 * obl_u, -obl_u,
               {4.5, obl_base + 1.5 * obl_a + 0.5 * obl_u, obl_u, 1, true});
    // 0.3 off the axis along u, coming along −w: w² + 0.09 = 0.25 at w = 0.4, t = 3 − 0.4.
    EXPECT_HIT(scene, obl_base + obl_a + 3.0 * obl_w + 0.3 * obl_u, -obl_w,
               {2.6, obl_base + obl_a + 0.4 * obl_w + 0.3 * obl_u, 0.6 * obl_u + 0.8 * obl_w, 1, true});
}

TEST_P(IntersectionCylinder, ObliqueAxisCapsHaveNormalsAlongTheAxis) {
    auto scene = oblique_cylinder_scene();
    EXPECT_HIT(scene, obl_cap + 4.0 * obl_a + 0.2 * obl_u, -obl_a, {4, obl_cap + 0.2 * obl_u, obl_a, 1, true});
    EXPECT_HIT(scene, obl_base - 2.0 * obl_a + 0.1 * obl_w, obl_a, {2, obl_base + 0.1 * obl_w, -obl_a, 1, true});
}

// Towards q = cap + 0.1u along −(a − 0.5u)/|a − 0.5u| from 4 away: the line crosses the side's radius
// only 1.2 above the cap plane, so the cap bounds the solid and the hit is q at t = 4.
TEST_P(IntersectionCylinder, ObliqueAxisTiltedRayHitsTheCapAtTheDistanceWorkedOutByHand) {
    auto scene = oblique_cylinder_scene();
    V q = obl_cap + 0.1 * obl_u;
    V toward = -normalize(obl_a - 0.5 * obl_u);
    EXPECT_HIT(scene, q - 4.0 * toward, toward, {4, q, obl_a, 1, true});
}

TEST_P(IntersectionCylinder, ObliqueAxisRayFromInsideAlongTheAxisLeavesThroughTheCap) {
    auto scene = oblique_cylinder_scene();
    EXPECT_HIT(scene, obl_base + obl_a, obl_a, {2, obl_cap, -obl_a, 1, false});
}

// ---------------------------------------------------------------------------------------------------
// Box min (1,2,3), max (2,4,7): centre (1.5,3,5), half-sizes (0.5,1,2).

const V box_center(1.5, 3, 5);
const V box_half(0.5, 1, 2);

twinray::scene::Scene box_scene() {
    return scene_with(test::box({1, 2, 3}, {2, 4, 7}));
}

V unit_axis(int axis, double sign) {
    return V(axis == 0 ? sign : 0, axis == 1 ? sign : 0, axis == 2 ? sign : 0);
}

TEST_P(IntersectionBox, HitOnEachOfTheSixFacesReportsThatFacesNormal) {
    auto scene = box_scene();
    for (int axis = 0; axis < 3; ++axis) {
        for (double sign : {-1.0, 1.0}) {
            SCOPED_TRACE(testing::Message() << "face on axis " << axis << ", side " << sign);
            V face = unit_axis(axis, sign);
            // Off the face's centre in both other axes, well inside the face.
            V offset = 0.1 * unit_axis((axis + 1) % 3, 1) - 0.2 * unit_axis((axis + 2) % 3, 1);
            V origin = box_center + 10.0 * face + offset;
            V point = box_center + box_half[axis] * face + offset;
            EXPECT_HIT(scene, origin, -face, {10 - box_half[axis], point, face, 1, true});
        }
    }
}

// Aimed at q = (1.5, 4, 4) on the +y face from 3 away along (1,−2,0.5)/|…|.
TEST_P(IntersectionBox, ObliqueHitLandsOnTheAimedPointOfTheEntryFace) {
    auto scene = box_scene();
    V direction = normalize(V(1, -2, 0.5));
    EXPECT_HIT(scene, V(1.5, 4, 4) - 3.0 * direction, direction, {3, {1.5, 4, 4}, {0, 1, 0}, 1, true});
}

TEST_P(IntersectionBox, HitFromInsideLeavesThroughTheNearestExitFaceWithNormalFacingTheRay) {
    auto scene = box_scene();
    EXPECT_HIT(scene, box_center, V(0, 0, 1), {2, {1.5, 3, 7}, {0, 0, -1}, 1, false});
    // Along (1,0,1)/√2 the x = 2 face comes at t = 0.5√2, before z = 7.
    EXPECT_HIT(scene, box_center, V(1, 0, 1), {0.5 * std::sqrt(2.0), {2, 3, 5.5}, {-1, 0, 0}, 1, false});
}

TEST_P(IntersectionBox, RayParallelToAFaceOutsideTheBoxMisses) {
    auto scene = box_scene();
    EXPECT_MISS(scene, V(0, 3, 5), V(0, 1, 0));
    EXPECT_MISS(scene, V(0, 3, 5), V(0, 1, 1));
    EXPECT_MISS(scene, V(1.5, 3, 8), V(1, 0, 0));
    EXPECT_MISS(scene, V(1.5, 0, 5), V(0, 0, 1));
}

// Along (1,1,0)/√2 from (0,−0.5,5): inside the x slab for t/√2 in [1,2], the y slab in [2.5,4.5].
TEST_P(IntersectionBox, RayWhoseSlabIntervalsDoNotOverlapMisses) {
    auto scene = box_scene();
    EXPECT_MISS(scene, V(0, -0.5, 5), V(1, 1, 0));
}

TEST_P(IntersectionBox, BoxBehindTheRayOriginIsMissed) {
    auto scene = box_scene();
    EXPECT_MISS(scene, V(1.5, 3, 10), V(0, 0, 1));
    EXPECT_MISS(scene, V(3, 3, 5), V(1, 0.1, 0));
}

// ---------------------------------------------------------------------------------------------------
// Several objects: the nearest wins, whatever its place in the list, and reports its own leaf.

TEST_P(IntersectionScene, NearestOfSeveralPrimitivesIsReportedWithItsDocumentOrderLeaf) {
    test::SceneBuilder builder;
    builder
        .object(test::plane({0, 1, 0}, -10))               // leaf 0, y = −10
        .object(test::sphere({0, 0, -20}, 1))              // leaf 1
        .object(test::cylinder({5, -1, 0}, {5, 1, 0}, 1))  // leaf 2
        .object(test::box({-6, -1, -1}, {-4, 1, 1}));      // leaf 3
    auto scene = builder.build();
    EXPECT_HIT(scene, V(0, 0, 0), V(0, 0, -1), {19, {0, 0, -19}, {0, 0, 1}, 1, true});
    EXPECT_HIT(scene, V(0, 0, 0), V(1, 0, 0), {4, {4, 0, 0}, {-1, 0, 0}, 2, true});
    EXPECT_HIT(scene, V(0, 0, 0), V(-1, 0, 0), {4, {-4, 0, 0}, {1, 0, 0}, 3, true});
    EXPECT_HIT(scene, V(0, 0, 0), V(0, -1, 0), {10, {0, -10, 0}, {0, 1, 0}, 0, true});
    // The plane lies beyond the sphere along this ray: the sphere, later in the list, is reported.
    EXPECT_HIT(scene, V(0, 9, -20), V(0, -1, 0), {8, {0, 1, -20}, {0, 1, 0}, 1, true});
}

}  // namespace
