// Degenerate but legal scenes (docs/numerics.md): a sphere of radius 1e-6 beside one of radius 1e6,
// coincident CSG surfaces, a cylinder of length 1e-6, a box of size 1e-6, the camera inside a solid, a
// light on a surface. Every tracer renders each without a NaN, and the answers that are exactly known
// are met.
#include "numerics/numerics.h"
#include "reference/tracer.h"
#include "sse/tracer.h"
#include "tests/extremes.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace {

namespace scene = twinray::scene;
namespace test = twinray::test;
using twinray::Vec3d;
using twinray::numerics::TracerKind;
using twinray::test::unit_roundoff;

twinray::Image render_with(TracerKind kind, const scene::Scene& scene) {
    twinray::RenderOptions options{24, 24, 1, {}, nullptr};
    switch (kind) {
        case TracerKind::reference_double: return twinray::reference::render<double>(scene, options).image;
        case TracerKind::reference_float: return twinray::reference::render<float>(scene, options).image;
        case TracerKind::sse: return twinray::sse::render(scene, options).image;
    }
    return twinray::Image(1, 1);
}

int non_finite_pixels(const twinray::Image& image) {
    int count = 0;
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            const twinray::Rgb& p = image.at(x, y);
            count += !(std::isfinite(p.r) && std::isfinite(p.g) && std::isfinite(p.b));
        }
    }
    return count;
}

scene::Material glass() {
    scene::Material m;
    m.diffuse = 0.05;
    m.reflection = 0.1;
    m.transmission = 0.85;
    m.ior = 1.5;
    return m;
}

class ExtremesDegenerate : public twinray::test::EachTracer {};

// Double resolves the small sphere on the large one; float cannot: near it, the large sphere's surface is
// known only within 16·u·(1e6 + 1e6) ≈ 0.19, far more than the small sphere. Both hold the bound of the
// scale test per primitive, 16·u·(radius + |centre|∞), and neither produces a NaN.
TEST_P(ExtremesDegenerate, SphereOfRadius1e6BesideOneOfRadius1e6HitsWithinItsBoundAndRendersWithoutNaN) {
    test::SceneBuilder builder;
    builder.light({1, 1, 1});
    builder.object(test::sphere({0, -1e6, 0}, 1e6));
    builder.object(test::sphere({0, 2e-6, 0}, 1e-6));
    builder.scene().camera = {{0, 3e-6, 1e-5}, {0, 2e-6, 0}, {0, 1, 0}, 40};
    scene::Scene scene = builder.build();
    EXPECT_EQ(non_finite_pixels(render_with(GetParam(), scene)), 0);
    auto tracer = twinray::numerics::make_tracer(scene, GetParam());
    auto leaves = twinray::numerics::leaf_objects(scene);
    const double bounds[2] = {16 * unit_roundoff(GetParam()) * 2e6, 16 * unit_roundoff(GetParam()) * 3e-6};
    int seen[2] = {0, 0};
    double worst[2] = {0, 0};
    for (int y = 0; y < 24; ++y) {
        for (int x = 0; x < 24; ++x) {
            twinray::numerics::FirstHit hit = tracer->primary_hit(x, y, 24, 24);
            if (!hit.hit) {
                continue;
            }
            ++seen[hit.leaf];
            double error = static_cast<double>(
                twinray::numerics::distance_to_surface(*leaves[static_cast<std::size_t>(hit.leaf)], hit.point));
            EXPECT_LE(error, bounds[hit.leaf]) << "leaf " << hit.leaf << " at pixel " << x << "," << y;
            worst[hit.leaf] = std::max(worst[hit.leaf], error);
        }
    }
    if (GetParam() == TracerKind::reference_double) {
        EXPECT_GT(seen[1], 20) << "double sees the small sphere";
        EXPECT_GT(seen[0], 50) << "and the large one below it";
    }
    std::printf(
        "[ measured ] %s: large sphere in %d pixels (error up to %.2e, bound %.2e), small sphere in %d (error up to "
        "%.2e, bound %.2e)\n",
        twinray::numerics::tracer_name(GetParam()), seen[0], worst[0], bounds[0], seen[1], worst[1], bounds[1]);
}

// Identical boxes in a union are one box (the earlier leaf wins the tie); subtracted from each other they
// are nothing; boxes sharing a face leave no seam inside their union; coplanar faces of an intersection
// are hit once, by the earlier leaf.
TEST_P(ExtremesDegenerate, CoincidentCsgSurfacesLeaveNoSeamAndNothingWhereTheyCancel) {
    auto single_scene = [](scene::Object object) {
        test::SceneBuilder builder;
        builder.object(std::move(object));
        return builder.build();
    };
    scene::Object cube = test::box({-1, -1, -1}, {1, 1, 1});
    auto one = twinray::numerics::make_tracer(single_scene(cube), GetParam());
    auto doubled =
        twinray::numerics::make_tracer(single_scene(test::csg(scene::CsgOp::union_, {cube, cube})), GetParam());
    auto cancelled =
        twinray::numerics::make_tracer(single_scene(test::csg(scene::CsgOp::difference, {cube, cube})), GetParam());
    int rays = 0;
    for (double y = -1.25; y <= 1.25; y += 0.125) {
        for (double x = -1.25; x <= 1.25; x += 0.125) {
            Vec3d origin{x, y, 5}, direction{0.0, 0.0, -1.0};
            twinray::numerics::FirstHit a = one->intersect(origin, direction),
                                        b = doubled->intersect(origin, direction);
            EXPECT_EQ(a.hit, b.hit) << x << "," << y;
            if (a.hit && b.hit) {
                EXPECT_EQ(a.t, b.t);
                EXPECT_EQ(b.leaf, 0);
            }
            EXPECT_FALSE(cancelled->intersect(origin, direction).hit) << "A − A is empty; hit at " << x << "," << y;
            ++rays;
        }
    }
    // Two boxes sharing the face x = 0: from inside the first, the union is left at x = 1, not at x = 0.
    auto touching = twinray::numerics::make_tracer(
        single_scene(
            test::csg(scene::CsgOp::union_, {test::box({-1, -1, -1}, {0, 1, 1}), test::box({0, -1, -1}, {1, 1, 1})})),
        GetParam());
    twinray::numerics::FirstHit leaving = touching->intersect({-0.5, 0.1, 0.2}, {1, 0, 0});
    ASSERT_TRUE(leaving.hit);
    EXPECT_EQ(leaving.t, 1.5) << "the shared face is inside the union";
    EXPECT_EQ(leaving.leaf, 1);
    // The faces y = 1 of both operands of an intersection coincide: hit once, by the earlier leaf.
    auto coplanar = twinray::numerics::make_tracer(
        single_scene(test::csg(scene::CsgOp::intersection, {cube, test::box({-1, -1, 0}, {1, 1, 2})})), GetParam());
    twinray::numerics::FirstHit top = coplanar->intersect({0.25, 3, 0.5}, {0, -1, 0});
    ASSERT_TRUE(top.hit);
    EXPECT_EQ(top.t, 2.0);
    EXPECT_EQ(top.leaf, 0);
    EXPECT_EQ(std::fabs(top.normal[1]), 1.0);
    std::printf("[ measured ] %s: %d rays agree between a box and a union of two copies; its difference is empty\n",
                twinray::numerics::tracer_name(GetParam()), rays);
}

// A cylinder 1e-6 long is a disc: hit on its top from above (not its bottom, 1e-6 lower) and on its rim
// from the side. A box 1e-6 wide is hit on the right face. Float resolves both near the origin: its
// spacing there is far below 1e-6.
TEST_P(ExtremesDegenerate, CylinderOfLength1e6AndBoxOfSize1e6AreHitOnTheRightFaces) {
    double u = unit_roundoff(GetParam());
    test::SceneBuilder disc_builder;
    disc_builder.object(test::cylinder({0, 0, 0}, {0, 1e-6, 0}, 1));
    auto disc = twinray::numerics::make_tracer(disc_builder.build(), GetParam());
    twinray::numerics::FirstHit top = disc->intersect({0.3, 1, 0.2}, {0, -1, 0});
    ASSERT_TRUE(top.hit);
    EXPECT_NEAR(top.t, 1 - 1e-6, 4 * u) << "the top cap, not the bottom one 1e-6 lower";
    EXPECT_NEAR(top.normal[1], 1.0, 1e-6);
    twinray::numerics::FirstHit rim = disc->intersect({-5, 5e-7, 0}, {1, 0, 0});
    ASSERT_TRUE(rim.hit);
    EXPECT_NEAR(rim.t, 4.0, 16 * u);
    EXPECT_NEAR(rim.normal[0], -1.0, 1e-6);

    test::SceneBuilder grain_builder;
    grain_builder.object(test::box({-5e-7, -5e-7, -5e-7}, {5e-7, 5e-7, 5e-7}));
    auto grain = twinray::numerics::make_tracer(grain_builder.build(), GetParam());
    twinray::numerics::FirstHit front = grain->intersect({1e-7, 2e-7, 1}, {0, 0, -1});
    ASSERT_TRUE(front.hit);
    EXPECT_NEAR(front.t, 1 - 5e-7, 4 * u);
    EXPECT_EQ(front.normal[2], 1.0);
    EXPECT_FALSE(grain->intersect({6e-7, 0, 1}, {0, 0, -1}).hit) << "1e-7 beside the box";
    std::printf("[ measured ] %s: disc top at t = %.9g (exact %.9g), rim at %.9g, box face at %.9g (exact %.9g)\n",
                twinray::numerics::tracer_name(GetParam()), top.t, 1 - 1e-6, rim.t, front.t, 1 - 5e-7);
}

// The camera inside a glass sphere and inside a glass box: every primary ray leaves the solid, at the
// distance the geometry gives, and the image has no NaN.
TEST_P(ExtremesDegenerate, CameraInsideASolidSeesItsInsideFromEveryPixel) {
    for (scene::Object solid : {test::sphere({0, 0, 0}, 2), test::box({-2, -2, -2}, {2, 2, 2})}) {
        test::SceneBuilder builder;
        int material = builder.material(glass());
        solid.material = material;
        builder.object(solid);
        builder.light({1, 1, 1});
        builder.scene().camera = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 60};
        scene::Scene scene = builder.build();
        EXPECT_EQ(non_finite_pixels(render_with(GetParam(), scene)), 0);
        auto tracer = twinray::numerics::make_tracer(scene, GetParam());
        for (int y = 0; y < 24; y += 3) {
            for (int x = 0; x < 24; x += 3) {
                twinray::RayTree tree;
                tracer->trace_primary(x, y, 24, 24, tree);
                const twinray::RayNode& primary = tree.nodes.front();
                ASSERT_TRUE(primary.hit) << x << "," << y;
                EXPECT_FALSE(primary.entering) << "the camera is inside: the first surface is left";
                double expected =
                    std::holds_alternative<scene::Sphere>(solid.shape)
                        ? 2.0
                        : 2.0 / std::max({std::fabs(primary.direction[0]), std::fabs(primary.direction[1]),
                                          std::fabs(primary.direction[2])});
                EXPECT_NEAR(primary.t, expected, 16 * unit_roundoff(GetParam()) * 4) << x << "," << y;
            }
        }
    }
}

// A light exactly on a plane and another exactly on a sphere's surface: N·L is 0 or the light sits on
// the shadow ray's own surface; shading stays finite everywhere.
TEST_P(ExtremesDegenerate, LightsOnASurfaceShadeWithoutNaN) {
    test::SceneBuilder builder;
    builder.object(test::plane({0, 1, 0}, 0));
    builder.object(test::sphere({2, 1, -4}, 1));
    builder.light({0, 0, -3});
    builder.light({2, 2, -4});
    builder.scene().camera = {{0, 3, 4}, {0, 0, -3}, {0, 1, 0}, 60};
    scene::Scene scene = builder.build();
    twinray::Image image = render_with(GetParam(), scene);
    EXPECT_EQ(non_finite_pixels(image), 0);
    double brightest = 0;
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            brightest = std::max(brightest, static_cast<double>(image.at(x, y).r));
        }
    }
    EXPECT_GT(brightest, 0.2) << "the lights light something";
}

TWINRAY_FOR_EACH_TRACER(ExtremesDegenerate);

}  // namespace
