// The truth the extremes are measured against: each primitive's span, normal and distance to its surface
// in long double, from the scene's double parameters. A third, independent computation (textbook roots,
// no cancellation trick needed at 64 bits of mantissa), so neither tracer judges itself. One section per
// primitive, in the order of scene::PrimitiveTypes; a primitive missing here does not compile.
#include "numerics/numerics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <variant>

namespace twinray::numerics {
namespace {

using Real = long double;
using Point = math::Vec3<Real>;

constexpr Real infinity = std::numeric_limits<Real>::infinity();

Point to_point(const Vec3d& v) {
    return Point(v);
}

Vec3d unit(const Point& v) {
    Real l = math::length(v);
    return {static_cast<double>(v.x / l), static_cast<double>(v.y / l), static_cast<double>(v.z / l)};
}

// Roots of a·t² + 2·b·t + c = 0 without cancellation.
void roots(Real a, Real b, Real c, ExactSpan& span) {
    Real discriminant = b * b - a * c;
    if (!(discriminant >= 0) || a == 0) {
        return;
    }
    Real q = -b - std::copysign(std::sqrt(discriminant), b);
    Real t0 = q / a, t1 = q == 0 ? 0 : c / q;
    span = {true, std::min(t0, t1), std::max(t0, t1)};
}

// Plane ---------------------------------------------------------------------------------------------------

ExactSpan span_of(const scene::Plane& plane, const Point& o, const Point& d) {
    Point n = to_point(plane.normal);
    Real approach = math::dot(n, d);
    Real height = plane.offset * math::length(n) - math::dot(n, o);
    if (approach == 0) {
        return height > 0 ? ExactSpan{true, -infinity, infinity} : ExactSpan{};
    }
    Real t = height / approach;
    return approach > 0 ? ExactSpan{true, -infinity, t} : ExactSpan{true, t, infinity};
}
Vec3d normal_at(const scene::Plane& plane, const Point&) {
    return unit(to_point(plane.normal));
}
Real distance_to(const scene::Plane& plane, const Point& p) {
    Point n = to_point(plane.normal);
    return std::fabs(math::dot(n, p) / math::length(n) - plane.offset);
}

// Sphere --------------------------------------------------------------------------------------------------

ExactSpan span_of(const scene::Sphere& sphere, const Point& o, const Point& d) {
    Point f = o - to_point(sphere.center);
    ExactSpan span;
    roots(math::dot(d, d), math::dot(f, d), math::dot(f, f) - Real(sphere.radius) * sphere.radius, span);
    return span;
}
Vec3d normal_at(const scene::Sphere& sphere, const Point& p) {
    return unit(p - to_point(sphere.center));
}
Real distance_to(const scene::Sphere& sphere, const Point& p) {
    return std::fabs(math::length(p - to_point(sphere.center)) - sphere.radius);
}

// Cylinder ------------------------------------------------------------------------------------------------

// A cylinder's base, unit axis and height, in long double.
struct CylinderFrame {
    Point base, axis;
    Real height;
};
CylinderFrame frame_of(const scene::Cylinder& cylinder) {
    Point base = to_point(cylinder.base);
    Point along = to_point(cylinder.cap) - base;
    Real height = math::length(along);
    return {base, (1 / height) * along, height};
}

ExactSpan span_of(const scene::Cylinder& cylinder, const Point& o, const Point& d) {
    auto [base, axis, height] = frame_of(cylinder);
    Point f = o - base;
    Point f_perp = f - math::dot(f, axis) * axis;
    Point d_perp = d - math::dot(d, axis) * axis;
    Real c = math::dot(f_perp, f_perp) - Real(cylinder.radius) * cylinder.radius;
    ExactSpan side;
    if (math::dot(d_perp, d_perp) == 0) {
        side = c < 0 ? ExactSpan{true, -infinity, infinity} : ExactSpan{};
    } else {
        roots(math::dot(d_perp, d_perp), math::dot(f_perp, d_perp), c, side);
    }
    Real axial = math::dot(f, axis), speed = math::dot(d, axis);
    if (speed == 0) {
        return axial > 0 && axial < height ? side : ExactSpan{};
    }
    Real t_base = -axial / speed, t_cap = (height - axial) / speed;
    side.enter = std::max(side.enter, std::min(t_base, t_cap));
    side.exit = std::min(side.exit, std::max(t_base, t_cap));
    side.valid = side.valid && side.enter <= side.exit;
    return side;
}
Vec3d normal_at(const scene::Cylinder& cylinder, const Point& p) {
    auto [base, axis, height] = frame_of(cylinder);
    Point f = p - base;
    Real axial = math::dot(f, axis);
    Point radial = f - axial * axis;
    Real to_cap = std::min(std::fabs(axial), std::fabs(height - axial));
    return to_cap < std::fabs(math::length(radial) - cylinder.radius) ? unit(axis) : unit(radial);
}
Real distance_to(const scene::Cylinder& cylinder, const Point& p) {
    auto [base, axis, height] = frame_of(cylinder);
    Point f = p - base;
    Real axial = math::dot(f, axis);
    Real radial = math::length(f - axial * axis);
    if (axial >= 0 && axial <= height && radial <= cylinder.radius) {
        return std::min({axial, height - axial, cylinder.radius - radial});
    }
    Real outside_axially = std::max({-axial, axial - height, Real(0)});
    Real outside_radially = std::max(radial - cylinder.radius, Real(0));
    return std::hypot(outside_axially, outside_radially);
}

// Box -----------------------------------------------------------------------------------------------------

ExactSpan span_of(const scene::Box& box, const Point& o, const Point& d) {
    ExactSpan span{true, -infinity, infinity};
    for (int axis = 0; axis < 3; ++axis) {
        if (d[axis] == 0) {
            span.valid = span.valid && o[axis] > box.min[axis] && o[axis] < box.max[axis];
            continue;
        }
        Real t_min = (box.min[axis] - o[axis]) / d[axis], t_max = (box.max[axis] - o[axis]) / d[axis];
        span.enter = std::max(span.enter, std::min(t_min, t_max));
        span.exit = std::min(span.exit, std::max(t_min, t_max));
    }
    span.valid = span.valid && span.enter <= span.exit;
    return span;
}
Vec3d normal_at(const scene::Box& box, const Point& p) {
    int nearest_axis = 0;
    Real nearest = infinity;
    for (int axis = 0; axis < 3; ++axis) {
        Real gap = std::min(std::fabs(p[axis] - box.min[axis]), std::fabs(p[axis] - box.max[axis]));
        if (gap < nearest) {
            nearest = gap;
            nearest_axis = axis;
        }
    }
    Vec3d n{0, 0, 0};
    n[nearest_axis] = 1;
    return n;
}
Real distance_to(const scene::Box& box, const Point& p) {
    Real inside = infinity;
    Real outside_squared = 0;
    for (int axis = 0; axis < 3; ++axis) {
        Real below = box.min[axis] - p[axis];
        Real above = p[axis] - box.max[axis];
        inside = std::min(inside, std::max(below, above) <= 0 ? -std::max(below, above) : Real(0));
        Real out = std::max({below, above, Real(0)});
        outside_squared += out * out;
    }
    return outside_squared > 0 ? std::sqrt(outside_squared) : inside;
}

// Transformed ---------------------------------------------------------------------------------------------

// The map in long double, its inverse computed here from L rather than rounded from the scene's double one.
math::Transform<Real> exact_map(const scene::Transform& to_world) {
    math::Transform<Real> m = math::Transform<Real>::from(to_world);
    m.inverse = math::inverse_of(m.linear);
    return m;
}

// o' + t·d' = L⁻¹·(o + t·d − t₀): the same t along both lines, whatever d' 's length.
template <typename S>
ExactSpan span_of(const scene::Transformed<S>& primitive, const Point& o, const Point& d) {
    math::Transform<Real> m = exact_map(primitive.to_world());
    return span_of(primitive.shape(), m.point_to_object(o), m.direction_to_object(d));
}
template <typename S>
Vec3d normal_at(const scene::Transformed<S>& primitive, const Point& p) {
    math::Transform<Real> m = exact_map(primitive.to_world());
    return unit(m.normal_to_world(Point(normal_at(primitive.shape(), m.point_to_object(p)))));
}
// To first order in the distance, which is all a hit point's error is: the object-space distance φ over the
// rate |L⁻ᵀ·n̂ₒ| at which φ grows per unit of world distance along the surface's normal. A point where the
// primitive has no normal (a sphere's very centre, where a float hit far from the origin can round to) gets
// φ/‖L⁻¹‖_F, which the world distance is never below.
template <typename S>
Real distance_to(const scene::Transformed<S>& primitive, const Point& p) {
    math::Transform<Real> m = exact_map(primitive.to_world());
    Point object_point = m.point_to_object(p);
    Real distance = distance_to(primitive.shape(), object_point);
    Real rate = math::length(m.normal_to_world(Point(normal_at(primitive.shape(), object_point))));
    return rate > 0 && std::isfinite(rate) ? distance / rate : distance / math::frobenius_norm(m.inverse);
}

// A CSG object is not a primitive: these queries take leaves only, and a CSG object answers `none`.
template <typename Query, typename Result>
Result on_primitive(const scene::Object& object, Query&& query, Result none) {
    return std::visit(
        [&](const auto& shape) -> Result {
            if constexpr (scene::is_primitive<std::decay_t<decltype(shape)>>) {
                return query(shape);
            } else {
                return none;
            }
        },
        object.shape);
}

}  // namespace

ExactSpan exact_span(const scene::Object& primitive, const Vec3d& origin, const Vec3d& direction) {
    return on_primitive(
        primitive, [&](const auto& shape) { return span_of(shape, to_point(origin), to_point(direction)); },
        ExactSpan{});
}

Vec3d exact_normal(const scene::Object& primitive, const Vec3d& point) {
    return on_primitive(
        primitive, [&](const auto& shape) { return normal_at(shape, to_point(point)); }, Vec3d{});
}

long double distance_to_surface(const scene::Object& primitive, const Vec3d& point) {
    return on_primitive(
        primitive, [&](const auto& shape) { return distance_to(shape, to_point(point)); },
        std::numeric_limits<Real>::quiet_NaN());
}

}  // namespace twinray::numerics
