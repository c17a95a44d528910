// Axis-aligned box min ≤ p ≤ max.
#pragma once

#include "reference/ray.h"

#include <cmath>
#include <optional>

namespace twinray::reference {

template <typename T>
struct BoxShape {
    Vec3<T> min;
    Vec3<T> max;
    int leaf = -1;
};

template <typename T>
BoxShape<T> make_shape(const scene::Box& box, int leaf) {
    return {Vec3<T>(box.min), Vec3<T>(box.max), leaf};
}

// Slabs (Kay–Kajiya): per axis the line is between the two face planes for t in [near, far]; the
// box is the intersection of the three. The entering face is the axis of the largest near, the
// leaving face the axis of the smallest far. A ray parallel to a slab is inside it everywhere or
// nowhere; one running exactly within a face plane is not inside (as for planes).
template <typename T>
std::optional<Span<T>> span_of(const BoxShape<T>& box, const Ray<T>& ray) {
    Crossing<T> enter = infinitely_far(T(-1));
    Crossing<T> exit = infinitely_far(T(1));
    for (int axis = 0; axis < 3; ++axis) {
        T origin = ray.origin[axis];
        T direction = ray.direction[axis];
        if (direction == T(0)) {
            if (!(origin > box.min[axis] && origin < box.max[axis])) {
                return std::nullopt;
            }
            continue;
        }
        T t_min_face = (box.min[axis] - origin) / direction;
        T t_max_face = (box.max[axis] - origin) / direction;
        bool forward = direction > T(0);
        T near = forward ? t_min_face : t_max_face;
        T far = forward ? t_max_face : t_min_face;
        Vec3<T> axis_normal{axis == 0 ? T(1) : T(0), axis == 1 ? T(1) : T(0), axis == 2 ? T(1) : T(0)};
        if (near > enter.t) {
            enter = {near, forward ? -axis_normal : axis_normal, box.leaf};
        }
        if (far < exit.t) {
            exit = {far, forward ? axis_normal : -axis_normal, box.leaf};
        }
    }
    if (!(enter.t <= exit.t)) {
        return std::nullopt;
    }
    return Span<T>{enter, exit};
}

// The coordinate of the face hit (the normal's dominant axis, the nearer of its two faces) set exactly to the face's:
// p' is on the face with no error. Dominant, not non-zero: a turned box's normal comes back into object space with
// rounding residue off its axis (transformed.h). The next ray compares its origin with the face by face − o, exact
// where they are within a factor of two (Sterbenz), so an origin one ulp off the face is on the right side: γ(3)·|p'|∞
// moves it by at least one ulp.
template <typename T>
SurfacePoint<T> surface_point(const BoxShape<T>& box, Vec3<T> point, Vec3<T> normal) {
    T coordinates[3] = {point.x, point.y, point.z};
    int axis = std::fabs(normal.y) > std::fabs(normal.x) ? 1 : 0;
    axis = std::fabs(normal.z) > std::fabs(normal[axis]) ? 2 : axis;
    T c = coordinates[axis];
    coordinates[axis] = std::fabs(c - box.max[axis]) < std::fabs(c - box.min[axis]) ? box.max[axis] : box.min[axis];
    Vec3<T> projected{coordinates[0], coordinates[1], coordinates[2]};
    return {projected, scene::surface_bounds_of_box<T>().spawn_offset.at(max_abs_component(projected))};
}

}  // namespace twinray::reference
