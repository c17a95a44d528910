// The one 3-vector of twinray's scalar code: the scene model (Vec3<double>), both tracers' scalar math
// (Vec3<double>, Vec3<float>), ray trees and tools. The SSE tracer also instantiates it on vfloat4 for
// four rays at once (sse/simd.h). Only the textbook operations, each with the one obvious order of
// rounded operations, so a formula written with them rounds the same wherever it is written.
#pragma once

#include <cmath>
#include <type_traits>

namespace twinray::math {

template <typename T>
struct Vec3 {
    T x{}, y{}, z{};

    constexpr Vec3() = default;
    constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    // Between precisions: each component rounded once.
    template <typename U>
    requires(std::is_arithmetic_v<T>&& std::is_arithmetic_v<U> &&
             !std::is_same_v<T, U>) constexpr explicit Vec3(const Vec3<U>& v)
        : x(static_cast<T>(v.x)), y(static_cast<T>(v.y)), z(static_cast<T>(v.z)) {}

    constexpr T& operator[](int axis) { return axis == 0 ? x : axis == 1 ? y : z; }
    constexpr const T& operator[](int axis) const { return axis == 0 ? x : axis == 1 ? y : z; }

    friend constexpr Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend constexpr Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend constexpr Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
    friend constexpr Vec3 operator*(T s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
    friend constexpr Vec3 operator*(Vec3 a, T s) { return s * a; }
    friend constexpr Vec3 operator/(Vec3 a, T s) { return {a.x / s, a.y / s, a.z / s}; }
    // Component-wise: colour times colour.
    friend constexpr Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
    constexpr Vec3& operator+=(const Vec3& b) { return *this = *this + b; }
    friend constexpr bool operator==(const Vec3& a, const Vec3& b) requires std::is_arithmetic_v<T> {
        return a.x == b.x && a.y == b.y && a.z == b.z;
    }
};

template <typename T>
constexpr T dot(Vec3<T> a, Vec3<T> b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

template <typename T>
constexpr Vec3<T> cross(Vec3<T> a, Vec3<T> b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

template <typename T>
T length(Vec3<T> a) {
    return std::sqrt(dot(a, a));
}

// Three divisions: each component rounded once (the reference's textbook normalisation).
template <typename T>
Vec3<T> normalize(Vec3<T> a) {
    return a / length(a);
}

// One division shared by three numerators, then multiplies: one rounding more per component (≤ 1 ulp)
// for a third of the divisions, the thesis's rule where several numerators share a denominator. The SSE
// tracer normalises this way.
template <typename T>
Vec3<T> normalize_by_reciprocal(Vec3<T> a) {
    return (T(1) / length(a)) * a;
}

template <typename T>
bool is_finite(const Vec3<T>& a) {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

template <typename T>
T max_abs_component(Vec3<T> a) {
    return std::fmax(std::fabs(a.x), std::fmax(std::fabs(a.y), std::fabs(a.z)));
}

}  // namespace twinray::math
