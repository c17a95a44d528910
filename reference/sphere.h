// Sphere |p − c| = r.
#pragma once

#include "reference/ray.h"

#include <cmath>
#include <optional>
#include <utility>

namespace twinray::reference {

template <typename T>
struct SphereShape {
    Vec3<T> center;
    T radius{};
    int leaf = -1;
};

template <typename T>
SphereShape<T> make_shape(const scene::Sphere& sphere, int leaf) {
    return {Vec3<T>(sphere.center), static_cast<T>(sphere.radius), leaf};
}

// With f = o − c and unit d: t² + 2bt + c = 0, b = f·d, c = f·f − r².
// The discriminant is taken as r² − |f − b·d|² instead of b² − c, which cancels catastrophically once
// the sphere is far away relative to its radius (Haines et al., Ray Tracing Gems ch. 7). The roots use
// q = −b − sign(b)·√Δ, t = q and t = c/q, so neither subtracts nearly equal numbers.
template <typename T>
std::optional<Span<T>> span_of(const SphereShape<T>& sphere, const Ray<T>& ray) {
    Vec3<T> f = ray.origin - sphere.center;
    T b = dot(f, ray.direction);
    Vec3<T> perpendicular = f - b * ray.direction;
    T discriminant = sphere.radius * sphere.radius - dot(perpendicular, perpendicular);
    if (!(discriminant >= T(0))) {
        return std::nullopt;
    }
    T c = dot(f, f) - sphere.radius * sphere.radius;
    T q = -b - std::copysign(std::sqrt(discriminant), b);
    // q = 0 only for b = 0 and a zero discriminant: the origin touches the sphere, both roots are 0.
    T t0 = q;
    T t1 = q == T(0) ? T(0) : c / q;
    if (t0 > t1) {
        std::swap(t0, t1);
    }
    auto crossing = [&](T t) {
        return Crossing<T>{t, radial_normal(ray.at(t) - sphere.center, ray.direction), sphere.leaf};
    };
    return Span<T>{crossing(t0), crossing(t1)};
}

// p' = c + r·n̂ with n̂ the unit normal turned towards p (a CSG complement turns a crossing's normal): on the sphere
// within γ(5)·r (n̂ is unit within γ(4), times r) plus one rounding of the sum per component (√3·u·|p'|∞ ≤ γ(2)·|p'|∞).
// The next ray decides its side by the sign of |f|² − r² ≈ 2·r·distance, rounded within (γ(3) + 2u)·r² with f = o − c:
// a distance of γ(4)·r settles it. The origin's own rounding adds γ(2)·|p'|∞.
template <typename T>
SurfacePoint<T> surface_point(const SphereShape<T>& sphere, Vec3<T> point, Vec3<T> normal) {
    T distance = dot(normal, point - sphere.center);  // ±|p − c|: the normal lies along p − c
    T radius = distance < T(0) ? -sphere.radius : sphere.radius;
    math::SurfaceBounds<T> bounds = scene::surface_bounds_of_sphere(sphere.radius);
    T own_rounding = bounds.own_rounding.at(max_abs_component(point));
    Vec3<T> projected =
        std::fabs(std::fabs(distance) - sphere.radius) > own_rounding ? sphere.center + radius * normal : point;
    return {projected, bounds.spawn_offset.at(max_abs_component(projected))};
}

}  // namespace twinray::reference
