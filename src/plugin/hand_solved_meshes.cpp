// A mesh's first hits, worked out by hand from the triangles' geometry: which triangle, its side, the tie-break rules,
// and that degenerate triangles are never hit.
#include "plugin/hand_solved_cases.h"
#include "scene/scene_builder.h"

#include <memory>

namespace twinray::plugin::hand_solved {
namespace {

namespace build = scene::builder;

// The square [0, 2]² of z = 0 as two triangles, counter-clockwise seen from +z (its front): triangle 0 below the
// diagonal x = y, triangle 1 above it.
scene::Mesh square() {
    return build::mesh({{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}}, {{{0, 1, 2}}, {{0, 2, 3}}});
}

}  // namespace

void add_mesh_cases(std::vector<HandSolvedCase>& cases) {
    Suite suite(cases, "IntersectionMesh");
    // The square is leaf 1, after the decoy.
    const scene::Scene alone = after_a_decoy(square());
    suite.add("RayOntoTheFrontEntersTheTriangleUnderIt", alone,
              {hit({1.5, 0.5, 5}, {0, 0, -1}, {5, {1.5, 0.5, 0}, {0, 0, 1}, 1, true, 0}),
               hit({0.5, 1.5, 5}, {0, 0, -1}, {5, {0.5, 1.5, 0}, {0, 0, 1}, 1, true, 1})});
    suite.add("RayOntoTheBackLeavesWithTheNormalTurnedToTheRay", alone,
              {hit({0.5, 1.5, -3}, {0, 0, 1}, {3, {0.5, 1.5, 0}, {0, 0, -1}, 1, false, 1})});
    // (3, 4, 12)/13 from (1.5 − 3, 0.5 − 4, 12): t = 13, landing on (1.5, 0.5, 0) in triangle 0.
    suite.add("ObliqueRayHitsAtTheDistanceSolvedByHand", alone,
              {hit({-1.5, -3.5, 12}, {3, 4, -12}, {13, {1.5, 0.5, 0}, {0, 0, 1}, 1, true, 0})});
    suite.add("RaysBesideTheSquareOrAwayFromItMiss", alone,
              {miss({2.5, 1, 5}, {0, 0, -1}), miss({1, -0.5, 5}, {0, 0, -1}), miss({1, 1, 5}, {0, 0, 1}),
               miss({1, 1, 5}, {1, 0, 0})});
    // Straight down at (1, 1), on the shared diagonal: the origin perturbed by (ε, ε²) in x and y (Simulation of
    // Simplicity, reference/triangle.h) lies below the diagonal, in triangle 0, and in triangle 0 alone.
    suite.add("RayThroughTheSharedEdgeHitsTheTriangleTheTieRuleGivesIt", alone,
              {hit({1, 1, 5}, {0, 0, -1}, {5, {1, 1, 0}, {0, 0, 1}, 1, true, 0}),
               hit({1.25, 1.25, 5}, {0, 0, -1}, {5, {1.25, 1.25, 0}, {0, 0, 1}, 1, true, 0})});
    // At a corner of the square shared by both triangles, (0, 0), and at the one triangle 1 alone has, (0, 2): the
    // perturbed origin (ε, ε²) lies inside the square at (0, 0), in triangle 0 (below the diagonal), and outside it at
    // (0, 2) (y = 2 + ε² > 2): a miss, as for the same ray beside the square.
    suite.add("RaysThroughCornersHitOnlyWhereThePerturbedOriginLiesInside", alone,
              {hit({0, 0, 5}, {0, 0, -1}, {5, {0, 0, 0}, {0, 0, 1}, 1, true, 0}), miss({0, 2, 5}, {0, 0, -1})},
              "which side of a mesh's outer corner a ray exactly through it falls on is the tie rule of twinray's "
              "watertight triangle test, not the tracer ABI's");

    // A repeated index (triangle 0) and three collinear vertices (triangle 1), marked degenerate, beside the one
    // real triangle 2.
    scene::Mesh degenerate =
        build::mesh({{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {1, 1, 0}}, {{{0, 1, 1}}, {{0, 3, 2}}, {{0, 1, 2}}});
    auto marked = std::make_shared<scene::MeshData>(*degenerate.data);
    marked->degenerate = {0, 1};
    degenerate.data = marked;
    suite.add(
        "DegenerateTrianglesAreNeverHit", after_a_decoy(degenerate),
        {hit({1.5, 0.5, 5}, {0, 0, -1}, {5, {1.5, 0.5, 0}, {0, 0, 1}, 1, true, 2}), miss({0.5, 1.5, 5}, {0, 0, -1})});

    // Two copies of the square at the same place: the earlier mesh (leaf 1) takes the hit at equal t.
    build::SceneBuilder twice;
    twice.object(build::sphere({-1000, 1000, 1000}, 1));
    twice.add(square());
    twice.add(square());
    suite.add("AtEqualDistanceTheEarlierMeshWins", twice.build(),
              {hit({1.5, 0.5, 5}, {0, 0, -1}, {5, {1.5, 0.5, 0}, {0, 0, 1}, 1, true, 0})});

    // A mesh holding the square twice (triangles 2 and 3 repeat 0 and 1): the lower triangle wins at equal t.
    suite.add("AtEqualDistanceTheLowerTriangleOfOneMeshWins",
              after_a_decoy(build::mesh({{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}},
                                        {{{0, 2, 3}}, {{0, 1, 2}}, {{0, 2, 3}}, {{0, 1, 2}}})),
              {hit({1.5, 0.5, 5}, {0, 0, -1}, {5, {1.5, 0.5, 0}, {0, 0, 1}, 1, true, 1}),
               hit({0.5, 1.5, 5}, {0, 0, -1}, {5, {0.5, 1.5, 0}, {0, 0, 1}, 1, true, 0})});

    // A sphere in front of the square takes the hit; one behind it does not.
    build::SceneBuilder with_spheres;
    with_spheres.add(square());
    with_spheres.object(build::sphere({1.5, 0.5, 2}, 1));
    with_spheres.object(build::sphere({0.5, 1.5, -2}, 1));
    suite.add("TheNearestSurfaceWinsBetweenAMeshAndOtherPrimitives", with_spheres.build(),
              {hit({1.5, 0.5, 5}, {0, 0, -1}, {2, {1.5, 0.5, 3}, {0, 0, 1}, 1, true}),
               hit({0.5, 1.5, 5}, {0, 0, -1}, {5, {0.5, 1.5, 0}, {0, 0, 1}, 0, true, 1})});
}

}  // namespace twinray::plugin::hand_solved
