// One ray against four primitives: the ray broadcast to all lanes, and the four spans that come back.
#pragma once

#include "sse/simd.h"
#include "sse/tracer.h"

#include <cstdint>
#include <limits>

namespace twinray::sse {

constexpr float infinity = std::numeric_limits<float>::infinity();

struct Ray4 {
    vfloat4 origin[3];
    vfloat4 direction[3];
    vfloat4 inverse_direction[3];  // 1/d per axis, IEEE division, once per ray (boxes use it)
    bool parallel[3];              // d[axis] == 0: that axis's slabs bound nothing
    bool forward[3];               // d[axis] > 0

    // The reciprocals cost three divisions per ray: only scenes with boxes (or CSG bounds) ask for them.
    Ray4(const Ray& ray, bool with_inverse_direction) {
        for (int axis = 0; axis < 3; ++axis) {
            origin[axis] = vfloat4(ray.origin[axis]);
            direction[axis] = vfloat4(ray.direction[axis]);
            if (with_inverse_direction) {
                inverse_direction[axis] = vfloat4(1.0f / ray.direction[axis]);
            }
            parallel[axis] = ray.direction[axis] == 0.0f;
            forward[axis] = ray.direction[axis] > 0.0f;
        }
    }
};

// Per lane, the closed interval of the ray's line inside the primitive ([enter, exit], either may be
// infinite for planes) and which face bounds each end (meaning per primitive type). Lanes where
// `valid` is false miss; padding lanes hold NaN parameters and are never valid.
struct Span4 {
    vfloat4 enter, exit;
    vint4 enter_face, exit_face;
    vbool4 valid;
};

inline vfloat4 dot3(const vfloat4 a[3], const vfloat4 b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace twinray::sse
