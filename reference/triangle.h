// A triangle mesh: a surface, not a solid. The oracle's hit test decides hit or miss exactly — the signs of
// the three edge functions E(a, b) = d·((a − o) × (b − o)) of the ray (o, d), from exact arithmetic
// (math/exact_predicates.h), with a ray exactly through an edge or a vertex given to one triangle by
// Simulation of Simplicity — so a ray crossing a closed mesh meets exactly one of the triangles around the
// point where it crosses, in T = float as in T = double. t, the normal and the barycentrics are then
// computed in T, as every other primitive's.
#pragma once

#include "math/exact_predicates.h"
#include "reference/bvh.h"
#include "reference/ray.h"
#include "reference/transformed.h"
#include "render/render.h"
#include "scene/geometry.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>
#include <vector>

namespace twinray::reference {

template <typename T>
struct MeshShape {
    std::vector<Vec3<T>> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;  // as in the file: a hit names one by its index here
    std::vector<Vec3<T>> normals;                         // per vertex, where the mesh shades smooth; else empty
    std::vector<std::uint32_t> live;                      // the triangles that can be hit (not degenerate)
    ObjectBvh<T> bvh;                                     // over `live`, or empty: every ray tests every one
    int leaf = -1;
};

// Where a ray meets one triangle. `front`: the ray meets its front (counter-clockwise side), so it enters.
template <typename T>
struct TriangleCrossing {
    T t{};
    std::uint32_t triangle = 0;
    bool front = false;
};

namespace detail {

template <typename T>
std::array<double, 3> exactly(Vec3<T> v) {
    return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}

}  // namespace detail

// A triangle that rounding its vertices to T makes degenerate, or infinite, is never hit. Degenerate: its three edge
// functions sum to d·((b − a) × (c − a)) = 0 at every perturbed origin, so their signs never agree. Skipping it
// changes no answer and spares the exact fallback its zero edge functions (in float, a mesh moved 1e7 from the origin
// collapses onto the grid of 1: most of its triangles, every ray that reaches them, all three edges). Infinite: a
// vertex beyond float's range (3.4e38) has no place on the triangle's plane; in double every vertex the loader gives
// is finite, and the predicates are exact for every finite input.
template <typename T>
bool lost_once_rounded(const MeshShape<T>& shape, std::uint32_t triangle) {
    if constexpr (std::is_same_v<T, double>) {
        return false;  // the loader's exact test saw these very vertices, all finite
    } else {
        const std::array<std::uint32_t, 3>& corners = shape.triangles[triangle];
        for (std::uint32_t corner : corners) {
            if (!math::is_finite(shape.vertices[corner])) {
                return true;
            }
        }
        return math::exactly_collinear(detail::exactly(shape.vertices[corners[0]]),
                                       detail::exactly(shape.vertices[corners[1]]),
                                       detail::exactly(shape.vertices[corners[2]]));
    }
}

// A mesh's triangles in T (a mesh of `objects` in world coordinates, a shape in its own), with `leaf`.
template <typename T>
MeshShape<T> make_shape(const scene::MeshData& data, int leaf, Accel accel) {
    MeshShape<T> shape;
    shape.leaf = leaf;
    shape.triangles = data.triangles;
    shape.vertices.reserve(data.vertices.size());
    for (const scene::Vec3& vertex : data.vertices) {
        shape.vertices.push_back(Vec3<T>(vertex));
    }
    if (data.smooth) {
        for (const scene::Vec3& normal : data.normals) {
            shape.normals.push_back(Vec3<T>(normal));
        }
    }
    std::vector<scene::Bounds> bounds;
    scene::for_each_live_triangle(data, [&](std::uint32_t i) {
        if (lost_once_rounded(shape, i)) {
            return;
        }
        shape.live.push_back(i);
        // The box of the vertices in T (each within one rounding of the file's): the BVH's padding covers it.
        bounds.push_back(scene::bounds(data, data.triangles[i]));
    });
    if (accel == Accel::bvh || (accel == Accel::automatic && shape.live.size() > bvh_crossover)) {
        shape.bvh = ObjectBvh<T>(bounds);
    }
    return shape;
}

template <typename T>
MeshShape<T> make_shape(const scene::Mesh& mesh, Accel accel) {
    return make_shape<T>(*mesh.data, mesh.leaf, accel);
}

// The crossing lies on the triangle, so in its box; the plane's t need not: n = (b − a) × (c − a) is rounded by
// about u·|b − a|·|c − a|, which on a sliver reaching far (a vertex at -1.5e10, two within a few units of the
// origin) tilts the plane enough to put t units off the box, even ahead of an origin the crossing lies behind. The
// BVH skips a triangle where the ray's stretch in its box, padded by ObjectBvh::padding of the box's largest
// coordinate and of the origin's, lies beyond the limit or behind the origin; so t is held to the ray's stretch in
// the box widened by half as much, which brute force and the BVH then agree on. A t within that reach (every t of a
// well-conditioned triangle: a few ulps of the distances) is unchanged. An axis the ray is parallel to bounds
// nothing: the exact test found its line crossing the triangle, so within that slab.
template <typename T>
T held_to_box(T t, const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c, const Ray<T>& ray) {
    const T reach = T(ObjectBvh<T>::padding / 2) *
                    (std::fmax(max_abs_component(a), std::fmax(max_abs_component(b), max_abs_component(c))) +
                     max_abs_component(ray.origin));
    T enter = -std::numeric_limits<T>::infinity();
    T leave = std::numeric_limits<T>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
        if (ray.direction[axis] == T(0)) {
            continue;
        }
        T low = (std::fmin(a[axis], std::fmin(b[axis], c[axis])) - reach - ray.origin[axis]) / ray.direction[axis];
        T high = (std::fmax(a[axis], std::fmax(b[axis], c[axis])) + reach - ray.origin[axis]) / ray.direction[axis];
        enter = std::fmax(enter, std::fmin(low, high));
        leave = std::fmin(leave, std::fmax(low, high));
    }
    return std::fmin(std::fmax(t, enter), leave);
}

// Hit when the three perturbed edge signs agree (both sides: no back-face culling). Their sum is
// d·((b − a) × (c − a)) exactly, so agreeing signs also decide the side exactly: all negative, the ray meets
// the front. t = ((a − o)·n) / (d·n) with n = (b − a) × (c − a), in T; a denominator that rounds to 0 (a ray
// within rounding of the triangle's plane) gives no finite t and is a miss, and so does a t whose products overflow;
// t is then held to the triangle's box (held_to_box), and a t not past 0 is a miss.
template <typename T>
std::optional<TriangleCrossing<T>> crossing_of(const MeshShape<T>& mesh, std::uint32_t triangle, const Ray<T>& ray) {
    const std::array<std::uint32_t, 3>& corners = mesh.triangles[triangle];
    const Vec3<T>& a = mesh.vertices[corners[0]];
    const Vec3<T>& b = mesh.vertices[corners[1]];
    const Vec3<T>& c = mesh.vertices[corners[2]];
    const std::array<double, 3> o = detail::exactly(ray.origin), d = detail::exactly(ray.direction);
    const std::array<double, 3> va = detail::exactly(a), vb = detail::exactly(b), vc = detail::exactly(c);
    int side = math::sign_of_ray_edge_perturbed(o, d, va, vb);
    if (side == 0 || math::sign_of_ray_edge_perturbed(o, d, vb, vc) != side ||
        math::sign_of_ray_edge_perturbed(o, d, vc, va) != side) {
        return std::nullopt;
    }
    Vec3<T> n = cross(b - a, c - a);
    T t = dot(a - ray.origin, n) / dot(ray.direction, n);
    if (!std::isfinite(t)) {
        return std::nullopt;
    }
    t = held_to_box(t, a, b, c, ray);
    if (!(t > T(0))) {
        return std::nullopt;
    }
    return TriangleCrossing<T>{t, triangle, side < 0};
}

// Calls visit(crossing) for every triangle the ray meets with t in (0, limit()], in no particular order;
// limit() is read again at every BVH node.
template <typename T, typename Limit, typename Visit>
void for_each_crossing(const MeshShape<T>& mesh, const Ray<T>& ray, Limit&& limit, Visit&& visit) {
    auto test = [&](std::uint32_t live_index) {
        if (std::optional<TriangleCrossing<T>> crossing = crossing_of(mesh, mesh.live[live_index], ray)) {
            if (crossing->t <= limit()) {
                visit(*crossing);
            }
        }
    };
    if (mesh.bvh.empty()) {
        for (std::uint32_t i = 0; i < mesh.live.size(); ++i) {
            test(i);
        }
        return;
    }
    mesh.bvh.for_each_met(ray, limit, test);
}

// The unit geometric normal of the triangle's front.
template <typename T>
Vec3<T> front_normal(const MeshShape<T>& mesh, std::uint32_t triangle) {
    const std::array<std::uint32_t, 3>& corners = mesh.triangles[triangle];
    const Vec3<T>& a = mesh.vertices[corners[0]];
    return normalize(cross(mesh.vertices[corners[1]] - a, mesh.vertices[corners[2]] - a));
}

// The interpolated normal at `point` (barycentric weights from the sub-triangles' areas along n), turned to
// `facing` (the geometric normal facing the ray) where it faces away from it; `facing` itself for a flat mesh.
template <typename T>
Vec3<T> shading_normal(const MeshShape<T>& mesh, std::uint32_t triangle, Vec3<T> point, Vec3<T> facing) {
    if (mesh.normals.empty()) {
        return facing;
    }
    const std::array<std::uint32_t, 3>& corners = mesh.triangles[triangle];
    const Vec3<T>& a = mesh.vertices[corners[0]];
    const Vec3<T>& b = mesh.vertices[corners[1]];
    const Vec3<T>& c = mesh.vertices[corners[2]];
    Vec3<T> n = cross(b - a, c - a);
    T area = dot(n, n);
    T weight_a = dot(n, cross(c - b, point - b)) / area;
    T weight_b = dot(n, cross(a - c, point - c)) / area;
    T weight_c = T(1) - weight_a - weight_b;
    Vec3<T> interpolated =
        weight_a * mesh.normals[corners[0]] + weight_b * mesh.normals[corners[1]] + weight_c * mesh.normals[corners[2]];
    if (!(dot(interpolated, interpolated) > T(0))) {
        return facing;
    }
    Vec3<T> unit = normalize(interpolated);
    return dot(unit, facing) < T(0) ? -unit : unit;
}

// p' = p + ((a − p)·n̂)·n̂, the plane's projection measured from a vertex: a − p is at most about the longest
// edge e (p lies on the triangle within rounding), so the height is rounded within γ(4)·√3·e and n̂ is
// unit within γ(4): p' lies within γ(6)·e + γ(3)·|p'|∞ of the plane (the sum adds one rounding per
// component and p's own). The next ray decides its side by the sign of (a − o)·n, within γ(9)·e of the
// plane for an origin within e; with p' off the plane and the origin's rounding γ(2)·|p'|∞ the offset is
// γ(16)·e + γ(5)·|p'|∞ (scene::surface_bounds_of_triangle).
template <typename T>
SurfacePoint<T> surface_point(const MeshShape<T>& mesh, std::uint32_t triangle, Vec3<T> point, Vec3<T> normal) {
    const std::array<std::uint32_t, 3>& corners = mesh.triangles[triangle];
    const Vec3<T>& a = mesh.vertices[corners[0]];
    T longest = T(0);
    for (int i = 0; i < 3; ++i) {
        longest = std::fmax(longest, length(mesh.vertices[corners[(i + 1) % 3]] - mesh.vertices[corners[i]]));
    }
    math::SurfaceBounds<T> bounds = scene::surface_bounds_of_triangle(longest);
    T height = dot(a - point, normal);
    T own_rounding = bounds.own_rounding.at(max_abs_component(point));
    Vec3<T> projected = std::fabs(height) > own_rounding ? point + height * normal : point;
    return {projected, bounds.spawn_offset.at(max_abs_component(projected))};
}

// A hit on an instance: the point re-projected in object space by the triangle's own rule and carried back
// (transformed.h's placed_surface_point), its spawn offset carried through both trips.
template <typename T>
SurfacePoint<T> surface_point(const Instance<T>& instance, const MeshShape<T>& shape, std::uint32_t triangle,
                              Vec3<T> point) {
    return placed_surface_point(instance.to_world, instance.norms, point, [&](Vec3<T> object_point) {
        return surface_point(shape, triangle, object_point, front_normal(shape, triangle));
    });
}

// The geometric normal of the placed triangle's side the ray met, through the inverse transpose.
template <typename T>
Vec3<T> facing_normal(const Instance<T>& instance, const MeshShape<T>& shape, const TriangleCrossing<T>& crossing) {
    Vec3<T> front = front_normal(shape, crossing.triangle);
    return normalize(instance.to_world.normal_to_world(crossing.front ? front : -front));
}

// The shape's interpolated normal at the point's object-space image, carried out through the inverse transpose
// and turned to `facing` in the world (the turn is not kept by the transform: it keeps sides, not angles).
template <typename T>
Vec3<T> shading_normal(const Instance<T>& instance, const MeshShape<T>& shape, std::uint32_t triangle, Vec3<T> point,
                       Vec3<T> facing) {
    if (shape.normals.empty()) {
        return facing;
    }
    const math::Transform<T>& m = instance.to_world;
    Vec3<T> object_front = front_normal(shape, triangle);
    Vec3<T> unit =
        normalize(m.normal_to_world(shading_normal(shape, triangle, m.point_to_object(point), object_front)));
    return dot(unit, facing) < T(0) ? -unit : unit;
}

}  // namespace twinray::reference
