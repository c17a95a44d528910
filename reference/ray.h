// Rays, hits, and the spans a ray's line spends inside a solid (the currency of CSG).
#pragma once

#include "math/rounding.h"
#include "reference/vec3.h"
#include "scene/geometry.h"

#include <cmath>
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
    Vec3<T> point;          // re-projected onto the primitive's surface (surface_point in its header)
    Vec3<T> normal;         // unit, facing the ray: dot(normal, direction) <= 0
    int leaf = -1;          // the primitive whose surface was hit (Scene::leaf_paths)
    int triangle = -1;      // for a mesh, the triangle's index in it; -1 for any other primitive
    bool entering = false;  // the ray enters the (composite) solid here; on a mesh, meets a triangle's front
    T spawn_offset{};       // how far off the surface secondary rays start (SurfacePoint::spawn_offset)
    // What shading uses (N·L, Phong, reflected and refracted directions): `normal` itself, or on a smooth
    // mesh the interpolated normal turned to its side. `normal` still decides sides and spawn offsets.
    Vec3<T> shading_normal;
    int part = -1;  // on an instance of a solid shape, the shape's primitive hit (scene::SolidShape's parts)
};

// The unit vector along `radial`, the normal of a curved surface at a hit. A primitive smaller than the
// spacing of the numbers where it stands (a radius below one ulp of its centre) can leave `radial` exactly
// zero: the normal is then undefined, and the ray's own reverse direction stands in for it, not a NaN.
template <typename T>
Vec3<T> radial_normal(Vec3<T> radial, Vec3<T> direction) {
    return radial == Vec3<T>{} ? -direction : normalize(radial);
}

// Every component finite and the direction of unit length (math/rounding.h); any other ray is a miss.
template <typename T>
bool is_traceable(const Ray<T>& ray) {
    return math::is_traceable(ray.origin, ray.direction);
}

// A hit point moved onto the primitive's surface, and the distance off the surface a secondary ray must
// start at so that it cannot find that surface again by rounding: the bound on the re-projected point's
// distance from the true surface, plus the bound on the rounding with which the next ray's intersection
// formula decides on which side of the surface its origin lies, plus one rounding of the origin itself.
// Every term scales with the primitive's size and its distance from the origin, never with t: after
// re-projection, how far the ray travelled no longer matters (docs/numerics.md). A point is re-projected
// only where it is measurably off the surface, by more than the projection would round itself: far
// from the origin the projection's own rounding (u·|p|) can exceed that of the ray's o + t·d.
template <typename T>
struct SurfacePoint {
    Vec3<T> point;
    T spawn_offset{};
};

// Where a ray's line crosses a solid's surface. `leaf` is -1 for the ends of a half-infinite span
// (t = ±infinity), which are not surfaces.
template <typename T>
struct Crossing {
    T t{};
    Vec3<T> outward_normal;  // of the solid this crossing bounds, unit length
    int leaf = -1;
    int part = -1;  // on an instance of a solid shape, the shape's primitive (`leaf` is then the instance's)
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
    return {sign * std::numeric_limits<T>::infinity(), {}, -1, -1};
}

}  // namespace twinray::reference
