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
#include <memory>
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

// Transformed ------------------------------------------------------------------------------------------
// A primitive in object space and its transform to the world (scene.h). Each function is the primitive's own,
// carried through the transform.

// L·p + t in double: each coordinate within γ(4)·(‖L‖∞·|p|∞ + |t|∞) of the exact map.
inline double placement_rounding(const Transform& m, double object_coordinate) {
    return math::rounding_bound<double>(4) *
           (math::row_sum_norm(m.linear) * object_coordinate + largest_coordinate(m.translation));
}
// The box around an object-space box's eight corners, placed, and widened by their rounding.
inline Bounds placed_bounds(const Bounds& inner, const Transform& to_world) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (!math::is_finite(inner.low) || !math::is_finite(inner.high)) {
        return {{-inf, -inf, -inf}, {inf, inf, inf}};  // a turn makes any unbounded axis unbounded along all three
    }
    Bounds out{{inf, inf, inf}, {-inf, -inf, -inf}};
    for (int corner = 0; corner < 8; ++corner) {
        Vec3 p{(corner & 1) ? inner.high.x : inner.low.x, (corner & 2) ? inner.high.y : inner.low.y,
               (corner & 4) ? inner.high.z : inner.low.z};
        Vec3 placed = to_world.point_to_world(p);
        for (int axis = 0; axis < 3; ++axis) {
            out.low[axis] = std::min(out.low[axis], placed[axis]);
            out.high[axis] = std::max(out.high[axis], placed[axis]);
        }
    }
    double pad = placement_rounding(to_world, std::max(largest_coordinate(inner.low), largest_coordinate(inner.high)));
    return around(out.low, out.high, pad);
}
template <typename S>
Bounds bounds(const Transformed<S>& primitive) {
    return placed_bounds(bounds(primitive.shape()), primitive.to_world());
}
// ‖L‖_F bounds how far L stretches any radius.
template <typename S>
BoundingSphere bounding_sphere(const Transformed<S>& primitive) {
    const BoundingSphere inner = bounding_sphere(primitive.shape());
    double stretch = math::frobenius_norm(primitive.to_world().linear);
    return {primitive.to_world().point_to_world(inner.center),
            stretch * inner.radius * (1 + math::rounding_bound<double>(8)) +
                placement_rounding(primitive.to_world(), largest_coordinate(inner.center))};
}
// p·s + shift of a placed point is (s·L)·x + (s·t + shift): the object-space primitive stays.
template <typename S>
Transformed<S> moved(const Transformed<S>& primitive, double scale, const Vec3& shift) {
    Transform m = primitive.to_world();
    for (int i = 0; i < 3; ++i) {
        m.linear.row[i] = scale * m.linear.row[i];
        m.inverse.row[i] = m.inverse.row[i] / scale;
    }
    m.translation = moved(m.translation, scale, shift);
    return Transformed<S>(primitive.shape(), m);
}
template <typename S>
Transformed<S> rounded_to_float(const Transformed<S>& primitive) {
    Transform m = primitive.to_world();
    for (int i = 0; i < 3; ++i) {
        m.linear.row[i] = rounded_to_float(m.linear.row[i]);
        m.inverse.row[i] = rounded_to_float(m.inverse.row[i]);
    }
    m.translation = rounded_to_float(m.translation);
    return Transformed<S>(rounded_to_float(primitive.shape()), m);
}
template <typename S>
double largest_coordinate(const Transformed<S>& primitive) {
    const Transform& m = primitive.to_world();
    return largest_coordinate(m.translation) + math::row_sum_norm(m.linear) * largest_coordinate(primitive.shape());
}
// The object's radius at the point, shrunk by the most the transform can bend it: a circle of radius r becomes
// an ellipse whose tightest radius is r·σ_min²/σ_max, and σ_min ≥ 1/‖L⁻¹‖_F, σ_max ≤ ‖L‖_F.
template <typename S>
double curvature_radius(const Transformed<S>& primitive, const Vec3& point) {
    const Transform& m = primitive.to_world();
    double shrink = math::frobenius_norm(m.inverse);
    return curvature_radius(primitive.shape(), m.point_to_object(point)) /
           (shrink * shrink * math::frobenius_norm(m.linear));
}

// The norms of a transform that its rounding bounds need, in T, rounded up.
template <typename T>
struct TransformNorms {
    T stretch;       // ‖L‖_F ≥ σ_max(L)
    T shrink;        // ‖L⁻¹‖_F ≥ 1/σ_min(L)
    T rows;          // ‖L‖∞
    T inverse_rows;  // ‖L⁻¹‖∞
    T translation;   // |t|∞
};
template <typename T>
TransformNorms<T> transform_norms(const Transform& m) {
    // The norm's own rounding in double (a few ulps), then rounded up to T.
    auto up = [](double v) { return math::rounded_up<T>(v * (1 + math::rounding_bound<double>(8))); };
    return {up(math::frobenius_norm(m.linear)), up(math::frobenius_norm(m.inverse)), up(math::row_sum_norm(m.linear)),
            up(math::row_sum_norm(m.inverse)), up(largest_coordinate(m.translation))};
}
// What a tracer keeps beside a transformed primitive's own record, in its precision T: the primitive as that tracer
// holds it (its shape or its surface), the transform and its norms. Held apart and shared by copies, as
// Transformed is, so that a tracer's per-primitive variants keep their plain size.
template <typename T, typename Inner>
class TransformedRecord {
public:
    TransformedRecord(const Inner& inner, const Transform& to_world)
        : placed_(std::make_shared<const Placed>(
              Placed{inner, math::Transform<T>::from(to_world), transform_norms<T>(to_world)})) {}

    const Inner& inner() const { return placed_->inner; }
    const math::Transform<T>& to_world() const { return placed_->to_world; }
    const TransformNorms<T>& norms() const { return placed_->norms; }

private:
    struct Placed {
        Inner inner;
        math::Transform<T> to_world;
        TransformNorms<T> norms;
    };
    std::shared_ptr<const Placed> placed_;
};
// How far off a transformed primitive's surface its secondary rays start: the object-space offset
// `object_offset` of the re-projected point p'ₒ (|p'ₒ|∞ = `object_point`), carried to the world point p'_w
// (|p'_w|∞ = `world_point`). reference/transformed.h derives it. T is the precision S or, for several hits at once
// (the SSE tracer's four lanes), a vector of it: each lane rounds as S alone would.
template <typename T, typename S = T>
T transformed_spawn_offset(const TransformNorms<T>& n, T object_offset, T object_point, T world_point) {
    auto gamma = [](int count) { return T(math::rounding_bound<S>(count)); };
    const T root3 = T(S(1.7320509));  // √3 rounded up: |v|₂ ≤ √3·|v|∞
    T back = gamma(4) * (n.rows * object_point + n.translation) + gamma(2) * world_point;
    T forward = gamma(5) * n.inverse_rows * (world_point + n.translation);
    // The next origin is p'_w + δ·n̂, so the forward rounding grows with δ too: δ = A + B·δ, δ = A/(1 − B), and
    // B ≤ √3·γ(5)·κ stays below 0.06 in float at the condition limit.
    T fixed = n.stretch * (object_offset + root3 * (forward + n.shrink * back));
    T growth = n.stretch * root3 * gamma(5) * n.inverse_rows;
    return (T(1) + gamma(8)) * fixed / (T(1) - growth);
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
// The box of every vertex (an instance's shape's, in its own space).
Bounds vertex_bounds(const MeshData& mesh);
// An instance's placement followed by the move (p·scale + shift).
Placement moved(const Placement& placement, double scale, const Vec3& shift);
// Vertices moved, normals kept (a move is a scale and a translation); an instance's placement moved instead.
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
// The whole scene moved so: camera, lights, every object, mesh and instance (shapes stay in their own space).
Scene moved(const Scene& scene, double scale, const Vec3& shift);
// Every coordinate and length rounded to float: the geometry a float tracer holds.
void round_to_float(Object& object);
// The largest |coordinate| (and sphere radius, plane offset) of the object's primitives.
double largest_coordinate(const Object& object);

}  // namespace twinray::scene
