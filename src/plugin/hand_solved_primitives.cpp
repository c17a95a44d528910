// Each primitive's first hit, with every expectation (t, hit point, normal, leaf, entering) worked out by hand from
// the primitive's geometry. The primitive under test comes after a decoy (after_a_decoy): it is leaf 1.
#include "plugin/hand_solved_cases.h"
#include "scene/scene_builder.h"

#include <cmath>

namespace twinray::plugin::hand_solved {
namespace {

namespace build = scene::builder;

// A plane: the surface n·p = d, solid on the side n·p < d.
void add_plane_cases(std::vector<HandSolvedCase>& cases) {
    Suite suite(cases, "IntersectionPlane");
    const scene::Scene level = after_a_decoy(build::plane({0, 1, 0}, 1));
    suite.add("HitFromTheOutsideEntersWithTheOutwardNormal", level,
              {hit({0.5, 5, -2}, {0, -1, 0}, {4, {0.5, 1, -2}, {0, 1, 0}, 1, true})});
    suite.add("HitFromTheSolidSideLeavesWithNormalFacingTheRay", level,
              {hit({0.5, -2, -2}, {0, 1, 0}, {3, {0.5, 1, -2}, {0, -1, 0}, 1, false})});

    const scene::Scene tilted = after_a_decoy(build::plane({1, 2, 2}, 3));
    const V n(1.0 / 3, 2.0 / 3, 2.0 / 3);
    // n = (1,2,2)/3, d = 3. From o = (4,4,4) (n·o = 20/3) along (−1,−2,0)/√5 (n·dir = −5/(3√5)):
    // t = (3 − 20/3)/(−5/(3√5)) = 11√5/5, landing on (4,4,4) + 11/5·(−1,−2,0) = (1.8, −0.4, 4), n·p = 3.
    suite.add("ObliqueHitFromTheOutsideIsAtTheDistanceSolvedByHand", tilted,
              {hit({4, 4, 4}, {-1, -2, 0}, {11 * std::sqrt(5.0) / 5, {1.8, -0.4, 4}, n, 1, true})});
    // The same plane from its solid side: o = (−1,−1,0) (n·o = −1) along (1,1,1)/√3:
    // t = (3 + 1)/(5/(3√3)) = 12√3/5, landing on (−1,−1,0) + 12/5·(1,1,1) = (1.4, 1.4, 2.4).
    suite.add("ObliqueHitFromTheSolidSideLeavesWithTheNormalTurnedToTheRay", tilted,
              {hit({-1, -1, 0}, {1, 1, 1}, {12 * std::sqrt(3.0) / 5, {1.4, 1.4, 2.4}, -n, 1, false})});

    suite.add("RayParallelToThePlaneMissesOnEitherSide", level,
              {miss({0, 5, 0}, {1, 0, 0}), miss({0, -5, 0}, {1, 0, 1})});
    suite.add("RayHeadingAwayFromThePlaneMissesOnEitherSide", level,
              {miss({0, 5, 0}, {0.3, 1, 0}), miss({0, -5, 0}, {0, -1, 0.3})});
}

// A sphere. A ray along unit d passing the centre c at perpendicular offset h·e (e ⟂ d, unit), starting s before the
// point of closest approach, meets the sphere at t = s ∓ √(r² − h²).
void add_sphere_cases(std::vector<HandSolvedCase>& cases) {
    Suite suite(cases, "IntersectionSphere");
    const V center(1, -2, 0.5);
    const double radius = 1.5;
    const V along(2.0 / 3, -1.0 / 3, 2.0 / 3);   // unit
    const V across(2.0 / 3, 2.0 / 3, -1.0 / 3);  // unit, ⟂ along
    const scene::Scene ball = after_a_decoy(build::sphere(center, radius));

    suite.add("HeadOnHitIsAtTheNearSurfaceWithTheRadialNormal", ball,
              {hit({1, -2, 10.5}, {0, 0, -1}, {8.5, {1, -2, 2}, {0, 0, 1}, 1, true})});
    // h = 0.9, s = 6: t = 6 − √(2.25 − 0.81) = 4.8, at c + 0.9e − 1.2d with normal (0.9e − 1.2d)/1.5, so the ray
    // meets the surface at the angle acos(0.8) from the normal.
    const V oblique_normal = 0.6 * across - 0.8 * along;
    suite.add("ObliqueHitIsAtTheChordEntryAtTheAngleWorkedOutByHand", ball,
              {hit(center - 6.0 * along + 0.9 * across, along,
                   {4.8, center + 1.5 * oblique_normal, oblique_normal, 1, true})});
    // From c + 0.5e along d the ray leaves at t = √(r² − 0.25) = √2 through c + 0.5e + √2·d, where the outward
    // normal (0.5e + √2d)/1.5 points along the ray: the reported normal is its opposite.
    const V outward = (0.5 * across + std::sqrt(2.0) * along) / 1.5;
    suite.add("HitFromInsideReportsLeavingWithNormalFacingTheRay", ball,
              {hit(center + 0.5 * across, along, {std::sqrt(2.0), center + 1.5 * outward, -outward, 1, false})});
    suite.add("HitFromTheCentreLeavesAtTheRadius", ball,
              {hit(center, -across, {1.5, center - 1.5 * across, across, 1, false})});
    suite.add("SphereBehindTheRayOriginIsMissed", ball, {miss(center + 5.0 * along + 0.3 * across, along)});
    suite.add("RayPassingFartherThanTheRadiusMisses", ball, {miss(center - 6.0 * along + 1.6 * across, along)});
}

// A cylinder, axis-aligned: base (1,−1,2), cap (1,1,2), radius 1. Points are written base + (x, y, z).
void add_upright_cylinder_cases(Suite& suite) {
    const V base(1, -1, 2);
    const scene::Scene upright = after_a_decoy(build::cylinder({1, -1, 2}, {1, 1, 2}, 1));

    // At height 0 the ray along +x, 0.6 off the axis in z, meets x² + 0.36 = 1 at x = −0.8.
    suite.add("SideHitPerpendicularToTheAxisHasTheRadialNormal", upright,
              {hit(base + V(-6, 1, 0.6), {1, 0, 0}, {5.2, base + V(-0.8, 1, 0.6), {-0.8, 0, 0.6}, 1, true})});
    // Along (1,−1,0)/√2 from (−3,3,0): the side x = −1 at t = 2√2, at height 1 — below the cap (height 2), although
    // the ray started above it.
    suite.add("ObliqueRayFromAboveTheCapHitsTheSideBelowTheRim", upright,
              {hit(base + V(-3, 3, 0), {1, -1, 0}, {2 * std::sqrt(2.0), base + V(-1, 1, 0), {-1, 0, 0}, 1, true})});
    // Along (1,−1,0)/√2 from (−1.5,3.5,0): the cap plane y = 2 at t = 1.5√2, at x = 0 inside the rim.
    suite.add("ObliqueRayHitsTheCapInsideTheRim", upright,
              {hit(base + V(-1.5, 3.5, 0), {1, -1, 0}, {1.5 * std::sqrt(2.0), base + V(0, 2, 0), {0, 1, 0}, 1, true})});
    suite.add("RaysParallelToTheAxisHitEitherCapWithTheAxialNormal", upright,
              {hit(base + V(0.3, 5, 0.2), {0, -1, 0}, {3, base + V(0.3, 2, 0.2), {0, 1, 0}, 1, true}),
               hit(base + V(0.3, -5, 0.2), {0, 1, 0}, {5, base + V(0.3, 0, 0.2), {0, -1, 0}, 1, true})});
    suite.add("RayAlongTheAxisEntersThroughTheBaseCap", upright,
              {hit(base + V(0, -3, 0), {0, 1, 0}, {3, base, {0, -1, 0}, 1, true}),
               hit(base + V(0, 7, 0), {0, -1, 0}, {5, base + V(0, 2, 0), {0, 1, 0}, 1, true})});
    suite.add("RayAlongTheAxisFromInsideLeavesThroughTheCapAheadWithNormalFacingTheRay", upright,
              {hit(base + V(0, 0.5, 0), {0, 1, 0}, {1.5, base + V(0, 2, 0), {0, -1, 0}, 1, false}),
               hit(base + V(0, 0.5, 0), {0, -1, 0}, {0.5, base, {0, 1, 0}, 1, false})});
    // From the axis at height 1 along (1,0,1)/√2: the side at radial distance 1, t = 1.
    const double h = 1 / std::sqrt(2.0);
    suite.add("SideHitFromInsideLeavesWithNormalFacingTheRay", upright,
              {hit(base + V(0, 1, 0), {1, 0, 1}, {1, base + V(h, 1, h), {-h, 0, -h}, 1, false})});
    suite.add("RayParallelToTheAxisOutsideTheRadiusMisses", upright,
              {miss(base + V(1.5, -3, 0), {0, 1, 0}), miss(base + V(0.8, -3, 0.8), {0, 1, 0})});
    suite.add("RayPassingAboveTheCapOrBehindTheOriginMisses", upright,
              {miss(base + V(-5, 2.5, 0), {1, 0, 0}), miss(base + V(5, 1, 0), {1, 0, 0}),
               miss(base + V(0, 4, 0), {0, 1, 0})});
}

// A cylinder on an oblique axis: base (1,1,1), cap (2,3,3) = base + 3a with a = (1,2,2)/3, radius 0.5. u and w
// complete the orthonormal frame (w = a × u).
void add_oblique_cylinder_cases(Suite& suite) {
    const V base(1, 1, 1);
    const V cap(2, 3, 3);
    const V a(1.0 / 3, 2.0 / 3, 2.0 / 3);
    const V u(2.0 / 3, 1.0 / 3, -2.0 / 3);
    const V w(-2.0 / 3, 2.0 / 3, -1.0 / 3);
    const scene::Scene oblique = after_a_decoy(build::cylinder({1, 1, 1}, {2, 3, 3}, 0.5));

    suite.add("ObliqueAxisSideHitsAreRadialInTheAxisFrame", oblique,
              {hit(base + 1.5 * a + 5.0 * u, -u, {4.5, base + 1.5 * a + 0.5 * u, u, 1, true}),
               // 0.3 off the axis along u, coming along −w: w² + 0.09 = 0.25 at w = 0.4, t = 3 − 0.4.
               hit(base + a + 3.0 * w + 0.3 * u, -w, {2.6, base + a + 0.4 * w + 0.3 * u, 0.6 * u + 0.8 * w, 1, true})});
    suite.add("ObliqueAxisCapsHaveNormalsAlongTheAxis", oblique,
              {hit(cap + 4.0 * a + 0.2 * u, -a, {4, cap + 0.2 * u, a, 1, true}),
               hit(base - 2.0 * a + 0.1 * w, a, {2, base + 0.1 * w, -a, 1, true})});
    // Towards q = cap + 0.1u along −(a − 0.5u)/|a − 0.5u| from 4 away: the line crosses the side's radius only 1.2
    // above the cap plane, so the cap bounds the solid and the hit is q at t = 4.
    const V q = cap + 0.1 * u;
    const V toward = -math::normalize(a - 0.5 * u);
    suite.add("ObliqueAxisTiltedRayHitsTheCapAtTheDistanceWorkedOutByHand", oblique,
              {hit(q - 4.0 * toward, toward, {4, q, a, 1, true})});
    suite.add("ObliqueAxisRayFromInsideAlongTheAxisLeavesThroughTheCap", oblique,
              {hit(base + a, a, {2, cap, -a, 1, false})});
}

V unit_axis(int axis, double sign) {
    return V(axis == 0 ? sign : 0, axis == 1 ? sign : 0, axis == 2 ? sign : 0);
}

// A box, min (1,2,3), max (2,4,7): centre (1.5,3,5), half-sizes (0.5,1,2).
void add_box_cases(std::vector<HandSolvedCase>& cases) {
    Suite suite(cases, "IntersectionBox");
    const V center(1.5, 3, 5);
    const V half(0.5, 1, 2);
    const scene::Scene box = after_a_decoy(build::box({1, 2, 3}, {2, 4, 7}));

    // Straight at each face from 10 beyond the centre, off the face's centre in both other axes (well inside the
    // face): the face is half a size from the centre, so t = 10 − half, on the face's outward normal.
    std::vector<HandSolvedRay> faces;
    for (int axis = 0; axis < 3; ++axis) {
        for (double sign : {-1.0, 1.0}) {
            const V face = unit_axis(axis, sign);
            const V offset = 0.1 * unit_axis((axis + 1) % 3, 1) - 0.2 * unit_axis((axis + 2) % 3, 1);
            faces.push_back(hit(center + 10.0 * face + offset, -face,
                                {10 - half[axis], center + half[axis] * face + offset, face, 1, true}));
        }
    }
    suite.add("HitOnEachOfTheSixFacesReportsThatFacesNormal", box, faces);
    // Aimed at q = (1.5, 4, 4) on the +y face from 3 away along (1,−2,0.5)/|…|.
    const V direction = math::normalize(V(1, -2, 0.5));
    suite.add("ObliqueHitLandsOnTheAimedPointOfTheEntryFace", box,
              {hit(V(1.5, 4, 4) - 3.0 * direction, direction, {3, {1.5, 4, 4}, {0, 1, 0}, 1, true})});
    suite.add("HitFromInsideLeavesThroughTheNearestExitFaceWithNormalFacingTheRay", box,
              {hit(center, {0, 0, 1}, {2, {1.5, 3, 7}, {0, 0, -1}, 1, false}),
               // Along (1,0,1)/√2 the x = 2 face comes at t = 0.5√2, before z = 7.
               hit(center, {1, 0, 1}, {0.5 * std::sqrt(2.0), {2, 3, 5.5}, {-1, 0, 0}, 1, false})});
    suite.add("RayParallelToAFaceOutsideTheBoxMisses", box,
              {miss({0, 3, 5}, {0, 1, 0}), miss({0, 3, 5}, {0, 1, 1}), miss({1.5, 3, 8}, {1, 0, 0}),
               miss({1.5, 0, 5}, {0, 0, 1})});
    // Along (1,1,0)/√2 from (0,−0.5,5): inside the x slab for t/√2 in [1,2], the y slab in [2.5,4.5].
    suite.add("RayWhoseSlabIntervalsDoNotOverlapMisses", box, {miss({0, -0.5, 5}, {1, 1, 0})});
    suite.add("BoxBehindTheRayOriginIsMissed", box, {miss({1.5, 3, 10}, {0, 0, 1}), miss({3, 3, 5}, {1, 0.1, 0})});
}

// Several objects: the nearest wins, whatever its place in the list, and reports its own leaf.
void add_scene_cases(std::vector<HandSolvedCase>& cases) {
    Suite suite(cases, "IntersectionScene");
    build::SceneBuilder builder;
    builder
        .object(build::plane({0, 1, 0}, -10))               // leaf 0, y = −10
        .object(build::sphere({0, 0, -20}, 1))              // leaf 1
        .object(build::cylinder({5, -1, 0}, {5, 1, 0}, 1))  // leaf 2
        .object(build::box({-6, -1, -1}, {-4, 1, 1}));      // leaf 3
    suite.add("NearestOfSeveralPrimitivesIsReportedWithItsDocumentOrderLeaf", builder.build(),
              {hit({0, 0, 0}, {0, 0, -1}, {19, {0, 0, -19}, {0, 0, 1}, 1, true}),
               hit({0, 0, 0}, {1, 0, 0}, {4, {4, 0, 0}, {-1, 0, 0}, 2, true}),
               hit({0, 0, 0}, {-1, 0, 0}, {4, {-4, 0, 0}, {1, 0, 0}, 3, true}),
               hit({0, 0, 0}, {0, -1, 0}, {10, {0, -10, 0}, {0, 1, 0}, 0, true}),
               // The plane lies beyond the sphere along this ray: the sphere, later in the list, is reported.
               hit({0, 9, -20}, {0, -1, 0}, {8, {0, 1, -20}, {0, 1, 0}, 1, true})});
}

}  // namespace

void add_primitive_cases(std::vector<HandSolvedCase>& cases) {
    add_plane_cases(cases);
    add_sphere_cases(cases);
    Suite cylinders(cases, "IntersectionCylinder");
    add_upright_cylinder_cases(cylinders);
    add_oblique_cylinder_cases(cylinders);
    add_box_cases(cases);
    add_scene_cases(cases);
}

}  // namespace twinray::plugin::hand_solved
