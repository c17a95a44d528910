// Solid capped cylinder against four rays. Mirrors reference/cylinder.h section by section: the record and
// its construction from the scene, the span, the surface at a hit.
#pragma once

#include "scene/geometry.h"
#include "sse/span4.h"

#include <algorithm>
#include <cmath>

namespace twinray::sse {

// Parameters stored already broadcast to four lanes (see SphereShape).
struct CylinderShape {
    Vec3x4 base;
    Vec3x4 axis;     // unit, base towards cap
    vfloat4 height;  // |cap − base|
    vfloat4 radius_squared;
    Vec3x4 bound_center;  // a sphere around the cylinder, widened beyond float rounding
    vfloat4 bound_radius_squared;
};

struct CylinderSurface {
    Vec3 base;
    Vec3 axis;
    float radius;
    float height;
};

// Axis and height are derived in float from the float end points, as the reference<float> does.
inline CylinderSurface make_surface(const scene::Cylinder& cylinder) {
    Vec3 base(cylinder.base);
    Vec3 along = Vec3(cylinder.cap) - base;
    return {base, math::normalize_by_reciprocal(along), static_cast<float>(cylinder.radius), math::length(along)};
}

inline CylinderShape make_shape(const scene::Cylinder& cylinder) {
    CylinderSurface surface = make_surface(cylinder);
    // The bounding sphere widened by 1e-4 relative: far beyond any float rounding, so that culling
    // never loses a hit.
    scene::BoundingSphere bound = scene::bounding_sphere(cylinder);
    const scene::Vec3& middle = bound.center;
    double widened =
        bound.radius +
        1e-4 * (bound.radius + std::max({std::fabs(middle[0]), std::fabs(middle[1]), std::fabs(middle[2])}));
    return {broadcast(surface.base), broadcast(surface.axis),
            vfloat4(surface.height), vfloat4(surface.radius * surface.radius),
            broadcast(Vec3(middle)), vfloat4(static_cast<float>(widened * widened))};
}

// The surface again from the record, once the scene's objects are given up (compiled_scene.cpp): as a sphere's radius
// (sphere.h).
inline CylinderSurface surface_of(const CylinderShape& cylinder) {
    return {lane(cylinder.base, 0), lane(cylinder.axis, 0), std::sqrt(cylinder.radius_squared.lane(0)),
            cylinder.height.lane(0)};
}

// Face codes.
constexpr int cylinder_side = 0;
constexpr int cylinder_base_cap = 1;  // outward normal −axis
constexpr int cylinder_top_cap = 2;   // outward normal +axis

// Same formulas as the reference (reference/cylinder.h): the quadratic on the components perpendicular
// to the axis with the cancellation-free discriminant A·r² − |f⊥ × d⊥|², roots q/A and c/q, clipped to
// the slab between the caps. A ray parallel to the axis (A = 0) or to the caps is a per-lane select.
// The textbook variant (a knob, precision.h): Δ = B² − A·C and roots (−B ∓ √Δ)/A.
template <typename P>
TWINRAY_KERNEL Span4 span_of(const CylinderShape& cylinder, const RayPacket& rays) {
    Span4 span;
    // A ray whose line passes outside the bounding sphere misses: a third of the arithmetic decides
    // that for most rays, which meet a cylinder only where it stands in the image.
    Vec3x4 g = rays.origin - cylinder.bound_center;
    vfloat4 along = dot<P>(g, rays.direction);
    Vec3x4 g_perp = g - along * rays.direction;
    if (none(dot<P>(g_perp, g_perp) <= cylinder.bound_radius_squared)) {
        return span;
    }
    Vec3x4 axis = cylinder.axis;
    Vec3x4 f = rays.origin - cylinder.base;
    vfloat4 axial_origin = dot<P>(f, axis);
    vfloat4 axial_direction = dot<P>(rays.direction, axis);
    Vec3x4 f_perp = f - axial_origin * axis;
    Vec3x4 d_perp = rays.direction - axial_direction * axis;
    vfloat4 r2 = cylinder.radius_squared;
    vfloat4 a = dot<P>(d_perp, d_perp);
    vfloat4 c = dot<P>(f_perp, f_perp) - r2;
    vfloat4 discriminant;
    if constexpr (P::textbook_quadratic) {
        vfloat4 b = dot<P>(f_perp, d_perp);
        discriminant = b * b - a * c;
    } else {
        Vec3x4 moment = cross(f_perp, d_perp);
        discriminant = a * r2 - dot<P>(moment, moment);
    }
    vfloat4 zero(0.0f);
    vfloat4 height = cylinder.height;
    vbool4 along_axis = a == zero;
    vbool4 side_valid = select_mask(along_axis, c < zero, discriminant >= zero);
    vbool4 slab_valid =
        (axial_direction > zero) | (axial_direction < zero) | ((axial_origin > zero) & (axial_origin < height));
    span.valid = side_valid & slab_valid;
    if (none(span.valid)) {
        return span;
    }
    vfloat4 b = dot<P>(f_perp, d_perp);
    vfloat4 root = sqrt(max(discriminant, zero));
    vfloat4 t0, t1;
    if constexpr (P::textbook_quadratic) {
        t0 = divide<P>(-b - root, a);
        t1 = divide<P>(-b + root, a);
    } else {
        vfloat4 q = -b - copysign(root, b);
        t0 = divide<P>(q, a);
        t1 = select(q == zero, zero, divide<P>(c, q));
    }
    vfloat4 side_near = select(along_axis, vfloat4(-infinity), min(t0, t1));
    vfloat4 side_far = select(along_axis, vfloat4(infinity), max(t0, t1));

    // Both cap planes share the denominator: one reciprocal, two multiplies (one extra rounding in t).
    vbool4 parallel_to_caps = axial_direction == zero;
    vfloat4 inverse_axial = reciprocal<P>(axial_direction);
    vfloat4 t_base = -axial_origin * inverse_axial;
    vfloat4 t_top = (height - axial_origin) * inverse_axial;
    vbool4 towards_top = axial_direction > zero;
    vfloat4 slab_near = select(parallel_to_caps, vfloat4(-infinity), select(towards_top, t_base, t_top));
    vfloat4 slab_far = select(parallel_to_caps, vfloat4(infinity), select(towards_top, t_top, t_base));
    vint4 near_cap = select(towards_top, vint4(cylinder_base_cap), vint4(cylinder_top_cap));
    vint4 far_cap = select(towards_top, vint4(cylinder_top_cap), vint4(cylinder_base_cap));

    vbool4 enter_by_cap = slab_near > side_near;
    vbool4 exit_by_cap = slab_far < side_far;
    span.enter = select(enter_by_cap, slab_near, side_near);
    span.exit = select(exit_by_cap, slab_far, side_far);
    span.enter_face = select(enter_by_cap, near_cap, vint4(cylinder_side));
    span.exit_face = select(exit_by_cap, far_cap, vint4(cylinder_side));
    span.valid = span.valid & (span.enter <= span.exit);
    return span;
}

// Radial on the side (not yet of unit length: the caller normalises four lanes at once), ±axis on a cap.
inline Vec3 outward_normal(const CylinderSurface& cylinder, std::int32_t face, Vec3 point, bool& needs_normalizing) {
    if (face == cylinder_side) {
        Vec3 w = point - cylinder.base;
        needs_normalizing = true;
        return w - math::dot(w, cylinder.axis) * cylinder.axis;
    }
    needs_normalizing = false;
    return face == cylinder_top_cap ? cylinder.axis : -cylinder.axis;
}

// As the reference's surface_point: on the side p' = base + h·axis + r·n̂ (`turned` −1 where a CSG
// complement turned n̂), on a cap p' = p − (h − h_cap)·axis, a flat face and its own anchor.
inline SurfaceAnchor surface_anchor(const CylinderSurface& cylinder, std::int32_t face, float turned, Vec3 point) {
    float axial = math::dot(point - cylinder.base, cylinder.axis);
    math::SurfaceBounds<float> bounds = scene::surface_bounds_of_cylinder(cylinder.radius, cylinder.height);
    float own_rounding = bounds.own_rounding.at(math::max_abs_component(point));
    if (face == cylinder_side) {
        return {cylinder.base + axial * cylinder.axis, turned * cylinder.radius, own_rounding, bounds.spawn_offset};
    }
    float cap_axial = face == cylinder_top_cap ? cylinder.height : 0.0f;
    return {point - (axial - cap_axial) * cylinder.axis, 0.0f, own_rounding, bounds.spawn_offset};
}

}  // namespace twinray::sse
