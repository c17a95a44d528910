// Four rays at once (a packet, one ray per lane) against one primitive, the four spans that come back,
// and what every primitive header provides for a hit's surface. Every computation is lane-wise: a lane's
// result never depends on the other lanes, so a ray gets the same answer alone (the per-ray API) as
// inside any packet (render).
#pragma once

#include "math/rounding.h"
#include "sse/precision.h"
#include "sse/simd.h"
#include "sse/tracer.h"

#include <cstdint>
#include <limits>

namespace twinray::sse {

constexpr float infinity = std::numeric_limits<float>::infinity();

struct RayPacket {
    Vec3x4 origin;
    Vec3x4 direction;          // unit length
    Vec3x4 inverse_direction;  // 1/d (reciprocal<P>); filled only for scenes whose kernels use it
    vbool4 active;             // lanes that carry a ray; the others hold a copy of an active ray

    RayPacket(const Vec3x4& origins, const Vec3x4& directions, vbool4 active_lanes)
        : origin(origins), direction(directions), active(active_lanes) {}

    // Three divisions per packet, shared by the two slabs of every box the rays meet: the thesis's rule
    // of one reciprocal where several numerators share a denominator (one extra rounding in t).
    template <typename P>
    void compute_inverse_direction() {
        for (int axis = 0; axis < 3; ++axis) {
            inverse_direction[axis] = reciprocal<P>(direction[axis]);
        }
    }
};

// Per lane, the closed interval of the ray's line inside the primitive ([enter, exit], either may be
// infinite for planes) and which face bounds each end (a code per primitive type, in its header). Lanes
// where `valid` is false miss.
struct Span4 {
    vfloat4 enter, exit;
    vint4 enter_face, exit_face;
    vbool4 valid;
};

// Where a hit point is re-projected onto its primitive: p' = anchor + radius·n̂ with n̂ the unit outward
// normal (radius 0 on flat faces, where the anchor is p' itself), only where p is farther than
// `own_rounding` from p' (measurably off the surface); and how far off p' its secondary rays start. The
// bounds are the reference's (scene/geometry.h), so both tracers leave surfaces alike.
struct SurfaceAnchor {
    Vec3 anchor;
    float radius = 0;
    float own_rounding = 0;
    math::SurfaceBound<float> spawn_offset;
};

// What testing a packet against one primitive of a kind costs, relative to a sphere: what `--accel auto` weighs
// brute force by against a BVH (compiled_scene.cpp; docs/performance.md, "The crossover of --accel auto"). A kind
// that costs more declares `test_cost` (box.h, transformed.h), measured as the instructions a render spends per
// primitive added.
template <typename Shape>
constexpr double relative_test_cost = [] {
    if constexpr (requires { Shape::test_cost; }) {
        return Shape::test_cost;
    } else {
        return 1.0;
    }
}();

// A kernel that divides by the ray's direction declares `uses_inverse_direction` (box.h): scenes
// without one never compute the reciprocal.
template <typename Shape>
constexpr bool uses_inverse_direction = requires {
    Shape::uses_inverse_direction;
};

}  // namespace twinray::sse
