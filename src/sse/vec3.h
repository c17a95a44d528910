// The SSE tracer's scalar vectors (per-ray API, scene compilation, one hit's normal and surface): twinray's
// one 3-vector (math/vec3.h) in float. The hot math runs four rays at a time on Vec3x4 (simd.h). Keeping
// one 3-vector per __m128 with _mm_dp_ps was the 2009 thesis's design; it wastes a lane and serialises on
// the horizontal add. Normalising here is math::normalize_by_reciprocal, never math::normalize.
#pragma once

#include "math/vec3.h"

namespace twinray::sse {

using Vec3 = math::Vec3<float>;
using Color = Vec3;

}  // namespace twinray::sse
