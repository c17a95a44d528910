// Plane n·p = d against four rays. Its solid is the half-space n·p < d.
#pragma once

#include "sse/span4.h"

namespace twinray::sse {

// Parameters stored already broadcast to four lanes (see SphereF).
struct PlaneF {
    vfloat4 normal[3];
    vfloat4 offset;
};

// t = (d − n·o) / (n·d), as in the reference (reference/plane.h). Moving out of the half-space the span
// is (−∞, t]; moving in, [t, +∞); parallel, the whole line if the origin is strictly inside, else none.
template <typename P>
TWINRAY_KERNEL Span4 spans(const PlaneF& plane, const RayPacket& rays) {
    vfloat4 approach = dot3<P>(plane.normal, rays.direction);
    vfloat4 height = plane.offset - dot3<P>(plane.normal, rays.origin);
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

}  // namespace twinray::sse
