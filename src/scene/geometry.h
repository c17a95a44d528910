// What the scene model knows of each primitive's geometry, shared by both tracers and the tools: bounds,
// moving and rounding a primitive, and the rounding bounds of its surface in a tracer's precision. One
// section per primitive, in the order of scene::PrimitiveTypes; intersection formulas are not here (each
// tracer writes its own).
#pragma once

#include "math/rounding.h"
#include "scene/scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace twinray::scene {

// An axis-aligned box, ±∞ where a solid is unbounded.
struct Bounds {
    Vec3 low, high;
};

struct BoundingSphere {
    Vec3 center;
    double radius;
};

// p·scale + shift: the move of numerics' scale and distance cases, and the SSE tracer's re-basing on its
// origin (scale 1, shift −origin: each coordinate one double subtraction).
inline Vec3 moved(const Vec3& p, double scale, const Vec3& shift) {
    return {p[0] * scale + shift[0], p[1] * scale + shift[1], p[2] * scale + shift[2]};
}

// The nearest float, as a double. Out of line on purpose: GCC 12.2's SLP vectorizer at -O2 drops the round
// trip double → float → double of two neighbouring values and copies the doubles unchanged (seen in
// `{static_cast<float>(v[0]), static_cast<float>(v[1]), …}`); a call per value keeps them apart.
double rounded_to_float(double value);

inline Vec3 rounded_to_float(const Vec3& v) {
    return {rounded_to_float(v[0]), rounded_to_float(v[1]), rounded_to_float(v[2])};
}

inline Bounds around(const Vec3& a, const Vec3& b, double pad) {
    Bounds out;
    for (int axis = 0; axis < 3; ++axis) {
        out.low[axis] = std::min(a[axis], b[axis]) - pad;
        out.high[axis] = std::max(a[axis], b[axis]) + pad;
    }
    return out;
}

// The sphere around the segment a–b widened by `pad`: centre the midpoint, radius √(|b − a|²/4 + pad²).
inline BoundingSphere sphere_around(const Vec3& a, const Vec3& b, double pad) {
    BoundingSphere out{};
    double half_length_squared = 0;
    for (int i = 0; i < 3; ++i) {
        out.center[i] = 0.5 * (a[i] + b[i]);
        half_length_squared += 0.25 * (b[i] - a[i]) * (b[i] - a[i]);
    }
    out.radius = std::sqrt(half_length_squared + pad * pad);
    return out;
}

inline double largest_coordinate(const Vec3& v) {
    return std::max({std::fabs(v[0]), std::fabs(v[1]), std::fabs(v[2])});
}

// Plane ------------------------------------------------------------------------------------------------

inline Bounds bounds(const Plane&) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    return {{-inf, -inf, -inf}, {inf, inf, inf}};
}
inline BoundingSphere bounding_sphere(const Plane&) {
    return {{0, 0, 0}, std::numeric_limits<double>::infinity()};
}
// n·(p·s + shift) = s·d + n·shift.
inline Plane moved(const Plane& plane, double scale, const Vec3& shift) {
    return {plane.normal, plane.offset * scale + math::dot(plane.normal, shift)};
}
inline Plane rounded_to_float(const Plane& plane) {
    return {rounded_to_float(plane.normal), rounded_to_float(plane.offset)};
}
inline double largest_coordinate(const Plane& plane) {
    return std::fabs(plane.offset);
}
// The radius of curvature at a point of the surface: a normal turns by lateral/radius as the point moves by
// `lateral` (attribution's bands); flat faces do not turn.
inline double curvature_radius(const Plane&, const Vec3&) {
    return std::numeric_limits<double>::infinity();
}
// own rounding γ(2)·|p|∞ + γ(1)·|d|, spawn offset γ(15)·|p'|∞ + γ(2)·|d| (reference/plane.h derives them).
template <typename T>
math::SurfaceBounds<T> surface_bounds_of_plane(T offset) {
    using math::rounding_bound;
    return {{rounding_bound<T>(1) * std::fabs(offset), rounding_bound<T>(2)},
            {rounding_bound<T>(2) * std::fabs(offset), rounding_bound<T>(15)}};
}

// Sphere -----------------------------------------------------------------------------------------------

inline Bounds bounds(const Sphere& sphere) {
    return around(sphere.center, sphere.center, sphere.radius);
}
inline BoundingSphere bounding_sphere(const Sphere& sphere) {
    return {sphere.center, sphere.radius};
}
inline Sphere moved(const Sphere& sphere, double scale, const Vec3& shift) {
    return {moved(sphere.center, scale, shift), sphere.radius * scale};
}
inline Sphere rounded_to_float(const Sphere& sphere) {
    return {rounded_to_float(sphere.center), rounded_to_float(sphere.radius)};
}
inline double largest_coordinate(const Sphere& sphere) {
    return std::max(largest_coordinate(sphere.center), sphere.radius);
}
inline double curvature_radius(const Sphere& sphere, const Vec3&) {
    return sphere.radius;
}
// own rounding γ(5)·r + γ(2)·|p|∞, spawn offset γ(9)·r + γ(4)·|p'|∞ (reference/sphere.h derives them).
template <typename T>
math::SurfaceBounds<T> surface_bounds_of_sphere(T radius) {
    using math::rounding_bound;
    return {{rounding_bound<T>(5) * radius, rounding_bound<T>(2)},
            {rounding_bound<T>(9) * radius, rounding_bound<T>(4)}};
}

// Cylinder ---------------------------------------------------------------------------------------------

// End points ± radius on every axis.
inline Bounds bounds(const Cylinder& cylinder) {
    return around(cylinder.base, cylinder.cap, cylinder.radius);
}
inline BoundingSphere bounding_sphere(const Cylinder& cylinder) {
    return sphere_around(cylinder.base, cylinder.cap, cylinder.radius);
}
inline Cylinder moved(const Cylinder& cylinder, double scale, const Vec3& shift) {
    return {moved(cylinder.base, scale, shift), moved(cylinder.cap, scale, shift), cylinder.radius * scale};
}
inline Cylinder rounded_to_float(const Cylinder& cylinder) {
    return {rounded_to_float(cylinder.base), rounded_to_float(cylinder.cap), rounded_to_float(cylinder.radius)};
}
inline double largest_coordinate(const Cylinder& cylinder) {
    return std::max(largest_coordinate(cylinder.base), largest_coordinate(cylinder.cap));
}
// The side's radius; a flat cap's none: the point is on a cap where it lies nearer a cap's plane than the side.
inline double curvature_radius(const Cylinder& cylinder, const Vec3& point) {
    Vec3 axis = cylinder.cap - cylinder.base;
    double length = std::sqrt(math::dot(axis, axis));
    double along = math::dot(point - cylinder.base, axis) / length;
    Vec3 radial = (point - cylinder.base) - (along / length) * axis;
    double from_side = std::fabs(std::sqrt(math::dot(radial, radial)) - cylinder.radius);
    double from_cap = std::min(std::fabs(along), std::fabs(length - along));
    return from_cap < from_side ? std::numeric_limits<double>::infinity() : cylinder.radius;
}
// own rounding γ(5)·(r + h) + γ(2)·|p|∞, spawn offset γ(12)·(r + h) + γ(4)·|p'|∞ (reference/cylinder.h).
template <typename T>
math::SurfaceBounds<T> surface_bounds_of_cylinder(T radius, T height) {
    using math::rounding_bound;
    return {{rounding_bound<T>(5) * (radius + height), rounding_bound<T>(2)},
            {rounding_bound<T>(12) * (radius + height), rounding_bound<T>(4)}};
}

// Box --------------------------------------------------------------------------------------------------

inline Bounds bounds(const Box& box) {
    return around(box.min, box.max, 0.0);
}
inline BoundingSphere bounding_sphere(const Box& box) {
    return sphere_around(box.min, box.max, 0.0);
}
inline Box moved(const Box& box, double scale, const Vec3& shift) {
    return {moved(box.min, scale, shift), moved(box.max, scale, shift)};
}
inline Box rounded_to_float(const Box& box) {
    return {rounded_to_float(box.min), rounded_to_float(box.max)};
}
inline double curvature_radius(const Box&, const Vec3&) {
    return std::numeric_limits<double>::infinity();
}
inline double largest_coordinate(const Box& box) {
    return std::max(largest_coordinate(box.min), largest_coordinate(box.max));
}
// The face coordinate is set exactly (no own rounding); spawn offset γ(3)·|p'|∞ (reference/box.h).
template <typename T>
math::SurfaceBounds<T> surface_bounds_of_box() {
    return {{T(0), T(0)}, {T(0), math::rounding_bound<T>(3)}};
}

// Mesh -------------------------------------------------------------------------------------------------
// Not in PrimitiveTypes: a mesh is a surface of many triangles, not a solid (scene.h).

inline Bounds bounds(const MeshData& mesh, const std::array<std::uint32_t, 3>& triangle) {
    Bounds out = around(mesh.vertices[triangle[0]], mesh.vertices[triangle[1]], 0.0);
    for (int axis = 0; axis < 3; ++axis) {
        out.low[axis] = std::min(out.low[axis], mesh.vertices[triangle[2]][axis]);
        out.high[axis] = std::max(out.high[axis], mesh.vertices[triangle[2]][axis]);
    }
    return out;
}
// The triangles with no area, ascending: a repeated index, or three collinear vertices (decided exactly, so that
// both tracers, which skip them, agree on which they are). What the loader puts in MeshData::degenerate.
std::vector<std::uint32_t> degenerate_triangles(const MeshData& mesh);
// Calls visit(index) for each triangle that can be hit, ascending: all but those in `degenerate`.
template <typename Visit>
void for_each_live_triangle(const MeshData& mesh, Visit&& visit) {
    auto next_degenerate = mesh.degenerate.begin();
    for (std::uint32_t i = 0; i < mesh.triangles.size(); ++i) {
        if (next_degenerate != mesh.degenerate.end() && *next_degenerate == i) {
            ++next_degenerate;
            continue;
        }
        visit(i);
    }
}
// The weights of the triangle's vertices 0, 1, 2 at `point`'s projection onto its plane: the sub-triangles'
// areas along its normal over the whole, so they sum to 1 and all lie in [0, 1] inside. In double, from the
// file's vertices: both tracers' hit points are weighed the same way (probe).
std::array<double, 3> barycentrics(const MeshData& mesh, std::uint32_t triangle, const Vec3& point);
// Vertices moved, normals kept (a move is a scale and a translation).
Mesh moved(const Mesh& mesh, double scale, const Vec3& shift);
double largest_coordinate(const Mesh& mesh);
// own rounding γ(6)·e + γ(3)·|p|∞, spawn offset γ(16)·e + γ(5)·|p'|∞ with e the longest edge
// (reference/triangle.h derives them).
template <typename T>
math::SurfaceBounds<T> surface_bounds_of_triangle(T longest_edge) {
    using math::rounding_bound;
    return {{rounding_bound<T>(6) * longest_edge, rounding_bound<T>(3)},
            {rounding_bound<T>(16) * longest_edge, rounding_bound<T>(5)}};
}

// Any object ---------------------------------------------------------------------------------------------

// A conservative bound: an intersection by the overlap of its children's bounds, a difference by its first
// child's, a union by the hull of all.
Bounds bounds(const Object& object);
// Every primitive moved (p·scale + shift, lengths times scale).
void move(Object& object, double scale, const Vec3& shift);
// The whole scene moved so: camera, lights, every object and every mesh.
Scene moved(const Scene& scene, double scale, const Vec3& shift);
// Every coordinate and length rounded to float: the geometry a float tracer holds.
void round_to_float(Object& object);
// The largest |coordinate| (and sphere radius, plane offset) of the object's primitives.
double largest_coordinate(const Object& object);

}  // namespace twinray::scene
