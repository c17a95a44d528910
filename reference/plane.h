// Plane n·p = d (n unit). Its solid is the half-space n·p < d, so a line crossing it is inside on one
// side: the span is half-infinite.
#pragma once

#include "reference/ray.h"

#include <optional>

namespace twinray::reference {

template <typename T>
struct PlaneShape {
    Vec3<T> normal;
    T offset{};
    int leaf = -1;
};

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

}  // namespace twinray::reference
