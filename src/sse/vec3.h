// The SSE tracer's scalar 3-vector: its per-ray API, scene compilation and normals. The hot math does
// not use it: it runs four rays at a time, one per vfloat4 lane (simd.h, tracer.cpp). Keeping one
// 3-vector per __m128 with _mm_dp_ps was the 2009 thesis's design; it wastes a lane and serialises on
// the horizontal add.
#pragma once

#include "scene/scene.h"

#include <cmath>

namespace twinray::sse {

struct Vec3 {
    float x = 0, y = 0, z = 0;

    Vec3() = default;
    Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    explicit Vec3(const scene::Vec3& v)
        : x(static_cast<float>(v[0])), y(static_cast<float>(v[1])), z(static_cast<float>(v[2])) {}

    float operator[](int axis) const { return axis == 0 ? x : axis == 1 ? y : z; }

    friend Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
    friend Vec3 operator*(float s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
    friend Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
    friend Vec3 operator/(Vec3 a, float s) { return {a.x / s, a.y / s, a.z / s}; }
    Vec3& operator+=(Vec3 b) { return *this = *this + b; }
};

inline float dot(Vec3 a, Vec3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3 a) {
    return std::sqrt(dot(a, a));
}
// One IEEE division shared by three numerators, then multiplies: one rounding more than dividing each
// component (≤ 1 ulp), for a third of the divisions, which dominate the cost of shading.
inline Vec3 normalize(Vec3 a) {
    return (1.0f / length(a)) * a;
}
inline float max_abs_component(Vec3 a) {
    return std::fmax(std::fabs(a.x), std::fmax(std::fabs(a.y), std::fabs(a.z)));
}

using Color = Vec3;

}  // namespace twinray::sse
