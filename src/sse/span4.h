// Four rays at once (a packet, one ray per lane) against one primitive, and the four spans that come
// back. Every computation is lane-wise: a lane's result never depends on the other lanes, so a ray
// gets the same answer alone (the per-ray API) as inside any packet (render).
#pragma once

#include "sse/precision.h"
#include "sse/simd.h"
#include "sse/tracer.h"

#include <cstdint>
#include <limits>

namespace twinray::sse {

constexpr float infinity = std::numeric_limits<float>::infinity();

struct RayPacket {
    vfloat4 origin[3];
    vfloat4 direction[3];          // unit length
    vfloat4 inverse_direction[3];  // 1/d (reciprocal<P>); filled only for scenes that test boxes
    vbool4 active;                 // lanes that carry a ray; the others hold a copy of an active ray

    // Lane i traces rays[i]; lanes where `active` is false repeat rays[first active lane].
    RayPacket(const Ray rays[4], vbool4 active_lanes) : active(active_lanes) {
        int mask = movemask(active_lanes);
        int filler = mask == 0 ? 0 : __builtin_ctz(static_cast<unsigned>(mask));
        alignas(16) float lanes[6][4];
        for (int lane = 0; lane < 4; ++lane) {
            const Ray& ray = rays[((mask >> lane) & 1) ? lane : filler];
            for (int axis = 0; axis < 3; ++axis) {
                lanes[axis][lane] = ray.origin[axis];
                lanes[3 + axis][lane] = ray.direction[axis];
            }
        }
        for (int axis = 0; axis < 3; ++axis) {
            origin[axis] = vfloat4::load(lanes[axis]);
            direction[axis] = vfloat4::load(lanes[3 + axis]);
        }
    }

    RayPacket(const vfloat4 origins[3], const vfloat4 directions[3], vbool4 active_lanes) : active(active_lanes) {
        for (int axis = 0; axis < 3; ++axis) {
            origin[axis] = origins[axis];
            direction[axis] = directions[axis];
        }
    }

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
// infinite for planes) and which face bounds each end (meaning per primitive type). Lanes where
// `valid` is false miss.
struct Span4 {
    vfloat4 enter, exit;
    vint4 enter_face, exit_face;
    vbool4 valid;
};

}  // namespace twinray::sse
