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

// An instance of a shape (scene::Placement): the shape in its own space, built once and shared by every instance
// (`shape`, an index into the tracer's), and this one's transform. For a mesh shape a ray goes in as a transformed
// primitive's does, o' = L⁻¹·(o − t), d' = L⁻¹·d, but d' is left as it is: the triangle test takes any direction,
// and along o' + t·d' the object ray meets a triangle at the world ray's own t. A solid shape's primitives take a
// unit direction, as a transformed primitive's do (unit_object_ray).
template <typename T>
struct Instance {
    std::uint32_t shape = 0;
    math::Transform<T> to_world;
    scene::TransformNorms<T> norms;
    bool mirrors = false;  // det L < 0: a placed mesh's fronts face the other way (scene.h)
    int leaf = -1;
};

template <typename T>
Instance<T> make_instance(const scene::Placement& placement, int leaf) {
    const scene::Transform m = placement.transform();
    return {static_cast<std::uint32_t>(placement.shape), math::Transform<T>::from(m), scene::transform_norms<T>(m),
            math::determinant(m.linear) < 0, leaf};
}

template <typename T>
Ray<T> object_ray(const Instance<T>& instance, const Ray<T>& ray) {
    return {instance.to_world.point_to_object(ray.origin), instance.to_world.direction_to_object(ray.direction)};
}

// The object-space ray o' = L⁻¹·(o − t), d' = L⁻¹·d is the world ray's line point for point at the same t, but
// d' is not of unit length and every primitive's span_of takes a unit direction: with s = |d'| (`stretch`) the
// object ray runs along d'/s and meets a surface at t' = s·t.
template <typename T>
Ray<T> unit_object_ray(const math::Transform<T>& m, const Ray<T>& ray, T& stretch) {
    Vec3<T> direction = m.direction_to_object(ray.direction);
    stretch = length(direction);
    return {m.point_to_object(ray.origin), direction / stretch};
}

// An object-space crossing of unit_object_ray's brought back: t' / s, and the normal through the inverse transpose,
// L⁻ᵀ·n, which keeps it perpendicular to the placed surface, made unit again.
template <typename T>
void carry_back(const math::Transform<T>& m, T stretch, Crossing<T>& crossing) {
    crossing.t = crossing.t / stretch;
    if (crossing.leaf >= 0) {
        crossing.outward_normal = normalize(m.normal_to_world(crossing.outward_normal));
    }
}

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

template <typename T, typename Inner>
std::optional<Span<T>> span_of(const TransformedShape<T, Inner>& shape, const Ray<T>& ray) {
    T stretch;
    std::optional<Span<T>> span = span_of(shape.inner(), unit_object_ray(shape.to_world(), ray, stretch));
    if (span) {
        carry_back(shape.to_world(), stretch, span->enter);
        carry_back(shape.to_world(), stretch, span->exit);
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
