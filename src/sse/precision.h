// The SSE tracer's speed/accuracy knobs (issue 7, docs/performance.md) as a compile-time policy: every
// division, normalisation, dot product and quadratic of the kernels and of shading goes through the
// functions below, so one source compiles into one tracer per policy, chosen once per render (no
// branch per ray). `ExactPrecision` is the tracer as it always was: IEEE divide and square root,
// structure-of-arrays dot products, the cancellation-free quadratic. Denormal flushing is not here: it
// is a run-time MXCSR setting (ScopedFlushDenormals), which costs nothing to choose.
#pragma once

#include "sse/simd.h"

#include <pmmintrin.h>

namespace twinray::sse {

template <bool FastReciprocal, bool FastInverseSqrt, bool AosDotProduct, bool TextbookQuadratic,
          bool MollerTrumbore = false>
struct PrecisionPolicy {
    static constexpr bool fast_rcp = FastReciprocal;               // _mm_rcp_ps + one Newton step for 1/x and a/b
    static constexpr bool fast_rsqrt = FastInverseSqrt;            // _mm_rsqrt_ps + one Newton step for 1/|v|
    static constexpr bool dpps = AosDotProduct;                    // transpose to one 3-vector per register, _mm_dp_ps
    static constexpr bool textbook_quadratic = TextbookQuadratic;  // b² − a·c and (−b ± √Δ)/a
    static constexpr bool moller_trumbore = MollerTrumbore;        // triangles by Möller–Trumbore (triangle.h)
};

using ExactPrecision = PrecisionPolicy<false, false, false, false>;

// 1/x. rcpps has 12 bits; one Newton step x₁ = x₀·(2 − a·x₀) brings it to about 22 bits (a few ulp),
// without rounding correctly. rcpps(0) = ∞ and the step then gives NaN (∞·0): every caller masks the
// lanes where the denominator is zero, as it masks the IEEE ∞ there.
template <typename P>
TWINRAY_KERNEL vfloat4 reciprocal(vfloat4 x) {
    if constexpr (P::fast_rcp) {
        vfloat4 estimate(_mm_rcp_ps(x.m));
        return estimate * (vfloat4(2.0f) - x * estimate);
    } else {
        return vfloat4(1.0f) / x;
    }
}

template <typename P>
TWINRAY_KERNEL vfloat4 divide(vfloat4 numerator, vfloat4 denominator) {
    if constexpr (P::fast_rcp) {
        return numerator * reciprocal<P>(denominator);
    } else {
        return numerator / denominator;
    }
}

// 1/√x, for normalising. rsqrtps has 12 bits; one Newton step y₁ = y₀·(1.5 − 0.5·x·y₀²) gives about 22.
template <typename P>
TWINRAY_KERNEL vfloat4 inverse_sqrt(vfloat4 x) {
    if constexpr (P::fast_rsqrt) {
        vfloat4 estimate(_mm_rsqrt_ps(x.m));
        return estimate * (vfloat4(1.5f) - vfloat4(0.5f) * x * estimate * estimate);
    } else {
        return reciprocal<P>(sqrt(x));
    }
}

// Four dot products of 3-vectors stored as structure of arrays (a.x holds the x of four vectors).
// SoA: three multiplies and two adds. The thesis's AoS way, as a packet tracer must pay for
// it: transpose both operands to one vector per register, four dpps, and blend the four results back
// into lanes. dpps sums (p0 + p1) + (p2 + p3) with p3 = 0, the SoA order, so both round alike.
template <typename P>
TWINRAY_KERNEL vfloat4 dot(const Vec3x4& a, const Vec3x4& b) {
    if constexpr (P::dpps) {
        __m128 a0 = a.x.m, a1 = a.y.m, a2 = a.z.m, a3 = _mm_setzero_ps();
        __m128 b0 = b.x.m, b1 = b.y.m, b2 = b.z.m, b3 = _mm_setzero_ps();
        _MM_TRANSPOSE4_PS(a0, a1, a2, a3);
        _MM_TRANSPOSE4_PS(b0, b1, b2, b3);
        __m128 lane0 = _mm_dp_ps(a0, b0, 0x71);
        __m128 lane1 = _mm_dp_ps(a1, b1, 0x72);
        __m128 lane2 = _mm_dp_ps(a2, b2, 0x74);
        __m128 lane3 = _mm_dp_ps(a3, b3, 0x78);
        return vfloat4(_mm_or_ps(_mm_or_ps(lane0, lane1), _mm_or_ps(lane2, lane3)));
    } else {
        return math::dot(a, b);
    }
}

// 1/|a| by the policy's inverse_sqrt; exact, as the scalar normalize_by_reciprocal: one IEEE division
// shared by the three components.
template <typename P>
TWINRAY_KERNEL Vec3x4 normalize(const Vec3x4& a) {
    return inverse_sqrt<P>(dot<P>(a, a)) * a;
}

// Flush-to-zero and denormals-are-zero in MXCSR for as long as it lives (when `enable`), then the
// thread's previous mode back. MXCSR is per thread: whoever traces sets it on its own thread.
class ScopedFlushDenormals {
public:
    explicit ScopedFlushDenormals(bool enable) : enabled_(enable), saved_(enable ? _mm_getcsr() : 0) {
        if (enabled_) {
            _mm_setcsr(saved_ | _MM_FLUSH_ZERO_ON | _MM_DENORMALS_ZERO_ON);
        }
    }
    ~ScopedFlushDenormals() {
        if (enabled_) {
            _mm_setcsr(saved_);
        }
    }
    ScopedFlushDenormals(const ScopedFlushDenormals&) = delete;
    ScopedFlushDenormals& operator=(const ScopedFlushDenormals&) = delete;

private:
    bool enabled_;
    unsigned saved_;
};

}  // namespace twinray::sse
