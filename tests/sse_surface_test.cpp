// Each SSE primitive header's surface at a hit, called directly (the stage a render reaches only through
// nearest_hit.h): a point measurably off the surface is re-projected onto it within the shared bound
// (scene::surface_bounds_of_*), and the outward normal points along the surface's true normal.
#include "scene/loader.h"
#include "scene/portable_random.h"
#include "sse/box.h"
#include "sse/compiled_scene.h"
#include "sse/cylinder.h"
#include "sse/plane.h"
#include "sse/sphere.h"
#include "sse/transformed.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <string>

namespace {

using twinray::sse::SurfaceAnchor;
using twinray::sse::Vec3;
namespace scene = twinray::scene;
namespace math = twinray::math;

// Where the hit pipeline puts p: anchor + radius·n̂ (n̂ the unit outward normal) where p is farther than
// the anchor's own rounding from the surface.
Vec3 reprojected(const SurfaceAnchor& anchor, Vec3 unit_normal) {
    return anchor.anchor + anchor.radius * unit_normal;
}

template <typename Surface>
Vec3 unit_outward(const Surface& surface, int face, Vec3 point) {
    bool needs_normalizing = false;
    Vec3 normal = twinray::sse::outward_normal(surface, face, point, needs_normalizing);
    return needs_normalizing ? math::normalize_by_reciprocal(normal) : normal;
}

constexpr float off_surface = 1e-3f;  // far beyond every own-rounding bound below (about 1e-5)

TEST(SseSurface, ASpherePointOffTheSurfaceReprojectsWithinItsOwnRoundingBound) {
    scene::Sphere sphere{{10, -20, 30}, 2};
    auto surface = twinray::sse::make_surface(sphere);
    Vec3 direction = math::normalize_by_reciprocal(Vec3{1, 2, -2});
    Vec3 point = surface.center + (surface.radius + off_surface) * direction;
    SurfaceAnchor anchor = twinray::sse::surface_anchor(surface, 0, 1.0f, point);
    Vec3 normal = unit_outward(surface, 0, point);
    float error = std::fabs(math::length(reprojected(anchor, normal) - surface.center) - surface.radius);
    float bound = scene::surface_bounds_of_sphere(surface.radius).own_rounding.at(math::max_abs_component(point));
    EXPECT_LE(error, bound) << "|p' − c| − r = " << error;
    EXPECT_GT(off_surface, anchor.own_rounding) << "the point must count as off the surface";
    EXPECT_GT(math::dot(normal, direction), 0.9999f);
}

TEST(SseSurface, APlanePointOffTheSurfaceReprojectsWithinItsOwnRoundingBound) {
    scene::Plane plane{{0, 0.6, 0.8}, 5};
    auto surface = twinray::sse::make_surface(plane);
    Vec3 point = surface.offset * surface.normal + Vec3{3, 4, -3} + off_surface * surface.normal;
    SurfaceAnchor anchor = twinray::sse::surface_anchor(surface, 0, 1.0f, point);
    float error = std::fabs(math::dot(surface.normal, reprojected(anchor, surface.normal)) - surface.offset);
    float bound = scene::surface_bounds_of_plane(surface.offset).own_rounding.at(math::max_abs_component(point));
    EXPECT_LE(error, bound) << "n·p' − d = " << error;
    EXPECT_EQ(anchor.radius, 0.0f) << "a flat face is its own anchor";
}

TEST(SseSurface, ABoxFaceCoordinateIsSetExactly) {
    scene::Box box{{-1, -2, -3}, {1, 2, 3}};
    auto surface = twinray::sse::make_surface(box);
    int top = twinray::sse::box_face(1, true);
    Vec3 point{0.25f, 2.0f + off_surface, -1.5f};
    SurfaceAnchor anchor = twinray::sse::surface_anchor(surface, top, 1.0f, point);
    EXPECT_EQ(anchor.anchor.y, 2.0f);
    EXPECT_EQ(anchor.anchor.x, point.x);
    EXPECT_EQ(anchor.anchor.z, point.z);
    Vec3 normal = unit_outward(surface, top, point);
    EXPECT_EQ(normal.y, 1.0f);
}

TEST(SseSurface, ACylinderSideAndCapPointReprojectWithinTheirOwnRoundingBound) {
    scene::Cylinder cylinder{{1, 1, 1}, {1, 5, 1}, 0.5};
    auto surface = twinray::sse::make_surface(cylinder);
    float bound_size = scene::surface_bounds_of_cylinder(surface.radius, surface.height).own_rounding.size;

    Vec3 side_point{1.0f + surface.radius + off_surface, 3.0f, 1.0f};
    SurfaceAnchor side = twinray::sse::surface_anchor(surface, twinray::sse::cylinder_side, 1.0f, side_point);
    Vec3 side_normal = unit_outward(surface, twinray::sse::cylinder_side, side_point);
    Vec3 on_side = reprojected(side, side_normal);
    float side_error = std::fabs(std::hypot(on_side.x - 1.0f, on_side.z - 1.0f) - surface.radius);
    EXPECT_LE(side_error, bound_size + side.own_rounding) << "distance from the axis − r = " << side_error;

    Vec3 cap_point{1.2f, 5.0f + off_surface, 0.9f};
    SurfaceAnchor cap = twinray::sse::surface_anchor(surface, twinray::sse::cylinder_top_cap, 1.0f, cap_point);
    Vec3 cap_normal = unit_outward(surface, twinray::sse::cylinder_top_cap, cap_point);
    float cap_error = std::fabs(reprojected(cap, cap_normal).y - 5.0f);
    EXPECT_LE(cap_error, cap.own_rounding) << "height above the cap = " << cap_error;
    EXPECT_EQ(cap_normal.y, 1.0f);
}

// The leaf table is made from the packet records once the scene's objects are given up (sse/compiled_scene.cpp).
template <typename Surface>
bool same_bits(const Surface& a, const Surface& b) {
    return std::memcmp(&a, &b, sizeof(Surface)) == 0;
}

TEST(SseSurface, EachRecordGivesBackItsSurfaceBitForBitWhereItsRadiusSquaredIsNormal) {
    twinray::SplitMix64 random(27);
    int checked = 0;
    for (int i = 0; i < 20000; ++i) {
        const scene::Vec3 center{random.uniform(-1e3, 1e3), random.uniform(-1e3, 1e3), random.uniform(-1e3, 1e3)};
        const double radius = std::pow(10.0, random.uniform(-18, 18));
        const float square = static_cast<float>(radius) * static_cast<float>(radius);
        if (!(square >= FLT_MIN && square <= FLT_MAX)) {
            continue;
        }
        const scene::Sphere sphere{center, radius};
        EXPECT_TRUE(
            same_bits(twinray::sse::surface_of(twinray::sse::make_shape(sphere)), twinray::sse::make_surface(sphere)))
            << "sphere of radius " << radius;
        const scene::Cylinder cylinder{center, center + scene::Vec3{radius, 2 * radius, -radius}, radius};
        EXPECT_TRUE(same_bits(twinray::sse::surface_of(twinray::sse::make_shape(cylinder)),
                              twinray::sse::make_surface(cylinder)))
            << "cylinder of radius " << radius;
        const scene::Box box{center, center + scene::Vec3{radius, radius, 2 * radius}};
        EXPECT_TRUE(
            same_bits(twinray::sse::surface_of(twinray::sse::make_shape(box)), twinray::sse::make_surface(box)));
        const scene::Plane plane{math::normalize(center), radius};
        EXPECT_TRUE(
            same_bits(twinray::sse::surface_of(twinray::sse::make_shape(plane)), twinray::sse::make_surface(plane)));
        ++checked;
    }
    EXPECT_GT(checked, 19000);
}

// Each leaf of a compiled scene, whether the scene was kept or given up, against what make_surface makes of its object.
template <typename Surface>
void expect_same_surface(const Surface& held, const Surface& made, const std::string& leaf) {
    EXPECT_TRUE(same_bits(held, made)) << leaf;
}
template <typename Inner>
void expect_same_surface(const twinray::sse::TransformedSurface<Inner>& held,
                         const twinray::sse::TransformedSurface<Inner>& made, const std::string& leaf) {
    EXPECT_TRUE(same_bits(held.inner(), made.inner()) && same_bits(held.to_world(), made.to_world())) << leaf;
}

void expect_leaves_of(const twinray::sse::LeafTable& leaves, const scene::Object& object, const scene::Scene& scene,
                      int& compared) {
    std::visit(
        [&](const auto& shape) {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (scene::is_primitive<S>) {
                const std::string leaf = scene.leaf_paths[static_cast<std::size_t>(object.leaf)];
                const twinray::sse::Leaf& entry = leaves[static_cast<std::size_t>(object.leaf)];
                const auto* held = std::get_if<twinray::sse::SurfaceOf<S>>(&entry.surface);
                ASSERT_NE(held, nullptr) << leaf << " holds another kind of surface";
                expect_same_surface(*held, twinray::sse::make_surface(shape), leaf);
                EXPECT_EQ(entry.material, object.material) << leaf;
                ++compared;
            } else {
                for (const scene::Object& child : shape.children) {
                    expect_leaves_of(leaves, child, scene, compared);
                }
            }
        },
        object.shape);
}

// Radii whose float squares are subnormal (1e-20) or infinite (1e20), and transformed primitives, have surfaces their
// records cannot give back: the compiler keeps them apart, at the top level and inside CSG.
TEST(SseSurface, EveryCompiledLeafHoldsBitForBitTheSurfaceItsObjectMakesWhetherTheSceneIsKeptOrGivenUp) {
    const scene::Scene scene = scene::parse_scene(R"({"format": "twinray-scene/1",
      "camera": {"eye": [0, 2, 30], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 50},
      "materials": {"red": {"color": [1, 0, 0]}, "glass": {"color": [1, 1, 1], "transmission": 0.8, "ior": 1.5}},
      "objects": [
        {"type": "plane", "normal": [0, 1, 0], "offset": -3},
        {"type": "sphere", "center": [1.25, 0.5, -2], "radius": 0.7, "material": "red"},
        {"type": "sphere", "center": [2, 0, 0], "radius": 1e-20},
        {"type": "sphere", "center": [0, 0, -1e21], "radius": 1e20, "material": "glass"},
        {"type": "cylinder", "base": [-3, 0, 0], "cap": [-3, 2, 0.5], "radius": 3e-20},
        {"type": "cylinder", "base": [3, 0, 0], "cap": [3, 1, 0], "radius": 0.25},
        {"type": "box", "min": [-1, -1, 4], "max": [0.5, 0.25, 5]},
        {"type": "sphere", "center": [0, 0, 0], "radius": 1, "transform": [{"scale": [2, 0.5, 1]}]},
        {"type": "difference", "material": "glass", "children": [
          {"type": "box", "min": [4, 0, 0], "max": [6, 2, 2]},
          {"type": "sphere", "center": [5, 1, 1], "radius": 1e-20},
          {"type": "cylinder", "base": [5, 0, 1], "cap": [5, 2, 1], "radius": 0.5,
           "transform": [{"scale": [1, 1, 3]}]}]}]})",
                                                  "sse_surface_test");
    for (twinray::Accel accel : {twinray::Accel::bvh, twinray::Accel::none}) {
        scene::Scene given_up = scene;
        const twinray::sse::CompiledScene kept = twinray::sse::compile(scene, accel);
        const twinray::sse::CompiledScene giving_up = twinray::sse::compile(given_up, accel, &given_up);
        EXPECT_TRUE(given_up.objects.empty() && given_up.leaf_paths.empty());
        int compared = 0;
        for (const scene::Object& object : scene.objects) {
            expect_leaves_of(kept.leaves, object, scene, compared);
            expect_leaves_of(giving_up.leaves, object, scene, compared);
        }
        EXPECT_EQ(compared, 2 * 11);
    }
}

}  // namespace
