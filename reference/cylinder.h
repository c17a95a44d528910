// Solid capped cylinder: points within `radius` of the segment base→cap, between the two cap planes.
#pragma once

#include "reference/ray.h"

#include <cmath>
#include <optional>
#include <utility>

namespace twinray::reference {

template <typename T>
struct CylinderShape {
    Vec3<T> base;
    Vec3<T> axis;  // unit, from base towards cap
    T height{};    // |cap − base|
    T radius{};
    int leaf = -1;
};

// Axis and height are derived in the tracer's precision from its own end points.
template <typename T>
CylinderShape<T> make_shape(const scene::Cylinder& cylinder, int leaf) {
    Vec3<T> base(cylinder.base);
    Vec3<T> along = Vec3<T>(cylinder.cap) - base;
    return {base, normalize(along), length(along), static_cast<T>(cylinder.radius), leaf};
}

namespace cylinder_detail {

template <typename T>
Vec3<T> remove_axial(Vec3<T> v, Vec3<T> axis) {
    return v - dot(v, axis) * axis;
}

// The line's span inside the infinite cylinder, or nullopt. With the components perpendicular to the
// axis (f⊥ of o − base, d⊥ of d): A t² + 2 b t + c = 0, A = d⊥·d⊥, b = f⊥·d⊥, c = f⊥·f⊥ − r².
// b² − A c = A r² − |f⊥ × d⊥|² (Lagrange's identity) is the cancellation-free discriminant, the
// cylinder's analogue of the sphere's; the roots again use q = −b − sign(b)·√Δ: t = q/A and c/q.
template <typename T>
std::optional<std::pair<T, T>> side_span(const CylinderShape<T>& cylinder, const Ray<T>& ray) {
    Vec3<T> f = remove_axial(ray.origin - cylinder.base, cylinder.axis);
    Vec3<T> d = remove_axial(ray.direction, cylinder.axis);
    T a = dot(d, d);
    T c = dot(f, f) - cylinder.radius * cylinder.radius;
    T infinity = std::numeric_limits<T>::infinity();
    if (a == T(0)) {
        if (c < T(0)) {
            return std::pair{-infinity, infinity};
        }
        return std::nullopt;
    }
    Vec3<T> moment = cross(f, d);
    T discriminant = a * cylinder.radius * cylinder.radius - dot(moment, moment);
    if (!(discriminant >= T(0))) {
        return std::nullopt;
    }
    T b = dot(f, d);
    T q = -b - std::copysign(std::sqrt(discriminant), b);
    T t0 = q / a;
    T t1 = q == T(0) ? T(0) : c / q;
    if (t0 > t1) {
        std::swap(t0, t1);
    }
    return std::pair{t0, t1};
}

}  // namespace cylinder_detail

// The side span clipped to the slab between the cap planes (0 ≤ axial ≤ height). The crossing's
// normal is radial where the side bounds the span and ∓axis where a cap does.
template <typename T>
std::optional<Span<T>> span_of(const CylinderShape<T>& cylinder, const Ray<T>& ray) {
    auto side = cylinder_detail::side_span(cylinder, ray);
    if (!side) {
        return std::nullopt;
    }
    T axial_origin = dot(ray.origin - cylinder.base, cylinder.axis);
    T axial_direction = dot(ray.direction, cylinder.axis);
    T infinity = std::numeric_limits<T>::infinity();
    T slab_near = -infinity;
    T slab_far = infinity;
    Vec3<T> near_cap_normal;
    Vec3<T> far_cap_normal;
    if (axial_direction == T(0)) {
        if (!(axial_origin > T(0) && axial_origin < cylinder.height)) {
            return std::nullopt;
        }
    } else {
        T t_base = -axial_origin / axial_direction;
        T t_cap = (cylinder.height - axial_origin) / axial_direction;
        bool towards_cap = axial_direction > T(0);
        slab_near = towards_cap ? t_base : t_cap;
        slab_far = towards_cap ? t_cap : t_base;
        near_cap_normal = towards_cap ? -cylinder.axis : cylinder.axis;
        far_cap_normal = -near_cap_normal;
    }
    auto side_crossing = [&](T t) {
        Vec3<T> radial = cylinder_detail::remove_axial(ray.at(t) - cylinder.base, cylinder.axis);
        return Crossing<T>{t, radial_normal(radial, ray.direction), cylinder.leaf};
    };
    Crossing<T> enter =
        slab_near > side->first ? Crossing<T>{slab_near, near_cap_normal, cylinder.leaf} : side_crossing(side->first);
    Crossing<T> exit =
        slab_far < side->second ? Crossing<T>{slab_far, far_cap_normal, cylinder.leaf} : side_crossing(side->second);
    if (!(enter.t <= exit.t)) {
        return std::nullopt;
    }
    return Span<T>{enter, exit};
}

// On a cap (the normal along the axis; the nearer cap), p' = p − (h − h_cap)·axis with h = (p − base)·axis;
// on the side, p' = base + h·axis + r·n̂ with n̂ the unit radial normal turned towards p (a CSG complement
// turns a crossing's normal). Either way p' is within γ(5)·(r + height) of the surface plus the rounding of
// the sums (γ(2)·|p'|∞): h is rounded within γ(4)·|p − base| ≤ γ(4)·(r + height). The next ray decides its
// side by |f⊥|² − r² (f⊥ rounded within γ(5)·(r + height)) or by the cap's h − h_cap (within γ(4)·(r +
// height)): γ(7)·(r + height) more settles it, and the origin's own rounding adds γ(2)·|p'|∞.
template <typename T>
SurfacePoint<T> surface_point(const CylinderShape<T>& cylinder, Vec3<T> point, Vec3<T> normal) {
    Vec3<T> from_base = point - cylinder.base;
    T axial = dot(from_base, cylinder.axis);
    math::SurfaceBounds<T> bounds = scene::surface_bounds_of_cylinder(cylinder.radius, cylinder.height);
    T own_rounding = bounds.own_rounding.at(max_abs_component(point));
    Vec3<T> projected = point;
    if (std::fabs(dot(normal, cylinder.axis)) > T(0.5)) {
        T cap_axial = std::fabs(axial - cylinder.height) < std::fabs(axial) ? cylinder.height : T(0);
        if (std::fabs(axial - cap_axial) > own_rounding) {
            projected = point - (axial - cap_axial) * cylinder.axis;
        }
    } else {
        T distance = dot(normal, from_base);  // ±(distance from the axis): the normal is radial
        T radius = distance < T(0) ? -cylinder.radius : cylinder.radius;
        if (std::fabs(std::fabs(distance) - cylinder.radius) > own_rounding) {
            projected = cylinder.base + axial * cylinder.axis + radius * normal;
        }
    }
    return {projected, bounds.spawn_offset.at(max_abs_component(projected))};
}

}  // namespace twinray::reference
