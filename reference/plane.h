// Plane n·p = d (n unit). Its solid is the half-space n·p < d, so a line crossing it is inside on one
// side: the span is half-infinite.
#pragma once

#include "reference/ray.h"

#include <cmath>
#include <optional>

namespace twinray::reference {

template <typename T>
struct PlaneShape {
    Vec3<T> normal;
    T offset{};
    int leaf = -1;
};

template <typename T>
PlaneShape<T> make_shape(const scene::Plane& plane, int leaf) {
    return {Vec3<T>(plane.normal), static_cast<T>(plane.offset), leaf};
}

// n·(o + t·d) = d  =>  t = (d − n·o) / (n·d). A ray parallel to the plane is inside everywhere or
// nowhere; one running exactly within the plane is not inside (the inside is open).
template <typename T>
std::optional<Span<T>> span_of(const PlaneShape<T>& plane, const Ray<T>& ray) {
    T approach = dot(plane.normal, ray.direction);
    T height = plane.offset - dot(plane.normal, ray.origin);  // > 0: origin inside
    if (approach == T(0)) {
        if (height > T(0)) {
            return Span<T>{infinitely_far(T(-1)), infinitely_far(T(1))};
        }
        return std::nullopt;
    }
    Crossing<T> surface{height / approach, plane.normal, plane.leaf};
    if (approach > T(0)) {
        return Span<T>{infinitely_far(T(-1)), surface};
    }
    return Span<T>{surface, infinitely_far(T(1))};
}

// p' = p + (d − n·p)·n: n·p is rounded within γ(3)·|n|₁·|p|∞ ≤ γ(6)·|p|∞ (|n|₁ ≤ √3), the sum once more
// per component, so p' is within γ(7)·|p'|∞ + γ(1)·|d| of the plane wherever p was along the ray. The
// next ray decides its side by the sign of d − n·o, rounded within the same γ(6)·|o|∞ + γ(1)·|d|; its
// origin's rounding adds γ(2)·|p'|∞. Projected only where d − n·p exceeds two roundings of p
// (γ(2)·|p|∞ + γ(1)·|d|): a point that close is already within the projection's own error of the plane.
template <typename T>
SurfacePoint<T> surface_point(const PlaneShape<T>& plane, Vec3<T> point, Vec3<T> /*normal: the plane's own*/) {
    T height = plane.offset - dot(plane.normal, point);
    math::SurfaceBounds<T> bounds = scene::surface_bounds_of_plane(plane.offset);
    T own_rounding = bounds.own_rounding.at(max_abs_component(point));
    Vec3<T> projected = std::fabs(height) > own_rounding ? point + height * plane.normal : point;
    return {projected, bounds.spawn_offset.at(max_abs_component(projected))};
}

}  // namespace twinray::reference
