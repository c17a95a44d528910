// A thin layer over SSE4.1 so the kernels read like the formulas they compute (after Embree's
// vfloat4/vbool4): four floats, four ints, four-lane masks. Every function is one or two instructions.
// Only the SSE tracer's own translation units include this; they alone are built with -msse4.1.
#pragma once

#include "math/vec3.h"

#include <smmintrin.h>

#include <cstdint>

// Kernels are inlined into their loops even when large (the cylinder's is): a call would pass the
// four spans through memory, which costs more than the kernel saves in code size.
#define TWINRAY_KERNEL inline __attribute__((always_inline))

namespace twinray::sse {

struct vbool4 {
    __m128 m;
};

struct vfloat4 {
    __m128 m;

    vfloat4() : m(_mm_setzero_ps()) {}
    explicit vfloat4(__m128 v) : m(v) {}
    explicit vfloat4(float s) : m(_mm_set1_ps(s)) {}
    static vfloat4 load(const float* aligned) { return vfloat4(_mm_load_ps(aligned)); }
    void store(float* aligned) const { _mm_store_ps(aligned, m); }
    float lane(int i) const {
        alignas(16) float lanes[4];
        _mm_store_ps(lanes, m);
        return lanes[i];
    }
};

struct vint4 {
    __m128i m;

    vint4() : m(_mm_setzero_si128()) {}
    explicit vint4(__m128i v) : m(v) {}
    explicit vint4(std::int32_t s) : m(_mm_set1_epi32(s)) {}
    static vint4 load(const std::int32_t* aligned) {
        return vint4(_mm_load_si128(reinterpret_cast<const __m128i*>(aligned)));
    }
    void store(std::int32_t* aligned) const { _mm_store_si128(reinterpret_cast<__m128i*>(aligned), m); }
};

inline vfloat4 operator+(vfloat4 a, vfloat4 b) {
    return vfloat4(_mm_add_ps(a.m, b.m));
}
inline vfloat4 operator-(vfloat4 a, vfloat4 b) {
    return vfloat4(_mm_sub_ps(a.m, b.m));
}
inline vfloat4 operator*(vfloat4 a, vfloat4 b) {
    return vfloat4(_mm_mul_ps(a.m, b.m));
}
inline vfloat4 operator/(vfloat4 a, vfloat4 b) {
    return vfloat4(_mm_div_ps(a.m, b.m));
}
inline vfloat4 operator-(vfloat4 a) {
    return vfloat4(_mm_xor_ps(a.m, _mm_set1_ps(-0.0f)));
}
inline vfloat4 min(vfloat4 a, vfloat4 b) {
    return vfloat4(_mm_min_ps(a.m, b.m));
}
inline vfloat4 max(vfloat4 a, vfloat4 b) {
    return vfloat4(_mm_max_ps(a.m, b.m));
}
inline vfloat4 sqrt(vfloat4 a) {
    return vfloat4(_mm_sqrt_ps(a.m));
}
inline vfloat4 abs(vfloat4 a) {
    return vfloat4(_mm_andnot_ps(_mm_set1_ps(-0.0f), a.m));
}
// The magnitude of a with the sign of b.
inline vfloat4 copysign(vfloat4 a, vfloat4 b) {
    __m128 sign = _mm_set1_ps(-0.0f);
    return vfloat4(_mm_or_ps(_mm_andnot_ps(sign, a.m), _mm_and_ps(sign, b.m)));
}

// Comparisons are ordered: a lane holding NaN compares false, so NaN never counts as a hit.
inline vbool4 operator<(vfloat4 a, vfloat4 b) {
    return {_mm_cmplt_ps(a.m, b.m)};
}
inline vbool4 operator<=(vfloat4 a, vfloat4 b) {
    return {_mm_cmple_ps(a.m, b.m)};
}
inline vbool4 operator>(vfloat4 a, vfloat4 b) {
    return {_mm_cmpgt_ps(a.m, b.m)};
}
inline vbool4 operator>=(vfloat4 a, vfloat4 b) {
    return {_mm_cmpge_ps(a.m, b.m)};
}
inline vbool4 operator==(vfloat4 a, vfloat4 b) {
    return {_mm_cmpeq_ps(a.m, b.m)};
}
inline vbool4 operator&(vbool4 a, vbool4 b) {
    return {_mm_and_ps(a.m, b.m)};
}
inline vbool4 operator|(vbool4 a, vbool4 b) {
    return {_mm_or_ps(a.m, b.m)};
}
inline vbool4 operator!(vbool4 a) {
    return {_mm_xor_ps(a.m, _mm_castsi128_ps(_mm_set1_epi32(-1)))};
}
inline vbool4 operator==(vint4 a, vint4 b) {
    return {_mm_castsi128_ps(_mm_cmpeq_epi32(a.m, b.m))};
}
inline vbool4 operator<(vint4 a, vint4 b) {
    return {_mm_castsi128_ps(_mm_cmplt_epi32(a.m, b.m))};
}
inline vint4 operator|(vint4 a, vint4 b) {
    return vint4(_mm_or_si128(a.m, b.m));
}
inline vint4 operator&(vint4 a, vint4 b) {
    return vint4(_mm_and_si128(a.m, b.m));
}
// All bits set in lanes where the mask is true: lets a mask be combined with integer flags.
inline vint4 as_int(vbool4 a) {
    return vint4(_mm_castps_si128(a.m));
}
// The lanes of the set bits of `bits` (movemask's inverse).
inline vbool4 lanes_of(int bits) {
    vint4 bit(_mm_setr_epi32(1, 2, 4, 8));
    return (vint4(bits) & bit) == bit;
}
inline vbool4 all_true() {
    return {_mm_castsi128_ps(_mm_set1_epi32(-1))};
}
inline vbool4 none_true() {
    return {_mm_setzero_ps()};
}
// Lane i is true where element i of `lanes` is -1 (all bits set), false where it is 0.
inline vbool4 lanes_from(const std::int32_t lanes[4]) {
    return {_mm_castsi128_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(lanes)))};
}

inline int movemask(vbool4 a) {
    return _mm_movemask_ps(a.m);
}
inline bool any(vbool4 a) {
    return movemask(a) != 0;
}
inline bool none(vbool4 a) {
    return movemask(a) == 0;
}

// Rays in a lane mask (a popcount without relying on the POPCNT instruction, which SSE4.1 lacks).
inline std::uint64_t lane_count(vbool4 mask) {
    constexpr std::uint8_t bits[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
    return bits[movemask(mask)];
}

// The least of the four lanes (NaN-free input).
inline float horizontal_min(vfloat4 a) {
    __m128 pairs = _mm_min_ps(a.m, _mm_shuffle_ps(a.m, a.m, _MM_SHUFFLE(2, 3, 0, 1)));
    return _mm_cvtss_f32(_mm_min_ps(pairs, _mm_shuffle_ps(pairs, pairs, _MM_SHUFFLE(1, 0, 3, 2))));
}

// Lane-wise `mask ? a : b` (SSE4.1 blendv).
inline vfloat4 select(vbool4 mask, vfloat4 a, vfloat4 b) {
    return vfloat4(_mm_blendv_ps(b.m, a.m, mask.m));
}
inline vbool4 select_mask(vbool4 mask, vbool4 a, vbool4 b) {
    return {_mm_blendv_ps(b.m, a.m, mask.m)};
}
inline vint4 select(vbool4 mask, vint4 a, vint4 b) {
    return vint4(_mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(b.m), _mm_castsi128_ps(a.m), mask.m)));
}

// Four 3-vectors, one per lane: a packet's origins, directions, normals, colours. The same Vec3 as all
// scalar code (math/vec3.h) on vfloat4, so `a - b`, `s * a` and `cross(a, b)` round exactly as their
// scalar twins, lane by lane. Dot products go through the precision policy (dot in precision.h).
using Vec3x4 = math::Vec3<vfloat4>;

inline Vec3x4 broadcast(const math::Vec3<float>& v) {
    return {vfloat4(v.x), vfloat4(v.y), vfloat4(v.z)};
}

// Four parameters of a primitive's record, each stored once: a kernel loads them in one go and spreads each to the
// four lanes with a shuffle. Stored already broadcast they took four times the bytes, and a BVH leaf's records
// four times the cache lines.
struct alignas(16) Packed4 {
    float x, y, z, w;

    __m128 load() const { return _mm_load_ps(&x); }
};

template <int lane>
inline vfloat4 spread(__m128 packed) {
    return vfloat4(_mm_shuffle_ps(packed, packed, _MM_SHUFFLE(lane, lane, lane, lane)));
}
inline Vec3x4 spread_xyz(__m128 packed) {
    return {spread<0>(packed), spread<1>(packed), spread<2>(packed)};
}
inline Vec3x4 select(vbool4 mask, const Vec3x4& a, const Vec3x4& b) {
    return {select(mask, a.x, b.x), select(mask, a.y, b.y), select(mask, a.z, b.z)};
}
inline Vec3x4 abs(const Vec3x4& a) {
    return {abs(a.x), abs(a.y), abs(a.z)};
}
inline vfloat4 max_abs_component(const Vec3x4& a) {
    return max(abs(a.x), max(abs(a.y), abs(a.z)));
}
// Four floats from each of four records (unaligned), transposed: lane i of vector k is at[i][k]. How a field of
// four records, one per lane, is read into lanes.
struct Transposed4 {
    vfloat4 column[4];
};
TWINRAY_KERNEL Transposed4 load_transposed(const float* const at[4]) {
    __m128 v0 = _mm_loadu_ps(at[0]), v1 = _mm_loadu_ps(at[1]), v2 = _mm_loadu_ps(at[2]), v3 = _mm_loadu_ps(at[3]);
    _MM_TRANSPOSE4_PS(v0, v1, v2, v3);
    return {{vfloat4(v0), vfloat4(v1), vfloat4(v2), vfloat4(v3)}};
}

// Lane `i` of each component, as a scalar vector.
inline math::Vec3<float> lane(const Vec3x4& v, int i) {
    return {v.x.lane(i), v.y.lane(i), v.z.lane(i)};
}

}  // namespace twinray::sse
