// First hits on primitives placed by transforms no primitive of their kind expresses (an ellipsoid, a sheared
// cylinder, a scaled and turned box): the normal goes through the inverse transpose and comes out of unit length,
// and t is the world's. Each primitive comes after a decoy (after_a_decoy): it is leaf 1.
#include "plugin/hand_solved_cases.h"
#include "scene/placement.h"
#include "scene/scene_builder.h"

#include <cmath>

namespace twinray::plugin::hand_solved {

namespace build = scene::builder;

void add_transformed_cases(std::vector<HandSolvedCase>& cases) {
    Suite suite(cases, "IntersectionTransformed");

    // The unit sphere scaled by (2, 1, 1): x²/4 + y² + z² = 1, placed as an ellipsoid, not a sphere (the tests check
    // its kind).
    const scene::Scene ellipsoid = after_a_decoy(build::placed(build::sphere({0, 0, 0}, 1), scene::scaling({2, 1, 1})));
    suite.add("EllipsoidHitHeadOnAlongItsLongAxisIsAtItsTip", ellipsoid,
              {hit({5, 0, 0}, {-1, 0, 0}, {3, {2, 0, 0}, {1, 0, 0}, 1, true})});
    // At x = √2 the ellipsoid has y = √(1 − x²/4) = √½, and its gradient (x/4, y, 0) ∝ (1, 2, 0): the normal through
    // the inverse transpose, L⁻ᵀ·(p/|p|) in object space. Through L it would be ∝ (2, 1, 0)·… instead.
    const double x = std::sqrt(2.0), y = std::sqrt(0.5);
    suite.add("EllipsoidNormalIsTheGradientThroughTheInverseTranspose", ellipsoid,
              {hit({x, 5, 0}, {0, -1, 0}, {5 - y, {x, y, 0}, V(1, 2, 0) / std::sqrt(5.0), 1, true})});
    suite.add("EllipsoidHitFromItsCentreLeavesAtTheSemiAxis", ellipsoid,
              {hit({0, 0, 0}, {-1, 0, 0}, {2, {-2, 0, 0}, {1, 0, 0}, 1, false})});

    // The cylinder of radius 1 along y from 0 to 1, sheared by x += y/2: its side is no longer upright. At height ½
    // the side's object point (1, ½, 0) sits at x = 1.25, and its normal L⁻ᵀ·(1, 0, 0) = (1, −½, 0) ∝ (2, −1, 0); the
    // caps stay flat, y = 1 with normal (0, 1, 0).
    const scene::Matrix3 shear{{{1, 0.5, 0}, {0, 1, 0}, {0, 0, 1}}};
    const scene::Scene sheared =
        after_a_decoy(build::placed(build::cylinder({0, 0, 0}, {0, 1, 0}, 1), scene::affine(shear, {0, 0, 0})));
    suite.add("ShearedCylinderSideNormalLeansAgainstTheShear", sheared,
              {hit({5, 0.5, 0}, {-1, 0, 0}, {3.75, {1.25, 0.5, 0}, V(2, -1, 0) / std::sqrt(5.0), 1, true})});
    suite.add("ShearedCylinderCapStaysFlat", sheared,
              {hit({0.75, 5, 0.25}, {0, -1, 0}, {4, {0.75, 1, 0.25}, {0, 1, 0}, 1, true})});

    // The cube [−1, 1]³ stretched to x ∈ [−2, 2] and turned 45° about z: its +x face lies 2 from the centre along
    // (1, 1, 0)/√2. From (5, 5, 0) along −(1, 1, 0)/√2 the ray meets it at t = 5√2 − 2, at (√2, √2, 0). Its normal
    // through L⁻ᵀ is (½, 0, 0) turned: of unit length only once made so again.
    const scene::Transform stretched_turned = math::composed(scene::rotation({0, 0, 1}, 45), scene::scaling({2, 1, 1}));
    const scene::Scene box = after_a_decoy(build::placed(build::box({-1, -1, -1}, {1, 1, 1}), stretched_turned));
    const double r = std::sqrt(2.0);
    suite.add("StretchedTurnedBoxFaceIsHitWithAUnitNormal", box,
              {hit({5, 5, 0}, {-1, -1, 0}, {5 * r - 2, {r, r, 0}, V(1, 1, 0) / r, 1, true})});
    // The same box's −y face, 1 from the centre along (1, −1, 0)/√2: from inside, the ray along it leaves there.
    const double h = std::sqrt(0.5);
    suite.add("StretchedTurnedBoxIsLeftThroughItsNarrowFaceFromInside", box,
              {hit({0, 0, 0}, {1, -1, 0}, {1, {h, -h, 0}, V(-1, 1, 0) * h, 1, false})});

    // The unit sphere squashed to half its height: a ray at height 0.75 would have met the sphere, and passes the
    // ellipsoid.
    suite.add("RayPastTheEllipsoidsSideMissesItWhereTheSphereWouldHaveBeenMet",
              after_a_decoy(build::placed(build::sphere({0, 0, 0}, 1), scene::scaling({1, 0.5, 1}))),
              {miss({0, 0.75, 5}, {0, 0, -1})});
}

}  // namespace twinray::plugin::hand_solved
