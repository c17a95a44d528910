// A primitive in its own space, placed by an affine transform p ↦ L·p + t (scene::Transformed): an ellipsoid,
// a turned box, a cylinder scaled across its axis. The ray is carried into object space, the primitive's own
// span_of answers there, and its crossings come back. Mirrors src/sse/transformed.h section by section.
#pragma once

#include "math/transform.h"
#include "reference/box.h"
#include "reference/cylinder.h"
#include "reference/ray.h"
#include "reference/sphere.h"

#include <optional>

namespace twinray::reference {

// The primitive in object space (its leaf is this one's), its transform and norms, held apart
// (scene::TransformedRecord): the variant of every object stays its plain size.
template <typename T, typename Inner>
struct TransformedShape : scene::TransformedRecord<T, Inner> {
    TransformedShape(const Inner& inner, const scene::Transform& to_world, int leaf_)
        : scene::TransformedRecord<T, Inner>(inner, to_world), leaf(leaf_) {}

    int leaf = -1;
};

template <typename T, typename S>
auto make_shape(const scene::Transformed<S>& primitive, int leaf) {
    auto inner = make_shape<T>(primitive.shape(), leaf);
    return TransformedShape<T, decltype(inner)>(inner, primitive.to_world(), leaf);
}

// The object-space ray o' = L⁻¹·(o − t), d' = L⁻¹·d is the world ray's line point for point at the same t, but
// d' is not of unit length and every primitive's span_of takes a unit direction: with s = |d'| the object ray
// runs along d'/s and meets the surface at t' = s·t. Normals come back through the inverse transpose, L⁻ᵀ·n,
// which keeps them perpendicular to the placed surface, and are made unit again.
template <typename T, typename Inner>
std::optional<Span<T>> span_of(const TransformedShape<T, Inner>& shape, const Ray<T>& ray) {
    Vec3<T> direction = shape.to_world().direction_to_object(ray.direction);
    T stretch = length(direction);
    std::optional<Span<T>> span =
        span_of(shape.inner(), Ray<T>{shape.to_world().point_to_object(ray.origin), direction / stretch});
    if (span) {
        for (Crossing<T>* crossing : {&span->enter, &span->exit}) {
            crossing->t = crossing->t / stretch;
            if (crossing->leaf >= 0) {
                crossing->outward_normal = normalize(shape.to_world().normal_to_world(crossing->outward_normal));
            }
        }
    }
    return span;
}

// The hit point is carried into object space, re-projected there by the primitive's own surface_point (the
// normal goes back as Lᵀ·n) and carried out again. The spawn offset δ must survive both trips
// (scene::transformed_spawn_offset, with norms rounded up):
// - p'_w = L·p'ₒ + t is within e_back = γ(4)·(‖L‖∞·|p'ₒ|∞ + |t|∞) per coordinate of the exact image of p'ₒ, and
//   the next origin o = p'_w + δ·n̂ is rounded by γ(2)·|p'_w|∞ more;
// - the next ray computes oₒ = L⁻¹·(o − t) within e_fwd = γ(5)·‖L⁻¹‖∞·(|o|∞ + |t|∞) per coordinate;
// - in object space the origin then stands δ·(n̂ₒ·L⁻¹·n̂) = δ·|L⁻ᵀ·n̂ₒ| ≥ δ/‖L‖ off p'ₒ along the object normal,
//   less |L⁻¹·e_back|₂ ≤ ‖L⁻¹‖·√3·e_back and |e_fwd|₂ ≤ √3·e_fwd, and must still exceed the object's own spawn
//   offset δₒ: δ ≥ ‖L‖·(δₒ + √3·(e_fwd + ‖L⁻¹‖·e_back)), solved for δ since |o| holds δ too.
// A point the primitive leaves where it is (already within its own rounding of the surface) is not carried
// back, so it stays as the ray found it.
// `in_object(object_point)` is the object's own surface_point there; a mesh instance's hits come back the same way.
template <typename T, typename InObject>
SurfacePoint<T> placed_surface_point(const math::Transform<T>& m, const scene::TransformNorms<T>& norms, Vec3<T> point,
                                     InObject&& in_object) {
    Vec3<T> object_point = m.point_to_object(point);
    SurfacePoint<T> inner = in_object(object_point);
    Vec3<T> projected = inner.point == object_point ? point : m.point_to_world(inner.point);
    return {projected, scene::transformed_spawn_offset(norms, inner.spawn_offset, max_abs_component(inner.point),
                                                       max_abs_component(projected))};
}

template <typename T, typename Inner>
SurfacePoint<T> surface_point(const TransformedShape<T, Inner>& shape, Vec3<T> point, Vec3<T> normal) {
    const math::Transform<T>& m = shape.to_world();
    return placed_surface_point(m, shape.norms(), point, [&](Vec3<T> object_point) {
        return surface_point(shape.inner(), object_point, normalize(m.normal_to_object(normal)));
    });
}

}  // namespace twinray::reference
