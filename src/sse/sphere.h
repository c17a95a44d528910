// Sphere |p − c| = r, against four rays.
#pragma once

#include "sse/span4.h"

namespace twinray::sse {

// Parameters stored already broadcast to four lanes: a load per parameter instead of a load and a
// shuffle in the innermost loop (64 bytes a sphere, which a handful of spheres can afford).
struct SphereF {
    vfloat4 center[3];
    vfloat4 radius_squared;
};

// Same formula as the reference (reference/sphere.h): with f = o − c, b = f·d,
// Δ = r² − |f − b·d|² (no cancellation far from the sphere), q = −b − sign(b)·√Δ, t = q and c/q.
// The division waits until some lane is known to hit (the thesis: divide only where needed).
// The textbook variant (a knob, precision.h) computes Δ = b² − c and t = −b ∓ √Δ: b² and c are both
// about |f|², so Δ loses its digits to cancellation as the sphere gets far in radii, and so does the
// nearer root.
template <typename P>
TWINRAY_KERNEL Span4 spans(const SphereF& sphere, const RayPacket& rays) {
    vfloat4 f[3];
    for (int axis = 0; axis < 3; ++axis) {
        f[axis] = rays.origin[axis] - sphere.center[axis];
    }
    vfloat4 b = dot3<P>(f, rays.direction);
    vfloat4 r2 = sphere.radius_squared;
    vfloat4 discriminant;
    if constexpr (P::textbook_quadratic) {
        discriminant = b * b - (dot3<P>(f, f) - r2);
    } else {
        vfloat4 perpendicular[3];
        for (int axis = 0; axis < 3; ++axis) {
            perpendicular[axis] = f[axis] - b * rays.direction[axis];
        }
        discriminant = r2 - dot3<P>(perpendicular, perpendicular);
    }
    Span4 span;
    span.valid = discriminant >= vfloat4(0.0f);
    if (none(span.valid)) {
        return span;
    }
    vfloat4 root = sqrt(max(discriminant, vfloat4(0.0f)));
    if constexpr (P::textbook_quadratic) {
        span.enter = -b - root;
        span.exit = -b + root;
        return span;
    }
    vfloat4 c = dot3<P>(f, f) - r2;
    vfloat4 q = -b - copysign(root, b);
    vfloat4 t0 = q;
    vfloat4 t1 = select(q == vfloat4(0.0f), vfloat4(0.0f), divide<P>(c, q));
    span.enter = min(t0, t1);
    span.exit = max(t0, t1);
    return span;
}

}  // namespace twinray::sse
