// Rays, hits, and the spans a ray's line spends inside a solid (the currency of CSG).
#pragma once

#include "reference/vec3.h"

#include <limits>
#include <vector>

namespace twinray::reference {

// `direction` is of unit length, so t is a distance.
template <typename T>
struct Ray {
    Vec3<T> origin;
    Vec3<T> direction;

    Vec3<T> at(T t) const { return origin + t * direction; }
};

// The first surface a ray meets.
template <typename T>
struct Hit {
    T t{};
    Vec3<T> point;
    Vec3<T> normal;  // unit, facing the ray: dot(normal, direction) <= 0
    int leaf = -1;   // the primitive whose surface was hit (Scene::leaf_paths)
    bool entering = false;  // the ray enters the (composite) solid here
};

// Where a ray's line crosses a solid's surface. `leaf` is -1 for the ends of a half-infinite span
// (t = ±infinity), which are not surfaces.
template <typename T>
struct Crossing {
    T t{};
    Vec3<T> outward_normal;  // of the solid this crossing bounds, unit length
    int leaf = -1;
};

// The closed interval of the ray's line inside a solid, enter.t <= exit.t.
template <typename T>
struct Span {
    Crossing<T> enter;
    Crossing<T> exit;
};

// Sorted, disjoint spans: everything a solid (primitive or CSG) shows along a line. Convex primitives
// give at most one span; CSG gives any number.
template <typename T>
using SpanList = std::vector<Span<T>>;

template <typename T>
Crossing<T> infinitely_far(T sign) {
    return {sign * std::numeric_limits<T>::infinity(), {}, -1};
}

}  // namespace twinray::reference
