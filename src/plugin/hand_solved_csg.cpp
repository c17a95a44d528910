// CSG: the first hit through union, intersection and difference (nested, from outside and inside, with a half-space)
// and the tie rule, worked out by hand from the operands' geometry.
#include "plugin/hand_solved_cases.h"
#include "scene/scene_builder.h"

#include <cmath>
#include <utility>

namespace twinray::plugin::hand_solved {
namespace {

namespace build = scene::builder;
using scene::CsgOp;

scene::Scene scene_of(scene::Object object) {
    build::SceneBuilder builder;
    builder.object(std::move(object));
    return builder.build();
}

// The cube [−2,2]³.
scene::Object cube() {
    return build::box({-2, -2, -2}, {2, 2, 2});
}

void add_difference_cases(std::vector<HandSolvedCase>& cases) {
    Suite suite(cases, "CsgDifference");
    // The cube (leaf 0) minus the unit sphere at (0,0,2) (leaf 1), a dent in the top (+z) face whose surface faces
    // into the cavity.
    const scene::Scene dented = scene_of(build::csg(CsgOp::difference, {cube(), build::sphere({0, 0, 2}, 1)}));
    suite.add("RayIntoTheCavityHitsTheSubtractedSphereWithNormalFacingIntoTheCavity", dented,
              {hit({0, 0, 10}, {0, 0, -1}, {9, {0, 0, 1}, {0, 0, 1}, 1, true})});
    suite.add("RayBesideTheCavityHitsTheMinuendsFace", dented,
              {hit({1.5, 0, 10}, {0, 0, -1}, {8, {1.5, 0, 2}, {0, 0, 1}, 0, true})});
    // From (0,0,5) along (0.2,0,−1)/√1.04 the line enters the sphere above the cube (z ≈ 2.9), crosses the cube's top
    // inside the dent, and meets material where it leaves the sphere: the far root of t² + 2bt + c = 0 with
    // f = (0,0,3), b = f·d, c = |f|² − 1 = 8. The normal there points to the centre. (Its z, about 1.32, is inside
    // the cube: tests/hit_expectations_test.cpp checks it.)
    const V origin(0, 0, 5);
    const V d = math::normalize(V(0.2, 0, -1));
    const double b = math::dot(V(0, 0, 3), d);
    const double t = -b + std::sqrt(b * b - 8);
    const V far_wall = origin + t * d;
    suite.add("ObliqueRayThroughTheCavityMouthHitsTheFarWallOfTheCavity", dented,
              {hit(origin, d, {t, far_wall, V(0, 0, 2) - far_wall, 1, true})});
    suite.add("RayStartingInTheSolidLeavesIntoTheCavityThroughTheSphere", dented,
              {hit({0, 0, -1}, {0, 0, 1}, {2, {0, 0, 1}, {0, 0, -1}, 1, false})});
    suite.add("RayStartingInTheCavityEntersTheSolidThroughTheSphere", dented,
              {hit({0, 0, 1.5}, {0, 0, -1}, {0.5, {0, 0, 1}, {0, 0, 1}, 1, true})});
    // The part of the cube's top face over the dent was removed: a ray out of the dent meets nothing.
    suite.add("RayLeavingTheCavityThroughItsMouthMisses", dented,
              {miss({0, 0, 1.5}, {0, 0, 1}), miss({0, 0, 1.5}, {0.3, 0.2, 1})});

    // The cube minus two spheres, one denting the top, one the bottom: difference is the first child minus all the
    // others.
    suite.add(
        "DifferenceOfThreeChildrenRemovesEverySubtrahend",
        scene_of(build::csg(CsgOp::difference, {cube(), build::sphere({0, 0, 2}, 1), build::sphere({0, 0, -2}, 1)})),
        {hit({0, 0, 10}, {0, 0, -1}, {9, {0, 0, 1}, {0, 0, 1}, 1, true}),
         hit({0, 0, -10}, {0, 0, 1}, {9, {0, 0, -1}, {0, 0, -1}, 2, true}),
         hit({0, 0, 0}, {0, 0, 1}, {1, {0, 0, 1}, {0, 0, -1}, 1, false}),
         hit({0, 0, 0}, {0, 0, -1}, {1, {0, 0, -1}, {0, 0, 1}, 2, false})});

    // Cube [−1,1]³ (leaf 0) minus the half-space y < 0 (leaf 1): the upper half is left, and the cut face y = 0
    // faces down, out of the remaining solid.
    const scene::Scene cut =
        scene_of(build::csg(CsgOp::difference, {build::box({-1, -1, -1}, {1, 1, 1}), build::plane({0, 1, 0}, 0)}));
    suite.add("HalfSpaceCutFaceIsHitFromTheRemovedSideWithTheFlippedPlaneNormal", cut,
              {hit({0.2, -5, 0.3}, {0, 1, 0}, {5, {0.2, 0, 0.3}, {0, -1, 0}, 1, true}),
               // Oblique: from (−0.5,−3,0.5) along (1,3,0)/√10 the line reaches y = 0 at (0.5,0,0.5), t = √10,
               // having crossed the cube's bottom face (y = −1) inside the removed half.
               hit({-0.5, -3, 0.5}, {1, 3, 0}, {std::sqrt(10.0), {0.5, 0, 0.5}, {0, -1, 0}, 1, true})});
    suite.add("HalfSpaceCutKeepsTheMinuendsFacesOnTheOtherSide", cut,
              {hit({0, 5, 0}, {0, -1, 0}, {4, {0, 1, 0}, {0, 1, 0}, 0, true}),
               hit({0.5, 0.5, 5}, {0, 0, -1}, {4, {0.5, 0.5, 1}, {0, 0, 1}, 0, true}), miss({0, -0.5, 5}, {0, 0, -1})});
    suite.add("RayStartingInsideAHalfSpaceCutSolidLeavesThroughTheCutFace", cut,
              {hit({0, 0.5, 0}, {0, -1, 0}, {0.5, {0, 0, 0}, {0, 1, 0}, 1, false})});
    // From the removed lower half of the cube: upwards the cut face is entered; downwards the cube's bottom face lies
    // in the removed half and is no surface of the solid.
    suite.add("RayStartingInTheRemovedHalfSeesOnlyTheCutFace", cut,
              {hit({0, -0.5, 0}, {0, 1, 0}, {0.5, {0, 0, 0}, {0, -1, 0}, 1, true}), miss({0, -0.5, 0}, {0, -1, 0})});

    // The cube [−1,1]³ minus the box [0,1]×[−2,2]² shares the face x = 1 with it: the two faces cancel (no
    // zero-thickness skin is left), and the first surface is the subtrahend's face x = 0.
    suite.add("SubtrahendSharingAFaceLeavesNoSkinOnThatFace",
              scene_of(build::csg(CsgOp::difference,
                                  {build::box({-1, -1, -1}, {1, 1, 1}), build::box({0, -2, -2}, {1, 2, 2})})),
              {hit({5, 0.2, 0.3}, {-1, 0, 0}, {5, {0, 0.2, 0.3}, {1, 0, 0}, 1, true})});
}

// Two unit spheres at (∓0.5,0,0), leaves 0 and 1 of the operation.
scene::Scene two_balls(CsgOp op) {
    return scene_of(build::csg(op, {build::sphere({-0.5, 0, 0}, 1), build::sphere({0.5, 0, 0}, 1)}));
}

void add_intersection_cases(std::vector<HandSolvedCase>& cases) {
    Suite suite(cases, "CsgIntersection");
    // The two balls intersected make a lens spanning x in [−0.5,0.5] on the x axis; its −x face is sphere 1's
    // surface, its +x face sphere 0's.
    const scene::Scene lens = two_balls(CsgOp::intersection);
    suite.add("LensIsEnteredThroughTheSphereEnteredLast", lens,
              {hit({-5, 0, 0}, {1, 0, 0}, {4.5, {-0.5, 0, 0}, {-1, 0, 0}, 1, true}),
               hit({5, 0, 0}, {-1, 0, 0}, {4.5, {0.5, 0, 0}, {1, 0, 0}, 0, true})});
    // At height 0.95 the spheres' chords are x in [−0.812,−0.188] and [0.188,0.812]: disjoint.
    suite.add("RaysThroughOnlyOneOperandMiss", lens,
              {miss({-5, 0.95, 0}, {1, 0, 0}), miss({-1.2, 0, 5}, {0, 0, -1}), miss({1.2, 0, 5}, {0, 0, -1})});
    suite.add("RayStartingInsideTheLensLeavesThroughTheSphereLeftFirst", lens,
              {hit({0, 0, 0}, {1, 0, 0}, {0.5, {0.5, 0, 0}, {-1, 0, 0}, 0, false}),
               hit({0, 0, 0}, {-1, 0, 0}, {0.5, {-0.5, 0, 0}, {1, 0, 0}, 1, false})});
    // Along −z at x = 0 both spheres are entered at exactly the same t (the same arithmetic, mirrored): z = √0.75 on
    // the lens's rim. The tie goes to the earlier primitive, sphere 0, whose normal there is (0.5, 0, √0.75) —
    // sphere 1's would be (−0.5, 0, √0.75).
    const double z = std::sqrt(0.75);
    suite.add("LensRimWhereBothSpheresMeetAtTheSameTReportsTheEarlierSphere", lens,
              {hit({0, 0, 5}, {0, 0, -1}, {5 - z, {0, 0, z}, {0.5, 0, z}, 0, true})});

    // The cube [−1,1]³ and the box [−2,1]×[−2,2]² share the face x = 1, through which the ray enters both at t = 4:
    // the earlier child is reported, whichever of the two it is.
    const scene::Object smaller = build::box({-1, -1, -1}, {1, 1, 1});
    const scene::Object larger = build::box({-2, -2, -2}, {1, 2, 2});
    const HandSolvedRay onto_the_shared_face = hit({5, 0.1, 0.2}, {-1, 0, 0}, {4, {1, 0.1, 0.2}, {1, 0, 0}, 0, true});
    suite.add("CoincidentEntryFacesReportTheEarlierChildWhenTheSmallerBoxComesFirst",
              scene_of(build::csg(CsgOp::intersection, {smaller, larger})), {onto_the_shared_face});
    suite.add("CoincidentEntryFacesReportTheEarlierChildWhenTheLargerBoxComesFirst",
              scene_of(build::csg(CsgOp::intersection, {larger, smaller})), {onto_the_shared_face});

    // The unit ball (leaf 0) cut to its lower half by the half-space y < 0 (leaf 1).
    suite.add("BallIntersectedWithAHalfSpaceShowsTheFlatCutFromAbove",
              scene_of(build::csg(CsgOp::intersection, {build::sphere({0, 0, 0}, 1), build::plane({0, 1, 0}, 0)})),
              {hit({0.2, 5, 0.1}, {0, -1, 0}, {5, {0.2, 0, 0.1}, {0, 1, 0}, 1, true}),
               hit({0, -5, 0}, {0, 1, 0}, {4, {0, -1, 0}, {0, -1, 0}, 0, true}), miss({0, 0.5, 5}, {0, 0, -1})});
}

void add_union_cases(std::vector<HandSolvedCase>& cases) {
    Suite suite(cases, "CsgUnion");
    const scene::Scene two = two_balls(CsgOp::union_);
    suite.add("RayFromOutsideEntersThroughTheNearerSphere", two,
              {hit({-5, 0, 0}, {1, 0, 0}, {3.5, {-1.5, 0, 0}, {-1, 0, 0}, 0, true}),
               hit({5, 0, 0}, {-1, 0, 0}, {3.5, {1.5, 0, 0}, {1, 0, 0}, 1, true})});
    // From inside sphere 0 at x = −1 the ray passes sphere 0's surface at x = 0.5 inside sphere 1: no seam there; it
    // leaves at sphere 1's far surface x = 1.5.
    suite.add("RayFromInsideOneSphereCrossesTheOverlapWithoutASeam", two,
              {hit({-1, 0, 0}, {1, 0, 0}, {2.5, {1.5, 0, 0}, {-1, 0, 0}, 1, false}),
               hit({0, 0, 0}, {-1, 0, 0}, {1.5, {-1.5, 0, 0}, {1, 0, 0}, 0, false})});
    // Spheres at x = ∓3: from the origin the first piece is behind the ray, the second is ahead.
    suite.add("DisjointPieceBehindTheRayIsSkippedForThePieceAhead",
              scene_of(build::csg(CsgOp::union_, {build::sphere({-3, 0, 0}, 1), build::sphere({3, 0, 0}, 1)})),
              {hit({0, 0, 0}, {1, 0, 0}, {2, {2, 0, 0}, {-1, 0, 0}, 1, true}),
               hit({-5, 0, 0}, {1, 0, 0}, {1, {-4, 0, 0}, {-1, 0, 0}, 0, true})});
    suite.add("UnionOfTwoIdenticalSpheresReportsTheFirstChildFromOutsideAndInside",
              scene_of(build::csg(CsgOp::union_, {build::sphere({0, 1, 0}, 1), build::sphere({0, 1, 0}, 1)})),
              {hit({0, 1, 5}, {0, 0, -1}, {4, {0, 1, 1}, {0, 0, 1}, 0, true}),
               hit({0, 1, 0}, {0, 0, -1}, {1, {0, 1, -1}, {0, 0, 1}, 0, false})});
    // The half-space y < 0 (leaf 0) united with the unit ball (leaf 1): a ray from deep inside the half-space passes
    // the plane inside the ball and leaves through the ball's top.
    suite.add("RayFromInsideAHalfSpaceUnionLeavesWhereItIsInNeitherOperand",
              scene_of(build::csg(CsgOp::union_, {build::plane({0, 1, 0}, 0), build::sphere({0, 0, 0}, 1)})),
              {hit({0, -5, 0}, {0, 1, 0}, {6, {0, 1, 0}, {0, -1, 0}, 1, false}),
               hit({3, -5, 0}, {0, 1, 0}, {5, {3, 0, 0}, {0, -1, 0}, 0, false}),
               hit({0, 5, 0}, {0, -1, 0}, {4, {0, 1, 0}, {0, 1, 0}, 1, true})});
}

void add_nesting_cases(std::vector<HandSolvedCase>& cases) {
    Suite suite(cases, "CsgNesting");
    // The cube [−2,2]³ (leaf 0) minus the lens of spheres 1 and 2: a lens-shaped cavity, x in [−0.5,0.5] on the
    // axis; its −x wall is sphere 2's surface, its +x wall sphere 1's.
    const scene::Scene cavity = scene_of(build::csg(
        CsgOp::difference,
        {cube(), build::csg(CsgOp::intersection, {build::sphere({-0.5, 0, 0}, 1), build::sphere({0.5, 0, 0}, 1)})}));
    suite.add("CubeMinusLensIsLeftIntoTheCavityThroughTheLensFace", cavity,
              {hit({-5, 0, 0}, {1, 0, 0}, {3, {-2, 0, 0}, {-1, 0, 0}, 0, true}),
               hit({-1, 0, 0}, {1, 0, 0}, {0.5, {-0.5, 0, 0}, {-1, 0, 0}, 2, false})});
    suite.add("RayInsideALensCavityEntersTheSolidThroughTheFarLensFace", cavity,
              {hit({0, 0, 0}, {1, 0, 0}, {0.5, {0.5, 0, 0}, {-1, 0, 0}, 1, true}),
               hit({0, 0, 0}, {-1, 0, 0}, {0.5, {-0.5, 0, 0}, {1, 0, 0}, 2, true})});
    // The two overlapping balls (leaves 0, 1) cut to the slab |y| ≤ 0.25 (leaf 2).
    suite.add(
        "UnionCutBySlabShowsTheSlabFacesAndTheBallsSides",
        scene_of(build::csg(CsgOp::intersection,
                            {build::csg(CsgOp::union_, {build::sphere({-0.5, 0, 0}, 1), build::sphere({0.5, 0, 0}, 1)}),
                             build::box({-3, -0.25, -3}, {3, 0.25, 3})})),
        {hit({0, 5, 0}, {0, -1, 0}, {4.75, {0, 0.25, 0}, {0, 1, 0}, 2, true}),
         hit({-5, 0, 0}, {1, 0, 0}, {3.5, {-1.5, 0, 0}, {-1, 0, 0}, 0, true}),
         hit({0, 0, 0}, {1, 0, 0}, {1.5, {1.5, 0, 0}, {-1, 0, 0}, 1, false}),
         // At height 0.5 the line is in the balls but above the slab.
         miss({-5, 0.5, 0}, {1, 0, 0})});
}

// The tie rule at top level: at exactly the same t the object earlier in `objects` wins.
void add_tie_rule_cases(std::vector<HandSolvedCase>& cases) {
    Suite suite(cases, "CsgTieRule");
    build::SceneBuilder twins;
    twins.object(build::sphere({100, 100, 100}, 1));  // leaf 0, never hit: the twins are leaves 1 and 2
    twins.object(build::sphere({0, 0, 0}, 1));
    twins.object(build::sphere({0, 0, 0}, 1));
    const double y = std::sqrt(0.91);  // where the line x = 0.3 leaves the unit sphere
    suite.add("TwoIdenticalSpheresReportTheFirstOnesLeaf", twins.build(),
              {hit({0, 0, 5}, {0, 0, -1}, {4, {0, 0, 1}, {0, 0, 1}, 1, true}),
               hit({0.3, 0, 0}, {0, 1, 0}, {y, {0.3, y, 0}, {-0.3, -y, 0}, 1, false})});

    // A box's top face and a plane at y = 0 are met at exactly the same t (both −o_y/d_y): the earlier object wins,
    // whichever kind it is. The ray reaches y = 0 after 3 of its direction's steps, at (0.7, 0, 0.5).
    const V direction(0.2, -1, 0.1);
    const HandSolvedRay onto_the_shared_face =
        hit({0.1, 3, 0.2}, direction, {3 * math::length(direction), {0.7, 0, 0.5}, {0, 1, 0}, 0, true});
    const scene::Object ground = build::plane({0, 1, 0}, 0);
    const scene::Object slab = build::box({-1, -1, -1}, {1, 0, 1});
    build::SceneBuilder plane_first, box_first;
    plane_first.object(ground).object(slab);
    box_first.object(slab).object(ground);
    suite.add("CoincidentPlaneAndBoxFaceReportThePlaneWhenItComesFirst", plane_first.build(), {onto_the_shared_face});
    suite.add("CoincidentPlaneAndBoxFaceReportTheBoxWhenItComesFirst", box_first.build(), {onto_the_shared_face});
}

}  // namespace

void add_csg_cases(std::vector<HandSolvedCase>& cases) {
    add_difference_cases(cases);
    add_intersection_cases(cases);
    add_union_cases(cases);
    add_nesting_cases(cases);
    add_tie_rule_cases(cases);
}

}  // namespace twinray::plugin::hand_solved
