// Axis-aligned box, four at a time.
#pragma once

#include "sse/span4.h"

namespace twinray::sse {

struct alignas(16) BoxBlock {
    float min[3][4];
    float max[3][4];
};

// Face code: 2·axis + 1 where the outward normal is +axis, 2·axis where it is −axis.
constexpr int box_face(int axis, bool positive) { return 2 * axis + (positive ? 1 : 0); }

// Slabs, as in the reference (reference/box.h), but multiplying by the ray's reciprocal direction
// (computed once per ray) instead of dividing per box: the thesis's rule of one reciprocal where several
// numerators share a denominator, here shared by every box the ray meets. It costs one extra rounding
// (≤ 1 ulp more in t). A ray parallel to an axis is uniform across lanes, so that test is a branch.
inline Span4 spans(const BoxBlock& block, const Ray4& ray) {
    Span4 span;
    span.enter = vfloat4(-infinity);
    span.exit = vfloat4(infinity);
    span.valid = all_true();
    for (int axis = 0; axis < 3; ++axis) {
        vfloat4 low = vfloat4::load(block.min[axis]);
        vfloat4 high = vfloat4::load(block.max[axis]);
        if (ray.parallel[axis]) {
            span.valid = span.valid & (ray.origin[axis] > low) & (ray.origin[axis] < high);
            continue;
        }
        bool forward = ray.forward[axis];
        vfloat4 t_low = (low - ray.origin[axis]) * ray.inverse_direction[axis];
        vfloat4 t_high = (high - ray.origin[axis]) * ray.inverse_direction[axis];
        vfloat4 near = forward ? t_low : t_high;
        vfloat4 far = forward ? t_high : t_low;
        vbool4 nearer_face = near > span.enter;
        vbool4 farther_face = far < span.exit;
        span.enter = select(nearer_face, near, span.enter);
        span.exit = select(farther_face, far, span.exit);
        span.enter_face = select(nearer_face, vint4(box_face(axis, !forward)), span.enter_face);
        span.exit_face = select(farther_face, vint4(box_face(axis, forward)), span.exit_face);
    }
    span.valid = span.valid & (span.enter <= span.exit);
    return span;
}

}  // namespace twinray::sse
