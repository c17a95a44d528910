// A 3-vector on the tracer's scalar type: the textbook operations and nothing more.
#pragma once

#include "scene/scene.h"

#include <cmath>

namespace twinray::reference {

template <typename T>
struct Vec3 {
    T x{}, y{}, z{};

    constexpr Vec3() = default;
    constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    explicit Vec3(const scene::Vec3& v) : x(static_cast<T>(v[0])), y(static_cast<T>(v[1])), z(static_cast<T>(v[2])) {}

    T operator[](int axis) const { return axis == 0 ? x : axis == 1 ? y : z; }

    friend Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
    friend Vec3 operator*(T s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
    friend Vec3 operator*(Vec3 a, T s) { return s * a; }
    friend Vec3 operator/(Vec3 a, T s) { return {a.x / s, a.y / s, a.z / s}; }
    // Component-wise: colour times colour.
    friend Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
    Vec3& operator+=(Vec3 b) { return *this = *this + b; }
    friend bool operator==(const Vec3&, const Vec3&) = default;
};

template <typename T>
T dot(Vec3<T> a, Vec3<T> b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

template <typename T>
Vec3<T> cross(Vec3<T> a, Vec3<T> b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

template <typename T>
T length(Vec3<T> a) {
    return std::sqrt(dot(a, a));
}

template <typename T>
Vec3<T> normalize(Vec3<T> a) {
    return a / length(a);
}

template <typename T>
T max_abs_component(Vec3<T> a) {
    return std::fmax(std::fabs(a.x), std::fmax(std::fabs(a.y), std::fabs(a.z)));
}

template <typename T>
using Color = Vec3<T>;

}  // namespace twinray::reference
