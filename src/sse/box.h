// Axis-aligned box against four rays. Mirrors reference/box.h section by section: the record and its
// construction from the scene, the span, the surface at a hit.
#pragma once

#include "scene/geometry.h"
#include "sse/mutation.h"
#include "sse/span4.h"

namespace twinray::sse {

// Parameters stored already broadcast to four lanes (see SphereShape).
struct BoxShape {
    // Slabs multiply by the packet's reciprocal direction (RayPacket::compute_inverse_direction).
    static constexpr bool uses_inverse_direction = true;
    // Three slabs always, no early miss: 2.7 spheres' worth (relative_test_cost).
    static constexpr double test_cost = 2.7;
    Vec3x4 min;
    Vec3x4 max;
};

struct BoxSurface {
    Vec3 min;
    Vec3 max;
};

inline BoxShape make_shape(const scene::Box& box) {
    return {broadcast(Vec3(box.min)), broadcast(Vec3(box.max))};
}

inline BoxSurface make_surface(const scene::Box& box) {
    return {Vec3(box.min), Vec3(box.max)};
}

// The surface again from the record, once the scene's objects are given up (compiled_scene.cpp).
inline BoxSurface surface_of(const BoxShape& box) {
    return {lane(box.min, 0), lane(box.max, 0)};
}

// Face code: 2·axis + 1 where the outward normal is +axis, 2·axis where it is −axis.
constexpr int box_face(int axis, bool positive) {
    return 2 * axis + (positive ? 1 : 0);
}

// Slabs, as in the reference (reference/box.h): per axis the line is between the two face planes for
// t in [near, far]; the entering face is the axis of the largest near, the leaving face that of the
// smallest far. Lanes whose ray is parallel to an axis are inside that slab everywhere or nowhere (the
// product there is ±∞ or NaN, which the select discards).
template <typename P>
TWINRAY_KERNEL Span4 span_of(const BoxShape& box, const RayPacket& rays) {
    vfloat4 zero(0.0f);
    Span4 span;
    span.enter = vfloat4(-infinity);
    span.exit = vfloat4(infinity);
    span.valid = all_true();
    for (int axis = 0; axis < 3; ++axis) {
        vfloat4 low = box.min[axis];
        vfloat4 high = box.max[axis];
        vfloat4 origin = rays.origin[axis];
        vfloat4 direction = rays.direction[axis];
        vbool4 parallel = direction == zero;
        vbool4 forward = direction > zero;
        vfloat4 t_low = (low - origin) * rays.inverse_direction[axis];
        vfloat4 t_high = (high - origin) * rays.inverse_direction[axis];
        vfloat4 near = select(parallel, vfloat4(-infinity), select(forward, t_low, t_high));
        vfloat4 far = select(parallel, vfloat4(infinity), select(forward, t_high, t_low));
        span.valid = span.valid & ((!parallel) | ((origin > low) & (origin < high)));
        vbool4 nearer_face = near > span.enter;
        vbool4 farther_face = far < span.exit;
        span.enter = select(nearer_face, near, span.enter);
        span.exit = select(farther_face, far, span.exit);
        span.enter_face = select(
            nearer_face, select(forward, vint4(box_face(axis, false)), vint4(box_face(axis, true))), span.enter_face);
        span.exit_face = select(
            farther_face, select(forward, vint4(box_face(axis, true)), vint4(box_face(axis, false))), span.exit_face);
    }
    span.valid = span.valid & (mutated<Mutant::box_slab_strict> ? span.enter < span.exit : span.enter <= span.exit);
    return span;
}

inline Vec3 outward_normal(const BoxSurface& /*box*/, std::int32_t face, Vec3 /*point*/, bool& needs_normalizing) {
    needs_normalizing = false;
    float sign = (face & 1) ? 1.0f : -1.0f;
    int axis = face >> 1;
    return {axis == 0 ? sign : 0.0f, axis == 1 ? sign : 0.0f, axis == 2 ? sign : 0.0f};
}

// The face's coordinate set exactly, as the reference's surface_point: a flat face, its own anchor.
inline SurfaceAnchor surface_anchor(const BoxSurface& box, std::int32_t face, float /*turned*/, Vec3 point) {
    int axis = face >> 1;
    point[axis] = (face & 1) ? box.max[axis] : box.min[axis];
    math::SurfaceBounds<float> bounds = scene::surface_bounds_of_box<float>();
    return {point, 0.0f, bounds.own_rounding.at(math::max_abs_component(point)), bounds.spawn_offset};
}

}  // namespace twinray::sse
