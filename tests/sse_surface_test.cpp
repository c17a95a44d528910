// Each SSE primitive header's surface at a hit, called directly (the stage a render reaches only through
// nearest_hit.h): a point measurably off the surface is re-projected onto it within the shared bound
// (scene::surface_bounds_of_*), and the outward normal points along the surface's true normal.
#include "sse/box.h"
#include "sse/cylinder.h"
#include "sse/plane.h"
#include "sse/sphere.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
