// Plane n·p = d, four at a time. Its solid is the half-space n·p < d.
#pragma once

#include "sse/span4.h"

namespace twinray::sse {

struct alignas(16) PlaneBlock {
    float normal[3][4];
    float offset[4];
};

// t = (d − n·o) / (n·d), as in the reference (reference/plane.h). Moving out of the half-space the span
// is (−∞, t]; moving in, [t, +∞); parallel, the whole line if the origin is strictly inside, else none.
inline Span4 spans(const PlaneBlock& block, const Ray4& ray) {
    vfloat4 normal[3];
    for (int axis = 0; axis < 3; ++axis) {
        normal[axis] = vfloat4::load(block.normal[axis]);
    }
    vfloat4 approach = dot3(normal, ray.direction);
    vfloat4 height = vfloat4::load(block.offset) - dot3(normal, ray.origin);
    vfloat4 zero(0.0f);
    vbool4 leaving = approach > zero;
    vbool4 arriving = approach < zero;
    Span4 span;
    // Ordered comparisons: NaN padding lanes are neither leaving, arriving nor inside.
    span.valid = leaving | arriving | (height > zero);
    if (none(span.valid)) {
        return span;
    }
    vfloat4 t = height / approach;
    span.enter = select(arriving, t, vfloat4(-infinity));
    span.exit = select(leaving, t, vfloat4(infinity));
    return span;
}

}  // namespace twinray::sse
