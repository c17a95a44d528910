// The tracers the hand-solved expectations (src/plugin/hand_solved.h) run against: reference<double>,
// reference<float>, the SSE tracer exact and with each knob combination it is built for, and behind the tracer ABI
// (through plugin/plugin.h) the C example (examples/brute_force_tracer.c) and the SSE tracer, on the scenes whose
// kinds they intersect. Each tracer is held to the tolerance its precision earns (tolerance_of below); a hit is
// checked together with the invariants every hit has (plugin::check_first_hit). tests/hit_expectations_test.cpp
// runs every case against each of them as a test of its own.
#pragma once

#include "plugin/hand_solved.h"
#include "plugin/plugin.h"
#include "reference/tracer.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <cctype>
#include <limits>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace twinray::test {

using V = reference::Vec3<double>;

enum class TracerKind { reference_double, reference_float, sse, plugin };

struct TracerUnderTest {
    TracerKind kind = TracerKind::reference_double;
    sse::Precision precision;  // the SSE tracer's knobs
    std::string name;          // in the test's name
    // The plug-in, for TracerKind::plugin: loaded on the first call, when a test first needs it.
    const plugin::Plugin& (*plugin)() = nullptr;
    // Whether it breaks ties at a mesh's edges and corners by twinray's rule (HandSolvedCase::own_rule):
    // Möller–Trumbore takes every edge and corner (its leaks: twinray watertight).
    bool keeps_twinrays_own_rules = true;
};

// The C example and twinray's SSE tracer behind the tracer ABI, each loaded once.
inline const plugin::Plugin& example_plugin() {
    static const plugin::Plugin example(TWINRAY_EXAMPLE_TRACER);
    return example;
}
inline const plugin::Plugin& sse_plugin() {
    static const plugin::Plugin sse(TWINRAY_SSE_TRACER);
    return sse;
}

// plugin::hand_solved_tolerance with the tracer's unit roundoff and roundings, the IEEE ones (K = 16) plus:
// - rcp and rsqrt, 16 each: after one Newton step a quotient or 1/√x is within 1.9e-7 and 2.0e-7 relative
//   (docs/performance.md, measured by tests/precision_test.cpp), about 3.3·u where IEEE rounds within u: the
//   handful of divisions or normalisations a hit takes add under sixteen roundings' worth.
// - textbook, 32: b² − a·c cancels where the ray passes far from a sphere's centre or a cylinder's axis: rounded
//   within γ(3)·|f|² (f from the centre to the origin), it moves t by γ(3)·|f|²/(2·√Δ). The worst is the sphere met
//   19 away on a chord of half-length √Δ = 1: 3·u·20²/2 = 600·u ≈ 19·u·S.
// dpps sums in the order of the exact dot product (its image is bit-identical, docs/performance.md) and no
// expectation makes a denormal for ftz to flush.
inline double tolerance_of(const TracerUnderTest& tracer) {
    const double u = tracer.kind == TracerKind::plugin             ? tracer.plugin().unit_roundoff()
                     : tracer.kind == TracerKind::reference_double ? std::numeric_limits<double>::epsilon() / 2
                                                                   : std::numeric_limits<float>::epsilon() / 2;
    double roundings = plugin::ieee_roundings;
    if (tracer.kind == TracerKind::sse) {
        roundings += (tracer.precision.fast_rcp ? 16 : 0) + (tracer.precision.fast_rsqrt ? 16 : 0) +
                     (tracer.precision.textbook_quadratic ? 32 : 0);
    }
    return plugin::hand_solved_tolerance(u, roundings);
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

// Both references, the SSE tracer with every combination of its knobs that precision_is_built, then the C example
// and the SSE tracer through the ABI.
inline std::vector<TracerUnderTest> every_tracer() {
    std::vector<TracerUnderTest> tracers;
    tracers.push_back({TracerKind::reference_double, {}, "ReferenceDouble"});
    tracers.push_back({TracerKind::reference_float, {}, "ReferenceFloat"});
    for (const sse::Precision& precision : sse::every_built_precision()) {
        tracers.push_back({TracerKind::sse, precision, "Sse" + camel_case(sse::precision_name(precision)), nullptr,
                           !precision.moller_trumbore});
    }
    tracers.push_back({TracerKind::plugin, {}, "PluginBruteForceExample", &example_plugin, false});
    tracers.push_back({TracerKind::plugin, {}, "PluginSse", &sse_plugin});
    return tracers;
}

// How gtest names the parameter of a failed test.
inline void PrintTo(const TracerUnderTest& tracer, std::ostream* out) {
    *out << tracer.name << ", tolerance " << tolerance_of(tracer);
}

// A tracer's hit as a first hit (a float tracer's exactly in double: every float is a double).
template <typename TracerHit>
plugin::FirstHit first_hit_of(const TracerHit& hit) {
    auto widen = [](auto v) { return V(v.x, v.y, v.z); };
    return {hit.t, widen(hit.point), widen(hit.normal), hit.leaf, hit.entering, hit.triangle};
}

// The first hit of the tracer along the unit vector of `direction`. A float tracer gets the ray normalised in
// double, then rounded to float, as `twinray probe --ray` gives it; the SSE tracer takes its origin in double (it
// re-bases it on its own origin before rounding).
inline std::optional<plugin::FirstHit> first_hit(const TracerUnderTest& tracer, const scene::Scene& scene, V origin,
                                                 V direction) {
    const V unit = reference::normalize(direction);
    auto rounded = [](V v) {
        return reference::Vec3<float>(static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
    };
    auto found = [](const auto& hit) { return hit ? std::optional(first_hit_of(*hit)) : std::nullopt; };
    switch (tracer.kind) {
        case TracerKind::reference_double: return found(reference::Tracer<double>(scene).intersect({origin, unit}));
        case TracerKind::reference_float:
            return found(reference::Tracer<float>(scene).intersect({rounded(origin), rounded(unit)}));
        case TracerKind::sse: return found(sse::Tracer(scene, tracer.precision).intersect({origin, sse::Vec3(unit)}));
        case TracerKind::plugin: return plugin::first_hit(*tracer.plugin().build(scene), origin, direction);
    }
    return std::nullopt;
}

// Why the tracer cannot be held to the case here, or nothing: the SSE tracer on a CPU without SSE4.1, a plug-in
// lacking a kind the scene holds, a tracer that breaks ties its own way on a case of twinray's own rule.
inline std::optional<std::string> why_skipped(const TracerUnderTest& tracer,
                                              const plugin::HandSolvedCase& hand_solved) {
    const bool runs_sse = tracer.kind == TracerKind::sse || tracer.plugin == &sse_plugin;
    if (runs_sse && !sse::cpu_supports_sse41()) {
        return sse::missing_sse41_message();
    }
    if (tracer.kind == TracerKind::plugin) {
        const std::vector<std::string> missing = tracer.plugin().missing_kinds(hand_solved.scene);
        if (!missing.empty()) {
            return "the plug-in does not intersect a " + missing.front();
        }
    }
    if (!hand_solved.own_rule.empty() && !tracer.keeps_twinrays_own_rules) {
        return hand_solved.own_rule + "; this tracer breaks such ties its own way";
    }
    return std::nullopt;
}

}  // namespace twinray::test
