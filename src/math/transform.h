// Affine maps p ↦ L·p + t between an object's space and the world: the scene model (double), both tracers'
// scalar code (double, float) and the SSE tracer's four rays at once (vfloat4). L's inverse is kept beside
// it, computed once in double, so no tracer inverts a matrix. A point goes into object space as L⁻¹·(p − t),
// never as L⁻¹·p − L⁻¹·t: far from the origin p − t is small and nearly exact, where L⁻¹·p and L⁻¹·t would
// cancel (docs/numerics.md, "Transforms").
#pragma once

#include "math/vec3.h"

#include <algorithm>
#include <cmath>

namespace twinray::math {

template <typename T>
struct Matrix3 {
    Vec3<T> row[3];

    template <typename U>
    static Matrix3 from(const Matrix3<U>& m) {
        return {{Vec3<T>(m.row[0]), Vec3<T>(m.row[1]), Vec3<T>(m.row[2])}};
    }
};

template <typename T>
Vec3<T> operator*(const Matrix3<T>& m, Vec3<T> v) {
    return {dot(m.row[0], v), dot(m.row[1], v), dot(m.row[2], v)};
}

// mᵀ·v without forming mᵀ.
template <typename T>
Vec3<T> transposed_times(const Matrix3<T>& m, Vec3<T> v) {
    return {m.row[0].x * v.x + m.row[1].x * v.y + m.row[2].x * v.z,
            m.row[0].y * v.x + m.row[1].y * v.y + m.row[2].y * v.z,
            m.row[0].z * v.x + m.row[1].z * v.y + m.row[2].z * v.z};
}

template <typename T>
struct Transform {
    Matrix3<T> linear;   // L: object to world
    Matrix3<T> inverse;  // L⁻¹
    Vec3<T> translation;

    template <typename U>
    static Transform from(const Transform<U>& m) {
        return {Matrix3<T>::from(m.linear), Matrix3<T>::from(m.inverse), Vec3<T>(m.translation)};
    }

    Vec3<T> point_to_world(Vec3<T> p) const { return linear * p + translation; }
    Vec3<T> point_to_object(Vec3<T> p) const { return inverse * (p - translation); }
    Vec3<T> direction_to_object(Vec3<T> d) const { return inverse * d; }
    // Normals go through the inverse transpose, which keeps them perpendicular to the mapped surface.
    Vec3<T> normal_to_world(Vec3<T> n) const { return transposed_times(inverse, n); }
    Vec3<T> normal_to_object(Vec3<T> n) const { return transposed_times(linear, n); }
};

template <typename T>
Matrix3<T> identity_matrix() {
    return {{{T(1), T(0), T(0)}, {T(0), T(1), T(0)}, {T(0), T(0), T(1)}}};
}

template <typename T>
Matrix3<T> product(const Matrix3<T>& a, const Matrix3<T>& b) {
    Matrix3<T> out;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            out.row[i][j] = a.row[i][0] * b.row[0][j] + a.row[i][1] * b.row[1][j] + a.row[i][2] * b.row[2][j];
        }
    }
    return out;
}

template <typename T>
T determinant(const Matrix3<T>& m) {
    return dot(m.row[0], cross(m.row[1], m.row[2]));
}

// The adjugate over the determinant; for a matrix the caller has found invertible.
template <typename T>
Matrix3<T> inverse_of(const Matrix3<T>& m) {
    T det = determinant(m);
    Vec3<T> c0 = cross(m.row[1], m.row[2]), c1 = cross(m.row[2], m.row[0]), c2 = cross(m.row[0], m.row[1]);
    return {{Vec3<T>{c0.x, c1.x, c2.x} / det, Vec3<T>{c0.y, c1.y, c2.y} / det, Vec3<T>{c0.z, c1.z, c2.z} / det}};
}

// ‖m‖_F, an upper bound on the largest singular value (‖m‖₂ ≤ ‖m‖_F ≤ √3·‖m‖₂).
template <typename T>
T frobenius_norm(const Matrix3<T>& m) {
    return std::sqrt(dot(m.row[0], m.row[0]) + dot(m.row[1], m.row[1]) + dot(m.row[2], m.row[2]));
}

// ‖m‖∞, the largest row sum of |entries|: |m·v|∞ ≤ ‖m‖∞·|v|∞.
template <typename T>
T row_sum_norm(const Matrix3<T>& m) {
    T out = 0;
    for (const Vec3<T>& r : m.row) {
        out = std::max(out, std::fabs(r.x) + std::fabs(r.y) + std::fabs(r.z));
    }
    return out;
}

// `inner` first, then `outer`: x ↦ outer(inner(x)).
template <typename T>
Transform<T> composed(const Transform<T>& outer, const Transform<T>& inner) {
    Matrix3<T> linear = product(outer.linear, inner.linear);
    return {linear, inverse_of(linear), outer.linear * inner.translation + outer.translation};
}

}  // namespace twinray::math
