// Tracer<double>::trace against pixels worked out by hand from docs/scene-format.md's "Shading" formula
//   I = ambient·C·ambient_light + Σ unblocked lights (diffuse·C·Lc·max(0,N·L) + phong·Lc·max(0,R·L)^size)
//     + reflection·I(reflected) + transmission·I(refracted),
// and primary_ray against the camera paragraph of docs/scene-format.md. Each expected colour is built in the test
// from the geometry (N, L, R, Snell's law), never by calling the tracer's own helpers.
#include "reference/tracer.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

namespace {

using twinray::reference::normalize;
using twinray::reference::Tracer;
using twinray::scene::Material;
using V = twinray::reference::Vec3<double>;
namespace test = twinray::test;

constexpr double tolerance = 1e-12;

V trace(const twinray::scene::Scene& scene, V origin, V direction, twinray::TraceTally* tally = nullptr) {
    Tracer<double> tracer(scene);
    return tracer.trace({origin, normalize(direction)}, 1, tally);
}

V mirror(V d, V n) {
    return d - 2 * dot(d, n) * n;
}

Material material(V color, double ambient, double diffuse) {
    Material m;
    m.color = {color.x, color.y, color.z};
    m.ambient = ambient;
    m.diffuse = diffuse;
    return m;
}

// ---------------------------------------------------------------------------------------------------
// (1) Local model.

// The unit sphere hit at P = (1,2,2)/3 by a ray along −(0,1,2)/√5: N = P, L towards the light,
// R the mirror of the ray about N.
TEST(ReferenceShading, LitSphereIsAmbientPlusDiffusePlusPhongAtAnObliqueHit) {
    test::SceneBuilder builder;
    Material m = material({0.8, 0.6, 0.4}, 0.1, 0.7);
    m.phong = 0.5;
    m.phong_size = 10;
    builder.object(test::sphere({0, 0, 0}, 1, builder.material(m)));
    builder.light({4, 5, 6}, {1, 0.9, 0.8});
    builder.scene().ambient_light = {0.5, 0.6, 0.7};
    auto scene = builder.build();

    V p(1.0 / 3, 2.0 / 3, 2.0 / 3);
    V d = -normalize(V(0, 1, 2));
    V n = p;
    V l = normalize(V(4, 5, 6) - p);
    V r = mirror(d, n);
    V c(0.8, 0.6, 0.4);
    V lc(1, 0.9, 0.8);
    ASSERT_GT(dot(r, l), 0.5) << "the highlight must matter for this test";
    V expected = 0.1 * c * V(0.5, 0.6, 0.7) + 0.7 * dot(n, l) * c * lc + 0.5 * std::pow(dot(r, l), 10.0) * lc;
    TWINRAY_EXPECT_VEC_NEAR(trace(scene, p - 5.0 * d, d), expected, tolerance);
}

// ---------------------------------------------------------------------------------------------------
// (2) Shadows. The floor y = 0 is hit at the origin by a ray from (0,1,5); the light is at (1,10,0.5)
// and a blocker of radius 1 sits half-way, at (0.5,5,0.25).

struct FloorScene {
    test::SceneBuilder builder;
    V floor_color{0.9, 0.8, 0.7};

    FloorScene() {
        Material m = material(floor_color, 0.2, 0.6);
        m.phong = 0.3;
        m.phong_size = 5;
        builder.object(test::plane({0, 1, 0}, 0, builder.material(m)));
        builder.light({1, 10, 0.5}, {0.9, 1, 0.8});
    }

    // The lit floor at the origin, split into its ambient and its light's share.
    V ambient() const { return 0.2 * floor_color; }
    V light_share() const {
        V d = normalize(V(0, -1, -5));
        V n(0, 1, 0);
        V l = normalize(V(1, 10, 0.5));
        V lc(0.9, 1, 0.8);
        return 0.6 * dot(n, l) * floor_color * lc + 0.3 * std::pow(dot(mirror(d, n), l), 5.0) * lc;
    }
};

const V floor_eye(0, 1, 5);
const V floor_view(0, -1, -5);

TEST(ReferenceShading, UnblockedFloorPointGetsAmbientAndTheLightsShare) {
    FloorScene floor;
    TWINRAY_EXPECT_VEC_NEAR(trace(floor.builder.build(), floor_eye, floor_view), floor.ambient() + floor.light_share(),
                            tolerance);
}

TEST(ReferenceShading, OpaqueBlockerBetweenPointAndLightLeavesOnlyAmbient) {
    FloorScene floor;
    floor.builder.object(test::sphere({0.5, 5, 0.25}, 1));
    TWINRAY_EXPECT_VEC_NEAR(trace(floor.builder.build(), floor_eye, floor_view), floor.ambient(), tolerance);
}

TEST(ReferenceShading, GlassSphereBetweenPointAndLightPassesTransmissionSquared) {
    FloorScene floor;
    Material glass = material({1, 1, 1}, 0, 0);
    glass.transmission = 0.6;
    glass.ior = 1.5;
    floor.builder.object(test::sphere({0.5, 5, 0.25}, 1, floor.builder.material(glass)));
    TWINRAY_EXPECT_VEC_NEAR(trace(floor.builder.build(), floor_eye, floor_view),
                            floor.ambient() + 0.6 * 0.6 * floor.light_share(), tolerance);
}

// A glass sphere (0.6) and a glass box (0.5) on the way: four surfaces crossed, 0.6²·0.5².
TEST(ReferenceShading, EverySurfaceCrossedOnTheWayToTheLightMultipliesItsTransmission) {
    FloorScene floor;
    Material glass = material({1, 1, 1}, 0, 0);
    glass.transmission = 0.6;
    Material frosted = material({1, 1, 1}, 0, 0);
    frosted.transmission = 0.5;
    floor.builder.object(test::sphere({0.5, 5, 0.25}, 1, floor.builder.material(glass)));
    floor.builder.object(test::box({-0.5, 7, -0.5}, {1.5, 8, 1.5}, floor.builder.material(frosted)));
    TWINRAY_EXPECT_VEC_NEAR(trace(floor.builder.build(), floor_eye, floor_view),
                            floor.ambient() + (0.36 * 0.25) * floor.light_share(), tolerance);
}

// An opaque sphere on the line from the point through the light, but beyond the light.
TEST(ReferenceShading, SurfaceBeyondTheLightCastsNoShadow) {
    FloorScene floor;
    floor.builder.object(test::sphere({2, 20, 1}, 1));
    TWINRAY_EXPECT_VEC_NEAR(trace(floor.builder.build(), floor_eye, floor_view), floor.ambient() + floor.light_share(),
                            tolerance);
}

// ---------------------------------------------------------------------------------------------------
// (3) Mirrors. The ray from (0,1,0) along (1,−1,0)/√2 meets the floor y = 0 at (1,0,0) and is
// mirrored to (1,1,0)/√2.

TEST(ReferenceShading, MirrorAddsReflectionTimesTheBackgroundTheReflectedRaySees) {
    test::SceneBuilder builder;
    Material m = material({0.3, 0.6, 0.9}, 0.1, 0);
    m.reflection = 0.7;
    builder.object(test::plane({0, 1, 0}, 0, builder.material(m)));
    builder.scene().background = {0.2, 0.3, 0.4};
    V expected = 0.1 * V(0.3, 0.6, 0.9) + 0.7 * V(0.2, 0.3, 0.4);
    TWINRAY_EXPECT_VEC_NEAR(trace(builder.build(), V(0, 1, 0), V(1, -1, 0)), expected, tolerance);
}

// The mirrored ray from (1,0,0) along (1,1,0)/√2 passes the centre (3,1,0) of a unit sphere at
// distance √0.5 and meets it at (1,0,0) + √2·(1,1,0)/√2 = (2,1,0), where N = (−1,0,0).
struct MirrorAndBall {
    test::SceneBuilder builder;
    V ball_color{0.9, 0.2, 0.1};

    MirrorAndBall() {
        Material floor = material({1, 1, 1}, 0.05, 0.2);
        floor.reflection = 0.5;
        Material ball = material(ball_color, 0.1, 0.8);
        ball.phong = 0.4;
        ball.phong_size = 20;
        builder.object(test::plane({0, 1, 0}, 0, builder.material(floor)));
        builder.object(test::sphere({3, 1, 0}, 1, builder.material(ball)));
        builder.light({0, 5, 0});
    }
};

TEST(ReferenceShading, MirrorFloorAddsReflectionTimesTheLitSphereItReflects) {
    MirrorAndBall setup;
    V floor_n(0, 1, 0);
    V floor_l = normalize(V(0, 5, 0) - V(1, 0, 0));
    V floor_local = V(0.05, 0.05, 0.05) + 0.2 * dot(floor_n, floor_l) * V(1, 1, 1);

    V ball_d = normalize(V(1, 1, 0));
    V ball_n(-1, 0, 0);
    V ball_l = normalize(V(0, 5, 0) - V(2, 1, 0));
    V ball = 0.1 * setup.ball_color + 0.8 * dot(ball_n, ball_l) * setup.ball_color +
             0.4 * std::pow(dot(mirror(ball_d, ball_n), ball_l), 20.0) * V(1, 1, 1);

    TWINRAY_EXPECT_VEC_NEAR(trace(setup.builder.build(), V(0, 1, 0), V(1, -1, 0)), floor_local + 0.5 * ball, tolerance);
}

// The primary ray, the floor's shadow ray, the mirrored ray and the ball's shadow ray.
TEST(ReferenceShading, TraceCountsThePrimaryShadowAndSecondaryRays) {
    MirrorAndBall setup;
    twinray::TraceTally tally;
    tally.rays = 10;
    trace(setup.builder.build(), V(0, 1, 0), V(1, -1, 0), &tally);
    EXPECT_EQ(tally.rays, 10u + 4u);
}

// ---------------------------------------------------------------------------------------------------
// (4) Refraction. A glass slab −1 ≤ y ≤ 0 (transmission 0.9, ior 1.5, nothing else) over a lit floor
// y = −3. The ray from (0,1,0) along (1,−1,0)/√2 enters at (1,0,0) at 45°: sin θt = sin 45°/1.5 = √2/3,
// cos θt = √7/3, so it crosses the slab to x = 1 + tan θt = 1 + √(2/7) and leaves at 45° again
// (1.5·√2/3 = √2/2), reaching the floor 2 further on at x = 3 + √(2/7). A light under the slab at
// (3,−2,0) lights the floor there.
TEST(ReferenceShading, GlassSlabShowsTheFloorWhereSnellsLawSendsTheRay) {
    test::SceneBuilder builder;
    Material glass = material({1, 1, 1}, 0, 0);
    glass.transmission = 0.9;
    glass.ior = 1.5;
    V floor_color(0.9, 0.5, 0.2);
    builder.object(test::box({-10, -1, -10}, {10, 0, 10}, builder.material(glass)));
    builder.object(test::plane({0, 1, 0}, -3, builder.material(material(floor_color, 0.1, 0.8))));
    builder.light({3, -2, 0});

    V floor_point(3 + std::sqrt(2.0 / 7.0), -3, 0);
    V l = normalize(V(3, -2, 0) - floor_point);
    V floor = 0.1 * floor_color + 0.8 * dot(V(0, 1, 0), l) * floor_color;
    // Transmission 0.9 at the entry and again at the exit.
    TWINRAY_EXPECT_VEC_NEAR(trace(builder.build(), V(0, 1, 0), V(1, -1, 0)), 0.81 * floor, tolerance);
}

// ---------------------------------------------------------------------------------------------------
// (5) Total internal reflection. Glass fills y < 0 (a plane; ambient 0.05, reflection 0.1,
// transmission 0.8, ior 1.5). A ray inside it from (0,−1,0) reaches the surface at (√3,0,0) after 2.

struct GlassBelow {
    test::SceneBuilder builder;
    V background{0.2, 0.5, 0.7};
    V ball_color{0.3, 0.9, 0.1};

    GlassBelow() {
        Material glass = material({1, 1, 1}, 0.05, 0);
        glass.reflection = 0.1;
        glass.transmission = 0.8;
        glass.ior = 1.5;
        builder.object(test::plane({0, 1, 0}, 0, builder.material(glass)));
        // Inside the glass, where the ray mirrored at (√3,0,0) heads: 2 along (√3/2,−1/2,0).
        builder.object(test::sphere({2 * std::sqrt(3.0), -1, 0}, 0.3, builder.material(material(ball_color, 1, 0))));
        builder.light({0, 5, 0});  // above the surface: N faces down, so it never lights the hit
        builder.scene().background = {background.x, background.y, background.z};
    }
};

// At 60° from the normal, sin θt would be 1.5·sin 60° > 1: the transmission weight joins the
// reflection, 0.1 + 0.8, on the ray mirrored into the glass, which sees the ball (ambient 1).
TEST(ReferenceShading, TotalInternalReflectionAddsTheTransmissionWeightToTheReflection) {
    GlassBelow setup;
    V d(std::sqrt(3.0) / 2, 0.5, 0);
    ASSERT_GT(1.5 * d.x, 1.0) << "beyond the critical angle";
    TWINRAY_EXPECT_VEC_NEAR(trace(setup.builder.build(), V(0, -1, 0), d),
                            V(0.05, 0.05, 0.05) + (0.1 + 0.8) * setup.ball_color, tolerance);
}

// At 30° (sin θt = 0.75) the ray leaves into the background above with weight 0.8, and the mirrored
// ray (0.1) runs down into the glass, missing the ball, to the background too.
TEST(ReferenceShading, BelowTheCriticalAngleTransmissionGoesToTheRefractedRay) {
    GlassBelow setup;
    V d(0.5, std::sqrt(3.0) / 2, 0);
    TWINRAY_EXPECT_VEC_NEAR(trace(setup.builder.build(), V(0, -1, 0), d),
                            V(0.05, 0.05, 0.05) + (0.1 + 0.8) * setup.background, tolerance);
}

// ---------------------------------------------------------------------------------------------------
// (6) max_depth.

// A sphere that reflects (0.5) and transmits (0.3) under a white sky: with max_depth 1 neither
// secondary ray is traced; with 2 both are, and both end in the background.
TEST(ReferenceShading, MaxDepthOneDropsTheReflectionAndTransmissionTerms) {
    test::SceneBuilder builder;
    Material m = material({0.4, 0.5, 0.6}, 0.2, 0);
    m.reflection = 0.5;
    m.transmission = 0.3;
    m.ior = 1.3;
    builder.object(test::sphere({0, 0, 0}, 1, builder.material(m)));
    builder.scene().background = {1, 1, 1};
    builder.scene().max_depth = 1;
    V local = 0.2 * V(0.4, 0.5, 0.6);
    TWINRAY_EXPECT_VEC_NEAR(trace(builder.build(), V(0, 0, 5), V(0, 0, -1)), local, tolerance);
    // max_depth 2: the reflected ray sees the sky (0.5); the refracted ray reaches the far side at depth
    // 2, where its own secondary rays are cut off: it contributes 0.3·(that surface's ambient).
    builder.scene().max_depth = 2;
    TWINRAY_EXPECT_VEC_NEAR(trace(builder.build(), V(0, 0, 5), V(0, 0, -1)), local + V(0.5, 0.5, 0.5) + 0.3 * local,
                            tolerance);
}

// Between the mirror floor y = 0 (ambient colour a_f, reflection 0.5) and the mirror ceiling y = 2
// (a_c, 0.25) the ray from (0,1,0) along (1,−1,0)/√2 bounces for ever; each max_depth shades exactly
// that many surfaces.
TEST(ReferenceShading, MirrorCorridorIsTracedToExactlyMaxDepthSurfaces) {
    test::SceneBuilder builder;
    V floor_color(0.2, 0.4, 0.6);
    V ceiling_color(0.9, 0.1, 0.3);
    Material floor = material(floor_color, 0.5, 0);
    floor.reflection = 0.5;
    Material ceiling = material(ceiling_color, 0.5, 0);
    ceiling.reflection = 0.25;
    builder.object(test::plane({0, 1, 0}, 0, builder.material(floor)));
    builder.object(test::plane({0, -1, 0}, -2, builder.material(ceiling)));
    V af = 0.5 * floor_color;
    V ac = 0.5 * ceiling_color;
    V expected[] = {af, af + 0.5 * ac, af + 0.5 * (ac + 0.25 * af), af + 0.5 * (ac + 0.25 * (af + 0.5 * ac))};
    for (int depth = 1; depth <= 4; ++depth) {
        SCOPED_TRACE(testing::Message() << "max_depth " << depth);
        builder.scene().max_depth = depth;
        TWINRAY_EXPECT_VEC_NEAR(trace(builder.build(), V(0, 1, 0), V(1, -1, 0)), expected[depth - 1], tolerance);
    }
}

// ---------------------------------------------------------------------------------------------------
// (7) Lights behind the surface. The floor y = 0 is hit at the origin nearly grazing, from (−10,1,0):
// R = (10,1,0)/√101. A light at (10,−0.5,0), under the surface, has N·L < 0 yet R·L ≈ 0.989: its
// highlight would be bright if N·L ≤ 0 did not exclude it.
TEST(ReferenceShading, LightWithNDotLBelowZeroContributesNothingNotEvenPhong) {
    test::SceneBuilder builder;
    V c(0.5, 0.6, 0.7);
    Material m = material(c, 0.1, 0.9);
    m.phong = 1;
    m.phong_size = 1;
    builder.object(test::plane({0, 1, 0}, 0, builder.material(m)));
    builder.light({10, -0.5, 0});
    V d = normalize(V(10, -1, 0));
    V n(0, 1, 0);
    V l_under = normalize(V(10, -0.5, 0));
    ASSERT_LT(dot(n, l_under), 0.0);
    ASSERT_GT(dot(mirror(d, n), l_under), 0.98);
    TWINRAY_EXPECT_VEC_NEAR(trace(builder.build(), V(-10, 1, 0), d), 0.1 * c, tolerance);

    // A second light above the surface counts as usual; the one under it still adds nothing.
    builder.light({3, 4, 2}, {0.5, 0.5, 1});
    V l = normalize(V(3, 4, 2));
    V lc(0.5, 0.5, 1);
    V lit = 0.1 * c + 0.9 * dot(n, l) * c * lc + std::pow(std::fmax(0.0, dot(mirror(d, n), l)), 1.0) * lc;
    TWINRAY_EXPECT_VEC_NEAR(trace(builder.build(), V(-10, 1, 0), d), lit, tolerance);
}

// ---------------------------------------------------------------------------------------------------
// Camera: horizontal fov, pixel centres, right = normalize(f × up), image up = right × f, (0,0) the
// top-left pixel.

Tracer<double> camera_tracer(V eye, V look_at, V up, double fov_deg) {
    test::SceneBuilder builder;
    builder.scene().camera = {{eye.x, eye.y, eye.z}, {look_at.x, look_at.y, look_at.z}, {up.x, up.y, up.z}, fov_deg};
    return Tracer<double>(builder.build());
}

// fov 90° (half-width 1), 4 × 2 pixels: half-height 0.5. Pixel (3,0) is at u = (2·3.5/4 − 1) = 0.75,
// v = (1 − 2·0.5/2)·0.5 = 0.25; pixel (0,1) at u = −0.75, v = −0.25.
TEST(ReferenceCamera, CameraLookingDownNegativeZHasPositiveXToTheRightAndPositiveYUp) {
    Tracer<double> tracer = camera_tracer({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90);
    auto top_right = tracer.primary_ray(3, 0, 4, 2);
    auto bottom_left = tracer.primary_ray(0, 1, 4, 2);
    TWINRAY_EXPECT_VEC_NEAR(top_right.origin, V(0, 0, 0), 0.0);
    TWINRAY_EXPECT_VEC_NEAR(top_right.direction, normalize(V(0.75, 0.25, -1)), tolerance);
    TWINRAY_EXPECT_VEC_NEAR(bottom_left.direction, normalize(V(-0.75, -0.25, -1)), tolerance);
}

// Eye (1,2,3) looking at (2,1,−1) with fov 60° on a 7 × 5 image: the centre pixel (3,2) looks along f;
// every other pixel along f + u·right + v·up with u = (2(x+½)/7 − 1)·tan 30°,
// v = (1 − 2(y+½)/5)·tan 30°·5/7.
TEST(ReferenceCamera, PrimaryRaysFollowTheContractsFormulaForAGeneralCamera) {
    V eye(1, 2, 3);
    Tracer<double> tracer = camera_tracer(eye, {2, 1, -1}, {0, 1, 0}, 60);
    V f = normalize(V(1, -1, -4));
    V right = normalize(cross(f, V(0, 1, 0)));
    V up = cross(right, f);
    double half_width = std::tan(std::numbers::pi / 6);
    for (auto [x, y] : {std::pair{3, 2}, std::pair{4, 1}, std::pair{0, 0}, std::pair{6, 4}, std::pair{2, 3}}) {
        SCOPED_TRACE(testing::Message() << "pixel (" << x << ", " << y << ")");
        double u = (2 * (x + 0.5) / 7 - 1) * half_width;
        double v = (1 - 2 * (y + 0.5) / 5) * half_width * 5 / 7;
        auto ray = tracer.primary_ray(x, y, 7, 5);
        TWINRAY_EXPECT_VEC_NEAR(ray.origin, eye, 0.0);
        TWINRAY_EXPECT_VEC_NEAR(ray.direction, normalize(f + u * right + v * up), tolerance);
    }
    TWINRAY_EXPECT_VEC_NEAR(tracer.primary_ray(3, 2, 7, 5).direction, f, tolerance);
}

// Looking down at 45° with up = +y: right = (1,0,0), image up = (0,1,−1)/√2 (tilted, not +y).
// Pixel (0,0) of 2 × 2 at fov 90°: u = −0.5, v = 0.5.
TEST(ReferenceCamera, ImageUpIsTheCameraUpMadePerpendicularToTheViewDirection) {
    Tracer<double> tracer = camera_tracer({0, 0, 0}, {0, -1, -1}, {0, 1, 0}, 90);
    double s = std::sqrt(0.5);
    V expected = normalize(V(0, -s, -s) + V(-0.5, 0, 0) + 0.5 * V(0, s, -s));
    TWINRAY_EXPECT_VEC_NEAR(tracer.primary_ray(0, 0, 2, 2).direction, expected, tolerance);
}

// Seen from (0,0,5) towards −z, fov 60°, 8 × 8: a red ball (ambient 1) at +x appears in the right half,
// a green one at +y in the top half; their mirror-image pixels show the blue background.
TEST(ReferenceCamera, CameraLookingDownNegativeZSeesPositiveXOnTheRightAndPositiveYAtTheTop) {
    test::SceneBuilder builder;
    builder.object(test::sphere({1.5, 0, 0}, 0.8, builder.material(material({1, 0, 0}, 1, 0))));
    builder.object(test::sphere({0, 1.5, 0}, 0.8, builder.material(material({0, 1, 0}, 1, 0))));
    builder.scene().camera.fov_deg = 60;
    builder.scene().background = {0, 0, 1};
    Tracer<double> tracer(builder.build());
    auto pixel = [&](int x, int y) { return tracer.trace(tracer.primary_ray(x, y, 8, 8), 1); };
    TWINRAY_EXPECT_VEC_NEAR(pixel(5, 3), V(1, 0, 0), 0.0);
    TWINRAY_EXPECT_VEC_NEAR(pixel(5, 4), V(1, 0, 0), 0.0);
    TWINRAY_EXPECT_VEC_NEAR(pixel(2, 3), V(0, 0, 1), 0.0);
    TWINRAY_EXPECT_VEC_NEAR(pixel(3, 2), V(0, 1, 0), 0.0);
    TWINRAY_EXPECT_VEC_NEAR(pixel(3, 5), V(0, 0, 1), 0.0);
}

}  // namespace
