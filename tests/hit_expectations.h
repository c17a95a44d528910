// Hand-solved first hits, shared by the intersection and CSG tests, run against every tracer:
// reference<double>, reference<float>, the SSE tracer exact and with each knob combination it is built
// for, and the C example behind the tracer ABI (examples/brute_force_tracer.c, through plugin/plugin.h), on the
// scenes whose kinds it intersects. Each tracer is held to the tolerance its precision earns (hit_tolerance below); a hit is checked
// together with the invariants every hit has.
//
// A suite is declared with TWINRAY_HIT_EXPECTATION_SUITE(Name), which instantiates its TEST_Ps once per
// tracer (test names end in the tracer's: .../ReferenceFloat, .../SseRcpRsqrtTextbookFtz); inside them,
// EXPECT_HIT and EXPECT_MISS ask the tracer of the test.
#pragma once

#include "plugin/plugin.h"
#include "reference/tracer.h"
#include "sse/cpu.h"
#include "sse/tracer.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace twinray::test {

using V = reference::Vec3<double>;

struct Expected {
    double t;
    V point;
    V normal;
    int leaf;
    bool entering;
    int triangle = -1;  // on a mesh, the triangle hit
};

enum class TracerKind { reference_double, reference_float, sse, plugin };

// S, the expectations' size scale: every ray below starts within |o|∞ ≤ 20 and hits at t ≤ 20, on objects
// no larger than 4, and |o|∞ + t + 4 ≤ S is checked for every expected hit.
constexpr double size_scale = 32;

// The tolerance on t, on each coordinate of the point and of the normal, and on |normal| − 1: K·u·S, with u
// the tracer's unit roundoff and K the roundings a hit may carry (notation of docs/numerics.md).
// - IEEE arithmetic, K = 16: the ray and the scene reach a float tracer rounded (u·S each), the
//   intersection formula and the re-projection onto the surface add γ(5) to γ(12) (the point-error column
//   of docs/numerics.md's spawn-offset table), and t is divided by |cos θ| ≥ 0.7 at the most oblique hit
//   below. The same K holds reference<double> to 5.7e-14. dpps sums in the order of the exact dot product
//   (its image is bit-identical, docs/performance.md) and no expectation makes a denormal for ftz to flush.
// - rcp and rsqrt, K + 16 each: after one Newton step a quotient or 1/√x is within 1.9e-7 and 2.0e-7
//   relative (docs/performance.md, measured by tests/precision_test.cpp), about 3.3·u where IEEE rounds
//   within u: the handful of divisions or normalisations a hit takes add under sixteen roundings' worth.
// - textbook, K + 32: b² − a·c cancels where the ray passes far from a sphere's centre or a cylinder's axis:
//   rounded within γ(3)·|f|² (f from the centre to the origin), it moves t by γ(3)·|f|²/(2·√Δ). The worst
//   below is the sphere met 19 away on a chord of half-length √Δ = 1: 3·u·20²/2 = 600·u ≈ 19·u·S.
// - a plug-in, K = 16 with the unit roundoff it states.
inline double hit_tolerance(TracerKind kind, const sse::Precision& precision, double plugin_unit_roundoff = 0) {
    double u = kind == TracerKind::plugin             ? plugin_unit_roundoff
               : kind == TracerKind::reference_double ? std::numeric_limits<double>::epsilon() / 2
                                                      : std::numeric_limits<float>::epsilon() / 2;
    double roundings = 16;
    if (kind == TracerKind::sse) {
        roundings +=
            (precision.fast_rcp ? 16 : 0) + (precision.fast_rsqrt ? 16 : 0) + (precision.textbook_quadratic ? 32 : 0);
    }
    return roundings * u * size_scale;
}

struct TracerUnderTest {
    TracerKind kind = TracerKind::reference_double;
    sse::Precision precision;  // the SSE tracer's knobs
    std::string name;          // in the test's name
    double tolerance = 0;
    const plugin::Plugin* plugin = nullptr;  // the plug-in, for TracerKind::plugin
};

// How gtest names the parameter of a failed test.
inline void PrintTo(const TracerUnderTest& tracer, std::ostream* out) {
    *out << tracer.name << ", tolerance " << tracer.tolerance;
}

// "rcp+rsqrt+ftz" -> "RcpRsqrtFtz"
inline std::string camel_case(const std::string& knobs) {
    std::string name;
    bool word_start = true;
    for (char c : knobs) {
        if (c == '+') {
            word_start = true;
            continue;
        }
        name += word_start ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
        word_start = false;
    }
    return name;
}

// The C example and twinray's SSE tracer behind the tracer ABI, each loaded once.
inline const plugin::Plugin& example_plugin() {
    static const plugin::Plugin example(TWINRAY_EXAMPLE_TRACER);
    return example;
}
inline const plugin::Plugin& sse_plugin() {
    static const plugin::Plugin sse(TWINRAY_SSE_TRACER);
    return sse;
}

// Both references, the SSE tracer with every combination of its knobs that precision_is_built, then the C
// example and the SSE tracer through the ABI.
inline std::vector<TracerUnderTest> every_tracer() {
    std::vector<TracerUnderTest> tracers;
    for (TracerKind kind : {TracerKind::reference_double, TracerKind::reference_float}) {
        std::string name = kind == TracerKind::reference_double ? "ReferenceDouble" : "ReferenceFloat";
        tracers.push_back({kind, {}, name, hit_tolerance(kind, {})});
    }
    for (const sse::Precision& precision : sse::every_built_precision()) {
        tracers.push_back({TracerKind::sse, precision, "Sse" + camel_case(sse::precision_name(precision)),
                           hit_tolerance(TracerKind::sse, precision)});
    }
    tracers.push_back({TracerKind::plugin,
                       {},
                       "PluginBruteForceExample",
                       hit_tolerance(TracerKind::plugin, {}, example_plugin().unit_roundoff()),
                       &example_plugin()});
    tracers.push_back({TracerKind::plugin,
                       {},
                       "PluginSse",
                       hit_tolerance(TracerKind::plugin, {}, sse_plugin().unit_roundoff()),
                       &sse_plugin()});
    return tracers;
}

inline std::string tracer_test_name(const ::testing::TestParamInfo<TracerUnderTest>& info) {
    return info.param.name;
}

// A float tracer's hit in double (exactly: every float is a double).
template <typename FloatHit>
reference::Hit<double> widened(const FloatHit& hit) {
    auto widen = [](auto v) { return V(v.x, v.y, v.z); };
    reference::Hit<double> wide;
    wide.t = hit.t;
    wide.point = widen(hit.point);
    wide.normal = widen(hit.normal);
    wide.leaf = hit.leaf;
    wide.triangle = hit.triangle;
    wide.entering = hit.entering;
    wide.shading_normal = widen(hit.shading_normal);
    wide.spawn_offset = hit.spawn_offset;
    return wide;
}

// The first hit of the tracer along the unit vector of `direction`. A float tracer gets the ray normalised
// in double, then rounded to float, as `twinray probe --ray` gives it; the SSE tracer takes its origin in
// double (it re-bases it on its own origin before rounding).
inline std::optional<reference::Hit<double>> first_hit(const TracerUnderTest& tracer, const scene::Scene& scene,
                                                       V origin, V direction) {
    V unit = reference::normalize(direction);
    auto rounded = [](V v) {
        return reference::Vec3<float>(static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
    };
    switch (tracer.kind) {
        case TracerKind::reference_double: return reference::Tracer<double>(scene).intersect({origin, unit});
        case TracerKind::reference_float: {
            auto hit = reference::Tracer<float>(scene).intersect({rounded(origin), rounded(unit)});
            return hit ? std::optional(widened(*hit)) : std::nullopt;
        }
        case TracerKind::sse: {
            auto hit = sse::Tracer(scene, tracer.precision).intersect({origin, sse::Vec3(unit)});
            return hit ? std::optional(widened(*hit)) : std::nullopt;
        }
        case TracerKind::plugin: {
            plugin::Hit hit = plugin::BuiltScene(*tracer.plugin, scene)
                                  .nearest(origin, unit, 0, std::numeric_limits<double>::infinity());
            if (!hit.hit) {
                return std::nullopt;
            }
            reference::Hit<double> found;
            found.t = hit.t;
            found.point = origin + unit * hit.t;
            found.normal = reference::dot(hit.normal, unit) > 0 ? -hit.normal : hit.normal;
            found.shading_normal = found.normal;
            found.leaf = hit.leaf;
            found.triangle = hit.triangle;
            found.entering = hit.entering;
            return found;
        }
    }
    return std::nullopt;
}

// The fixture of every expectation suite: its parameter is the tracer under test.
class HitExpectation : public ::testing::TestWithParam<TracerUnderTest> {
protected:
    void SetUp() override {
        if ((GetParam().kind == TracerKind::sse || GetParam().plugin == &sse_plugin()) && !sse::cpu_supports_sse41()) {
            GTEST_SKIP() << sse::missing_sse41_message();
        }
    }

    // The largest error of the test's hits, against its tolerance, in the XML report (--gtest_output=xml).
    void TearDown() override {
        if (worst_error_ >= 0) {
            std::ostringstream measured;
            measured << worst_error_ << " of " << tolerance();
            RecordProperty("worst_error", measured.str());
        }
    }

    double tolerance() const { return GetParam().tolerance; }

    // Skips the test where the tracer under test is a plug-in lacking a kind the scene holds.
    bool tracer_lacks_a_kind_of(const scene::Scene& scene) {
        if (GetParam().kind != TracerKind::plugin) {
            return false;
        }
        std::vector<std::string> missing = GetParam().plugin->missing_kinds(scene);
        if (missing.empty()) {
            return false;
        }
        skip_for_lack_of(missing.front());
        return true;
    }
    void skip_for_lack_of(const std::string& kind) { GTEST_SKIP() << "the plug-in does not intersect a " << kind; }

    std::optional<reference::Hit<double>> first_hit(const scene::Scene& scene, V origin, V direction) const {
        return twinray::test::first_hit(GetParam(), scene, origin, direction);
    }

    // The hit of the ray from `origin` along `direction`, with the invariants every hit has: the normal is of
    // unit length and faces the ray, and the point lies at distance t along the ray.
    void expect_hit(const scene::Scene& scene, V origin, V direction, const Expected& expected) {
        ASSERT_LE(reference::max_abs_component(origin) + expected.t + 4, size_scale)
            << "the tolerance assumes this scale";
        if (tracer_lacks_a_kind_of(scene)) {
            return;
        }
        std::optional<reference::Hit<double>> hit = first_hit(scene, origin, direction);
        ASSERT_TRUE(hit.has_value()) << "expected a hit at t = " << expected.t;
        double limit = tolerance();
        EXPECT_NEAR(hit->t, expected.t, limit);
        TWINRAY_EXPECT_VEC_NEAR(hit->point, expected.point, limit);
        TWINRAY_EXPECT_VEC_NEAR(hit->normal, expected.normal, limit);
        EXPECT_NEAR(reference::length(hit->normal), 1.0, limit);
        EXPECT_LE(reference::dot(hit->normal, reference::normalize(direction)), 0.0) << "the normal must face the ray";
        EXPECT_EQ(hit->leaf, expected.leaf);
        EXPECT_EQ(hit->triangle, expected.triangle);
        EXPECT_EQ(hit->entering, expected.entering);
        worst_error_ = std::max({worst_error_, std::fabs(hit->t - expected.t),
                                 reference::max_abs_component(hit->point - expected.point),
                                 reference::max_abs_component(hit->normal - expected.normal),
                                 std::fabs(reference::length(hit->normal) - 1.0)});
    }

    void expect_miss(const scene::Scene& scene, V origin, V direction) {
        if (tracer_lacks_a_kind_of(scene)) {
            return;
        }
        std::optional<reference::Hit<double>> hit = first_hit(scene, origin, direction);
        EXPECT_FALSE(hit.has_value()) << "hit at t = " << hit->t << ", leaf " << hit->leaf;
    }

private:
    double worst_error_ = -1;  // none measured yet
};

}  // namespace twinray::test

// Declares the suite `Suite` of hand-solved expectations and runs each of its TEST_Ps once per tracer.
#define TWINRAY_HIT_EXPECTATION_SUITE(Suite)                                                         \
    class Suite : public twinray::test::HitExpectation {};                                           \
    INSTANTIATE_TEST_SUITE_P(EveryTracer, Suite, ::testing::ValuesIn(twinray::test::every_tracer()), \
                             twinray::test::tracer_test_name)

// In a TEST_P of such a suite: the expected first hit, or a miss, of the tracer under test.
#define EXPECT_HIT(scene, origin, direction, ...)               \
    do {                                                        \
        SCOPED_TRACE("ray from " #origin " along " #direction); \
        expect_hit(scene, origin, direction, __VA_ARGS__);      \
    } while (false)

#define EXPECT_MISS(scene, origin, direction)                   \
    do {                                                        \
        SCOPED_TRACE("ray from " #origin " along " #direction); \
        expect_miss(scene, origin, direction);                  \
    } while (false)
