// Axis-aligned box against four rays.
#pragma once

#include "sse/span4.h"

namespace twinray::sse {

// Parameters stored already broadcast to four lanes (see SphereF).
struct BoxF {
    vfloat4 min[3];
    vfloat4 max[3];
};

// Face code: 2·axis + 1 where the outward normal is +axis, 2·axis where it is −axis.
constexpr int box_face(int axis, bool positive) {
    return 2 * axis + (positive ? 1 : 0);
}

// Slabs, as in the reference (reference/box.h): per axis the line is between the two face planes for
// t in [near, far]; the entering face is the axis of the largest near, the leaving face that of the
// smallest far. Slabs multiply by the packet's reciprocal direction (RayPacket::compute_inverse_direction).
// Lanes whose ray is parallel to an axis are inside that slab everywhere or nowhere (the product there
// is ±∞ or NaN, which the select discards).
template <typename P>
TWINRAY_KERNEL Span4 spans(const BoxF& box, const RayPacket& rays) {
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
    span.valid = span.valid & (span.enter <= span.exit);
    return span;
}

}  // namespace twinray::sse
