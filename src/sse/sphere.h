// Sphere |p − c| = r, against four rays. Mirrors reference/sphere.h section by section: the record and
// its construction from the scene, the span, the surface at a hit.
#pragma once

#include "scene/geometry.h"
#include "sse/span4.h"

#include <cmath>

namespace twinray::sse {

// 16 bytes: a BVH leaf's four spheres are one cache line (64 bytes a sphere stored broadcast). Four shuffles a
// test; boxes and cylinders, whose kernels would need six and twelve, stay broadcast (packed, small scenes of them
// were 14–21% slower; docs/performance.md, "Packed sphere records").
struct SphereShape {
    Packed4 center_radius_squared;  // w: r²
};

// What one hit needs: its normal and re-projection.
struct SphereSurface {
    Vec3 center;
    float radius;
};

inline SphereShape make_shape(const scene::Sphere& sphere) {
    float radius = static_cast<float>(sphere.radius);
    const Vec3 center(sphere.center);
    return {{center.x, center.y, center.z, radius * radius}};
}

inline SphereSurface make_surface(const scene::Sphere& sphere) {
    return {Vec3(sphere.center), static_cast<float>(sphere.radius)};
}

// The surface again from the record, once the scene's objects are given up (compiled_scene.cpp): √fl(r²) is r for
// every float r whose square is normal and finite (checked for all of them); the compiler keeps the few others apart.
inline SphereSurface surface_of(const SphereShape& sphere) {
    const Packed4& packed = sphere.center_radius_squared;
    return {{packed.x, packed.y, packed.z}, std::sqrt(packed.w)};
}

// Same formula as the reference (reference/sphere.h): with f = o − c, b = f·d,
// Δ = r² − |f − b·d|² (no cancellation far from the sphere), q = −b − sign(b)·√Δ, t = q and c/q.
// The division waits until some lane is known to hit (the thesis: divide only where needed).
// The textbook variant (a knob, precision.h) computes Δ = b² − c and t = −b ∓ √Δ: b² and c are both
// about |f|², so Δ loses its digits to cancellation as the sphere gets far in radii, and so does the
// nearer root.
template <typename P>
TWINRAY_KERNEL Span4 span_of(const SphereShape& sphere, const RayPacket& rays) {
    const __m128 packed = sphere.center_radius_squared.load();
    Vec3x4 f = rays.origin - spread_xyz(packed);
    vfloat4 b = dot<P>(f, rays.direction);
    vfloat4 r2 = spread<3>(packed);
    vfloat4 discriminant;
    if constexpr (P::textbook_quadratic) {
        discriminant = b * b - (dot<P>(f, f) - r2);
    } else {
        Vec3x4 perpendicular = f - b * rays.direction;
        discriminant = r2 - dot<P>(perpendicular, perpendicular);
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
    vfloat4 c = dot<P>(f, f) - r2;
    vfloat4 q = -b - copysign(root, b);
    vfloat4 t0 = q;
    vfloat4 t1 = select(q == vfloat4(0.0f), vfloat4(0.0f), divide<P>(c, q));
    span.enter = min(t0, t1);
    span.exit = max(t0, t1);
    return span;
}

// The outward normal p − c, not yet of unit length (the caller normalises four lanes at once).
inline Vec3 outward_normal(const SphereSurface& sphere, std::int32_t /*face*/, Vec3 point, bool& needs_normalizing) {
    needs_normalizing = true;
    return point - sphere.center;
}

// p' = c + r·n̂, as the reference's surface_point; `turned` is −1 where a CSG complement turned n̂.
inline SurfaceAnchor surface_anchor(const SphereSurface& sphere, std::int32_t /*face*/, float turned, Vec3 point) {
    math::SurfaceBounds<float> bounds = scene::surface_bounds_of_sphere(sphere.radius);
    return {sphere.center, turned * sphere.radius, bounds.own_rounding.at(math::max_abs_component(point)),
            bounds.spawn_offset};
}

}  // namespace twinray::sse
