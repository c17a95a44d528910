// Hand-solved first hits on primitives placed by transforms no primitive of their kind expresses (an ellipsoid, a
// sheared cylinder, a scaled and turned box), against every tracer: the normal goes through the inverse
// transpose and comes out of unit length, and t is the world's.
#include "scene/placement.h"
#include "tests/hit_expectations.h"

#include <cmath>
#include <variant>

namespace twinray {
namespace {

using test::Expected;
using test::V;

TWINRAY_HIT_EXPECTATION_SUITE(IntersectionTransformed);

// A far-away decoy first, so the primitive under test is leaf 1 (as in hit_intersection_test.cpp).
scene::Scene scene_with(scene::Object object) {
    test::SceneBuilder builder;
    builder.object(test::sphere({-1000, 1000, 1000}, 1));
    builder.object(std::move(object));
    return builder.build();
}

// The unit sphere scaled by (2, 1, 1): x²/4 + y² + z² = 1. Placed as an ellipsoid, not a sphere.
scene::Object ellipsoid() {
    scene::Object object = test::placed(test::sphere({0, 0, 0}, 1), scene::scaling({2, 1, 1}));
    EXPECT_TRUE(std::holds_alternative<scene::Transformed<scene::Sphere>>(object.shape));
    return object;
}

TEST_P(IntersectionTransformed, EllipsoidHitHeadOnAlongItsLongAxisIsAtItsTip) {
    EXPECT_HIT(scene_with(ellipsoid()), V(5, 0, 0), V(-1, 0, 0), {3, {2, 0, 0}, {1, 0, 0}, 1, true});
}

// At x = √2 the ellipsoid has y = √(1 − x²/4) = √½, and its gradient (x/4, y, 0) ∝ (1, 2, 0): the normal
// through the inverse transpose, L⁻ᵀ·(p/|p|) in object space. Through L it would be ∝ (2, 1, 0)·… instead.
TEST_P(IntersectionTransformed, EllipsoidNormalIsTheGradientThroughTheInverseTranspose) {
    double x = std::sqrt(2.0), y = std::sqrt(0.5);
    EXPECT_HIT(scene_with(ellipsoid()), V(x, 5, 0), V(0, -1, 0),
               {5 - y, {x, y, 0}, V(1, 2, 0) / std::sqrt(5.0), 1, true});
}

TEST_P(IntersectionTransformed, EllipsoidHitFromItsCentreLeavesAtTheSemiAxis) {
    EXPECT_HIT(scene_with(ellipsoid()), V(0, 0, 0), V(-1, 0, 0), {2, {-2, 0, 0}, {1, 0, 0}, 1, false});
}

// The cylinder of radius 1 along y from 0 to 1, sheared by x += y/2: its side is no longer upright. At height
// ½ the side's object point (1, ½, 0) sits at x = 1.25, and its normal L⁻ᵀ·(1, 0, 0) = (1, −½, 0) ∝ (2, −1, 0);
// the caps stay flat, y = 1 with normal (0, 1, 0).
scene::Object sheared_cylinder() {
    scene::Matrix3 shear{{{1, 0.5, 0}, {0, 1, 0}, {0, 0, 1}}};
    return test::placed(test::cylinder({0, 0, 0}, {0, 1, 0}, 1), scene::affine(shear, {0, 0, 0}));
}

TEST_P(IntersectionTransformed, ShearedCylinderSideNormalLeansAgainstTheShear) {
    EXPECT_HIT(scene_with(sheared_cylinder()), V(5, 0.5, 0), V(-1, 0, 0),
               {3.75, {1.25, 0.5, 0}, V(2, -1, 0) / std::sqrt(5.0), 1, true});
}

TEST_P(IntersectionTransformed, ShearedCylinderCapStaysFlat) {
    EXPECT_HIT(scene_with(sheared_cylinder()), V(0.75, 5, 0.25), V(0, -1, 0), {4, {0.75, 1, 0.25}, {0, 1, 0}, 1, true});
}

// The cube [−1, 1]³ stretched to x ∈ [−2, 2] and turned 45° about z: its +x face lies 2 from the centre along
// (1, 1, 0)/√2. From (5, 5, 0) along −(1, 1, 0)/√2 the ray meets it at t = 5√2 − 2, at (√2, √2, 0). Its normal
// through L⁻ᵀ is (½, 0, 0) turned: of unit length only once made so again.
scene::Object stretched_turned_box() {
    scene::Transform to_world = math::composed(scene::rotation({0, 0, 1}, 45), scene::scaling({2, 1, 1}));
    return test::placed(test::box({-1, -1, -1}, {1, 1, 1}), to_world);
}

TEST_P(IntersectionTransformed, StretchedTurnedBoxFaceIsHitWithAUnitNormal) {
    double r = std::sqrt(2.0);
    EXPECT_HIT(scene_with(stretched_turned_box()), V(5, 5, 0), V(-1, -1, 0),
               {5 * r - 2, {r, r, 0}, V(1, 1, 0) / r, 1, true});
}

// The same box's −y face, 1 from the centre along (1, −1, 0)/√2: from inside, the ray along it leaves there.
TEST_P(IntersectionTransformed, StretchedTurnedBoxIsLeftThroughItsNarrowFaceFromInside) {
    double h = std::sqrt(0.5);
    EXPECT_HIT(scene_with(stretched_turned_box()), V(0, 0, 0), V(1, -1, 0), {1, {h, -h, 0}, V(-1, 1, 0) * h, 1, false});
}

TEST_P(IntersectionTransformed, RayPastTheEllipsoidsSideMissesItWhereTheSphereWouldHaveBeenMet) {
    EXPECT_MISS(scene_with(test::placed(test::sphere({0, 0, 0}, 1), scene::scaling({1, 0.5, 1}))), V(0, 0.75, 5),
                V(0, 0, -1));
}

}  // namespace
}  // namespace twinray
