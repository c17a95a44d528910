// A primitive in its own space under p ↦ L·p + t (scene::Transformed), against four rays. Mirrors
// reference/transformed.h section by section: the record and its construction from the scene, the span, the
// surface at a hit. Only scenes with such a primitive have this list; the others pay nothing.
#pragma once

#include "math/transform.h"
#include "scene/geometry.h"
#include "sse/box.h"
#include "sse/cylinder.h"
#include "sse/mutation.h"
#include "sse/span4.h"
#include "sse/sphere.h"

#include <utility>

namespace twinray::sse {

// The trip of a packet into object space costs 1.7 spheres' worth (relative_test_cost).
constexpr double transformed_trip_cost = 1.7;

// L⁻¹ and t broadcast (see SphereShape): 192 bytes beside the primitive's own record.
template <typename Inner>
struct TransformedShape {
    static constexpr double test_cost = relative_test_cost<Inner> + transformed_trip_cost;
    Inner inner;
    math::Matrix3<vfloat4> inverse;
    Vec3x4 translation;
};

// The primitive's surface, its transform and norms, held apart (scene::TransformedRecord): every Leaf stays the
// size of the largest plain surface.
template <typename InnerSurface>
using TransformedSurface = scene::TransformedRecord<float, InnerSurface>;

template <typename S>
auto make_shape(const scene::Transformed<S>& primitive) {
    auto inner = make_shape(primitive.shape());
    const math::Matrix3<double>& l = primitive.to_world().inverse;
    math::Matrix3<vfloat4> inverse;
    for (int i = 0; i < 3; ++i) {
        inverse.row[i] = broadcast(Vec3(l.row[i]));
    }
    return TransformedShape<decltype(inner)>{inner, inverse, broadcast(Vec3(primitive.to_world().translation))};
}

template <typename S>
auto make_surface(const scene::Transformed<S>& primitive) {
    auto inner = make_surface(primitive.shape());
    return TransformedSurface<decltype(inner)>(inner, primitive.to_world());
}

// A packet carried into an object's space for primitives that take a unit direction, as the reference's
// unit_object_ray: o' = L⁻¹·(o − t) along d'/|d'| with d' = L⁻¹·d, and `shrink` = 1/|d'|, which brings an
// object-space t back to the world's. One reciprocal of |d'| serves the three components and both ends of a span
// (the thesis's shared denominator).
struct UnitObjectRays {
    RayPacket rays;
    vfloat4 shrink;
};

template <typename P>
UnitObjectRays unit_object_rays(const math::Matrix3<vfloat4>& inverse, const Vec3x4& translation,
                                const RayPacket& rays) {
    Vec3x4 origin = mutated<Mutant::transform_order_swapped> ? inverse * rays.origin - translation
                                                             : inverse * (rays.origin - translation);
    Vec3x4 direction = inverse * rays.direction;
    vfloat4 shrink = reciprocal<P>(sqrt(dot<P>(direction, direction)));
    return {RayPacket(origin, shrink * direction, rays.active), shrink};
}

// The primitive's span along the object ray, and t = t'/|d'|. Not inlined, unlike the other kernels: inlined, its
// three instances grew every per-type loop past what GCC inlines into the walks, and scenes without transforms paid
// 3 % more instructions for it.
template <typename P, typename Inner>
__attribute__((noinline)) Span4 span_of(const TransformedShape<Inner>& shape, const RayPacket& rays) {
    UnitObjectRays object = unit_object_rays<P>(shape.inverse, shape.translation, rays);
    if constexpr (uses_inverse_direction<Inner>) {
        object.rays.compute_inverse_direction<P>();
    }
    Span4 span = span_of<P>(shape.inner, object.rays);
    span.enter = span.enter * object.shrink;
    span.exit = span.exit * object.shrink;
    return span;
}

// A surface in an object's space under a transform: a transformed primitive's (TransformedSurface), or a solid
// shape's part as an instance places it (PlacedPartSurface).
template <typename S>
concept PlacedSurface = requires(const S& surface) {
    surface.inner();
    surface.to_world();
    surface.norms();
};

// A solid shape's part (its surface in the shape's space) under an instance's transform and norms: the rules of a
// transformed primitive's surface, without a record of its own.
template <typename InnerSurface>
class PlacedPartSurface {
public:
    PlacedPartSurface(const InnerSurface& part, const math::Transform<float>& to_world,
                      const scene::TransformNorms<float>& norms)
        : part_(part), to_world_(to_world), norms_(norms) {}

    const InnerSurface& inner() const { return part_; }
    const math::Transform<float>& to_world() const { return to_world_; }
    const scene::TransformNorms<float>& norms() const { return norms_; }

private:
    const InnerSurface& part_;
    const math::Transform<float>& to_world_;
    const scene::TransformNorms<float>& norms_;
};

// The primitive's outward normal at the object-space point, through the inverse transpose (not yet unit).
template <PlacedSurface Surface>
Vec3 outward_normal(const Surface& surface, std::int32_t face, Vec3 point, bool& needs_normalizing) {
    bool inner_needs_normalizing = false;
    Vec3 object_normal =
        outward_normal(surface.inner(), face, surface.to_world().point_to_object(point), inner_needs_normalizing);
    needs_normalizing = mutated<Mutant::transformed_normal_not_renormalized> ? inner_needs_normalizing : true;
    return mutated<Mutant::transformed_normal_through_matrix> ? surface.to_world().linear * object_normal
                                                              : surface.to_world().normal_to_world(object_normal);
}

// As the reference's surface_point: re-projected in object space by the primitive's own anchor, carried back,
// and the anchor returned as the point itself (radius 0, no own rounding); the spawn offset carried through both
// trips (scene::transformed_spawn_offset).
template <PlacedSurface Surface>
SurfaceAnchor surface_anchor(const Surface& surface, std::int32_t face, float turned, Vec3 point) {
    const math::Transform<float>& m = surface.to_world();
    Vec3 object_point = m.point_to_object(point);
    bool needs_normalizing = false;
    Vec3 outward = outward_normal(surface.inner(), face, object_point, needs_normalizing);
    SurfaceAnchor inner = surface_anchor(surface.inner(), face, turned, object_point);
    Vec3 projected = object_point;
    if (!(outward == Vec3{})) {
        Vec3 unit = turned * math::normalize_by_reciprocal(outward);
        float off_surface =
            std::fabs(std::fabs(math::dot(unit, object_point - inner.anchor)) - std::fabs(inner.radius));
        if (off_surface > inner.own_rounding) {
            projected = inner.anchor + inner.radius * unit;
        }
    }
    Vec3 world = projected == object_point ? point : m.point_to_world(projected);
    float object_extent = math::max_abs_component(projected);
    float offset = scene::transformed_spawn_offset(surface.norms(), inner.spawn_offset.at(object_extent), object_extent,
                                                   math::max_abs_component(world));
    return {world, 0.0f, 0.0f, {offset, 0.0f}};
}

}  // namespace twinray::sse
