// The camera of docs/scene-format.md: horizontal field of view, image plane at distance 1, pixel centres
// at (x + ½, y + ½). Both tracers build this basis in their own precision and with their own
// normalisation (the reference divides each component, the SSE tracer multiplies by one reciprocal).
#pragma once

#include "math/vec3.h"

#include <cmath>
#include <numbers>

namespace twinray::math {

template <typename T>
struct CameraBasis {
    Vec3<T> eye, forward, right, up;
    T half_width{};  // tan(fov/2)
};

// `unit` is the tracer's normalisation (normalize or normalize_by_reciprocal).
template <typename T, typename Normalize>
CameraBasis<T> camera_basis(Vec3<T> eye, Vec3<T> look_at, Vec3<T> sky, double fov_deg, Normalize unit) {
    Vec3<T> forward = unit(look_at - eye);
    Vec3<T> right = unit(cross(forward, sky));
    Vec3<T> up = cross(right, forward);
    T half_width = static_cast<T>(std::tan(fov_deg * std::numbers::pi / 360.0));
    return {eye, forward, right, up, half_width};
}

}  // namespace twinray::math
