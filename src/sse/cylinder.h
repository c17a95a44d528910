// Solid capped cylinder against four rays.
#pragma once

#include "sse/span4.h"

namespace twinray::sse {

// Parameters stored already broadcast to four lanes (see SphereF).
struct CylinderF {
    vfloat4 base[3];
    vfloat4 axis[3];  // unit, base towards cap
    vfloat4 height;   // |cap − base|
    vfloat4 radius_squared;
    vfloat4 bound_center[3];  // a sphere around the cylinder, widened beyond float rounding
    vfloat4 bound_radius_squared;
};

// Face codes.
constexpr int cylinder_side = 0;
constexpr int cylinder_base_cap = 1;  // outward normal −axis
constexpr int cylinder_top_cap = 2;   // outward normal +axis

// Same formulas as the reference (reference/cylinder.h): the quadratic on the components perpendicular
// to the axis with the cancellation-free discriminant A·r² − |f⊥ × d⊥|², roots q/A and c/q, clipped to
// the slab between the caps. A ray parallel to the axis (A = 0) or to the caps is a per-lane select.
// The textbook variant (a knob, precision.h): Δ = B² − A·C and roots (−B ∓ √Δ)/A.
template <typename P>
TWINRAY_KERNEL Span4 spans(const CylinderF& cylinder, const RayPacket& rays) {
    Span4 span;
    // A ray whose line passes outside the bounding sphere misses: a third of the arithmetic decides
    // that for most rays, which meet a cylinder only where it stands in the image.
    vfloat4 g[3], g_perp[3];
    for (int i = 0; i < 3; ++i) {
        g[i] = rays.origin[i] - cylinder.bound_center[i];
    }
    vfloat4 along = dot3<P>(g, rays.direction);
    for (int i = 0; i < 3; ++i) {
        g_perp[i] = g[i] - along * rays.direction[i];
    }
    if (none(dot3<P>(g_perp, g_perp) <= cylinder.bound_radius_squared)) {
        return span;
    }
    vfloat4 axis[3], f[3], f_perp[3], d_perp[3];
    for (int i = 0; i < 3; ++i) {
        axis[i] = cylinder.axis[i];
        f[i] = rays.origin[i] - cylinder.base[i];
    }
    vfloat4 axial_origin = dot3<P>(f, axis);
    vfloat4 axial_direction = dot3<P>(rays.direction, axis);
    for (int i = 0; i < 3; ++i) {
        f_perp[i] = f[i] - axial_origin * axis[i];
        d_perp[i] = rays.direction[i] - axial_direction * axis[i];
    }
    vfloat4 r2 = cylinder.radius_squared;
    vfloat4 a = dot3<P>(d_perp, d_perp);
    vfloat4 c = dot3<P>(f_perp, f_perp) - r2;
    vfloat4 discriminant;
    if constexpr (P::textbook_quadratic) {
        vfloat4 b = dot3<P>(f_perp, d_perp);
        discriminant = b * b - a * c;
    } else {
        vfloat4 moment[3] = {f_perp[1] * d_perp[2] - f_perp[2] * d_perp[1],
                             f_perp[2] * d_perp[0] - f_perp[0] * d_perp[2],
                             f_perp[0] * d_perp[1] - f_perp[1] * d_perp[0]};
        discriminant = a * r2 - dot3<P>(moment, moment);
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
    vfloat4 b = dot3<P>(f_perp, d_perp);
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

}  // namespace twinray::sse
