// The hand-solved expectations: scenes small enough to solve by hand and, for rays through each, the first hit (t,
// point, normal, leaf, side, triangle) or a miss, worked out from the primitives' geometry, never by running a
// tracer's formulas (the derivations are beside the cases). The tests run every case against every tracer and knob
// (tests/hit_expectations_test.cpp); `twinray conform` against the tracer it judges (suite "hand-solved",
// plugin/conformance.h).
#pragma once

#include "plugin/judged_tracer.h"
#include "scene/scene.h"

#include <optional>
#include <string>
#include <vector>

namespace twinray::plugin {

// Where and how a ray first meets the scene: `normal` of unit length, facing the ray; `triangle` -1 off a mesh.
struct FirstHit {
    double t = 0;
    scene::Vec3 point;
    scene::Vec3 normal;
    int leaf = -1;
    bool entering = false;
    int triangle = -1;
};

struct HandSolvedRay {
    scene::Vec3 origin;
    scene::Vec3 direction;             // of any length: the ray runs along its unit vector
    std::optional<FirstHit> expected;  // empty: a miss
};

struct HandSolvedCase {
    std::string suite;  // what it is about: "IntersectionPlane", "CsgDifference", ...
    std::string name;   // the property its rays prove: "HitFromTheOutsideEntersWithTheOutwardNormal"
    scene::Scene scene;
    std::vector<HandSolvedRay> rays;
    // Where the expected hits follow a rule of twinray's own that the tracer ABI leaves to each tracer, the rule: a
    // tracer may rightly differ there (`conform` warns). Empty for every case the ABI's contract decides.
    std::string own_rule;
};

// Every case, built on the first call: primitives, CSG, meshes, then transformed primitives.
const std::vector<HandSolvedCase>& hand_solved_cases();

// S, the expectations' size scale: every ray starts within |o|∞ ≤ 20 and hits at t ≤ 20, on objects no larger than
// 4, so that |o|∞ + t + 4 ≤ S for every expected hit (the tests check it).
constexpr double hand_solved_size_scale = 32;

// K, the roundings an IEEE tracer's hit may carry: the ray and the scene reach a float tracer rounded (u·S each),
// the intersection formula and the re-projection onto the surface add γ(5) to γ(12) (the point-error column of
// docs/numerics.md's spawn-offset table), and t is divided by |cos θ| ≥ 0.7 at the most oblique hit. The same K
// holds reference<double> to 5.7e-14.
constexpr double ieee_roundings = 16;

// The tolerance on t, on each coordinate of the point and of the normal, and on |normal| − 1: K·u·S, with u the
// tracer's unit roundoff (notation of docs/numerics.md).
constexpr double hand_solved_tolerance(double unit_roundoff, double roundings = ieee_roundings) {
    return roundings * unit_roundoff * hand_solved_size_scale;
}

struct RayCheck {
    // One phrase for each way the hit found differs from the one expected ("t 4.0000012 expected 4, error 1.2e-06 >
    // 1e-06", "leaf 0, expected 1"), or breaks what every hit has (a normal of unit length, facing the ray): empty
    // where it is as solved.
    std::vector<std::string> differences;
    // The largest of the errors of t, of the point's and the normal's coordinates and of |normal|, where a hit was
    // expected and found.
    std::optional<double> worst_error;
};

RayCheck check_first_hit(const HandSolvedRay& ray, const std::optional<FirstHit>& found, double tolerance);

// The differences joined by "; ".
std::string differences_text(const RayCheck& check);

// "ray from (0.5, 5, -2) along (0, -1, 0)": the ray as the case writes it.
std::string ray_name(const HandSolvedRay& ray);

// The first hit of `scene` along the unit vector of `direction`, t > 0, with the normal turned to face the ray and
// the point t along it (the ABI returns the outward normal and no point).
std::optional<FirstHit> first_hit(const JudgedScene& scene, const scene::Vec3& origin, const scene::Vec3& direction);

}  // namespace twinray::plugin
