// Plane n·p = d against four rays. Its solid is the half-space n·p < d.
#pragma once

#include "sse/span4.h"

namespace twinray::sse {

struct alignas(16) PlaneF {
    float normal[3];
    float offset;
};

// t = (d − n·o) / (n·d), as in the reference (reference/plane.h). Moving out of the half-space the span
// is (−∞, t]; moving in, [t, +∞); parallel, the whole line if the origin is strictly inside, else none.
inline Span4 spans(const PlaneF& plane, const RayPacket& rays) {
    vfloat4 normal[3] = {vfloat4(plane.normal[0]), vfloat4(plane.normal[1]), vfloat4(plane.normal[2])};
    vfloat4 approach = dot3(normal, rays.direction);
    vfloat4 height = vfloat4(plane.offset) - dot3(normal, rays.origin);
    vfloat4 zero(0.0f);
    vbool4 leaving = approach > zero;
    vbool4 arriving = approach < zero;
    Span4 span;
    span.valid = leaving | arriving | (height > zero);
    vfloat4 t = height / approach;
    span.enter = select(arriving, t, vfloat4(-infinity));
    span.exit = select(leaving, t, vfloat4(infinity));
    return span;
}

}  // namespace twinray::sse
