// Numeric rules both tracers share (docs/numerics.md): the bound on n rounded operations and which rays
// are traced at all. The formulas that compute intersections are written once per tracer on purpose —
// the oracle must not share kernels with what it judges — but the rules that say how far to trust them
// are facts of floating point, stated once here.
#pragma once

#include "math/vec3.h"

#include <cmath>
#include <limits>

namespace twinray::math {

// γ(n) = n·u/(1 − n·u), u = ε/2 the unit roundoff: a bound on the relative error of n rounded operations
// (Higham, "Accuracy and Stability of Numerical Algorithms" §3.1; pbrt-v4 uses the same).
template <typename T>
constexpr T rounding_bound(int n) {
    constexpr T u = std::numeric_limits<T>::epsilon() / T(2);
    return static_cast<T>(n) * u / (T(1) - static_cast<T>(n) * u);
}

// `value` in T, rounded towards +∞ (rounded_up) or −∞ (rounded_down) rather than to nearest: a bound or a box in
// double that must still hold once in T.
template <typename T>
T rounded_up(double value) {
    T out = static_cast<T>(value);
    return static_cast<double>(out) < value ? std::nextafter(out, std::numeric_limits<T>::infinity()) : out;
}
template <typename T>
T rounded_down(double value) {
    T out = static_cast<T>(value);
    return static_cast<double>(out) > value ? std::nextafter(out, -std::numeric_limits<T>::infinity()) : out;
}

// A bound of the form size + point_factor·|p|∞: how far a re-projected point may be off its surface, or
// how far off it a secondary ray must start. Both terms scale with the primitive's size and where it
// stands, never with how far the ray travelled (docs/numerics.md).
template <typename T>
struct SurfaceBound {
    T size{};
    T point_factor{};

    T at(T largest_coordinate) const { return size + point_factor * largest_coordinate; }
};

// Per primitive: `own_rounding`, below which a hit point is not re-projected (it is already within the
// projection's own rounding of the surface), and `spawn_offset`, how far off the surface secondary rays
// start. The derivations sit beside each primitive's re-projection in reference/ (sphere.h, plane.h, ...).
template <typename T>
struct SurfaceBounds {
    SurfaceBound<T> own_rounding;
    SurfaceBound<T> spawn_offset;
};

// A ray is traced only if every component is finite and its direction of unit length (within 1e-3):
// anything else (NaN, infinity, a zero or unnormalised direction) has no defined hit and is a miss.
template <typename T>
bool is_traceable(const Vec3<T>& origin, const Vec3<T>& direction) {
    return is_finite(origin) && is_finite(direction) && std::fabs(dot(direction, direction) - T(1)) <= T(1e-3);
}

}  // namespace twinray::math
