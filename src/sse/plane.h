// Plane n·p = d against four rays. Its solid is the half-space n·p < d. Mirrors reference/plane.h
// section by section: the record and its construction from the scene, the span, the surface at a hit.
#pragma once

#include "scene/geometry.h"
#include "sse/span4.h"

namespace twinray::sse {

// Parameters stored already broadcast to four lanes (see SphereShape).
struct PlaneShape {
    Vec3x4 normal;
    vfloat4 offset;
};

struct PlaneSurface {
    Vec3 normal;
    float offset;
};

inline PlaneShape make_shape(const scene::Plane& plane) {
    return {broadcast(Vec3(plane.normal)), vfloat4(static_cast<float>(plane.offset))};
}

inline PlaneSurface make_surface(const scene::Plane& plane) {
    return {Vec3(plane.normal), static_cast<float>(plane.offset)};
}

// The surface again from the record, once the scene's objects are given up (compiled_scene.cpp).
inline PlaneSurface surface_of(const PlaneShape& plane) {
    return {lane(plane.normal, 0), plane.offset.lane(0)};
}

// t = (d − n·o) / (n·d), as in the reference (reference/plane.h). Moving out of the half-space the span
// is (−∞, t]; moving in, [t, +∞); parallel, the whole line if the origin is strictly inside, else none.
template <typename P>
TWINRAY_KERNEL Span4 span_of(const PlaneShape& plane, const RayPacket& rays) {
    vfloat4 approach = dot<P>(plane.normal, rays.direction);
    vfloat4 height = plane.offset - dot<P>(plane.normal, rays.origin);
    vfloat4 zero(0.0f);
    vbool4 leaving = approach > zero;
    vbool4 arriving = approach < zero;
    Span4 span;
    span.valid = leaving | arriving | (height > zero);
    vfloat4 t = divide<P>(height, approach);
    span.enter = select(arriving, t, vfloat4(-infinity));
    span.exit = select(leaving, t, vfloat4(infinity));
    return span;
}

inline Vec3 outward_normal(const PlaneSurface& plane, std::int32_t /*face*/, Vec3 /*point*/, bool& needs_normalizing) {
    needs_normalizing = false;
    return plane.normal;
}

// p' = p + (d − n·p)·n, as the reference's surface_point: a flat face, so p' is its own anchor.
inline SurfaceAnchor surface_anchor(const PlaneSurface& plane, std::int32_t /*face*/, float /*turned*/, Vec3 point) {
    Vec3 projected = point + (plane.offset - math::dot(plane.normal, point)) * plane.normal;
    math::SurfaceBounds<float> bounds = scene::surface_bounds_of_plane(plane.offset);
    return {projected, 0.0f, bounds.own_rounding.at(math::max_abs_component(point)), bounds.spawn_offset};
}

}  // namespace twinray::sse
