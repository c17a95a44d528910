// The per-ray suites `twinray conform` runs against a tracer (a plug-in, or the SSE tracer directly)
// (docs/plugins.md): each case judged against the hand-solved expectations or the double-precision oracle with the
// thresholds below, in this process; the command runs each case in a child process of its own, so that a plug-in
// that crashes or hangs costs its case a verdict, not twinray its report.
#pragma once

#include "plugin/hand_solved.h"
#include "plugin/judged_tracer.h"
#include "reference/tracer.h"
#include "scene/scene.h"

#include <functional>
#include <string>
#include <vector>

namespace twinray::plugin {

enum class Verdict { pass, warn, fail, skipped };
const char* verdict_name(Verdict verdict);

struct CaseResult {
    Verdict verdict = Verdict::pass;
    std::string detail;  // the figures behind the verdict, one line
};

// The thresholds of the primary-ray cases. A hit's t error is measured in the tracer's unit roundoffs of
// |o|∞ + t, the scale its rounding works at; disagreements (a hit where the oracle misses, a miss where it hits,
// another object) as a share of the rays.
constexpr double t_error_pass = 64;         // at most this: pass
constexpr double t_error_warn = 4096;       // at most this: warn; beyond: fail
constexpr double disagreement_warn = 1e-3;  // a share of rays at most this: warn (0: pass); beyond: fail

// Every pixel's primary ray of the oracle's camera at width × height, row by row, as the ABI passes rays: t > 0.
std::vector<twinray_ray> primary_rays(const reference::Tracer<double>& oracle, int width, int height);

// Every pixel's primary ray of `scene` at width × height, against reference<double>: hit or miss, the object,
// t and the normal. Skipped where the scene holds a kind the tracer lacks.
CaseResult judge_primary_rays(const JudgedTracer& tracer, const scene::Scene& scene, int width, int height);

// The watertightness suite's rays (accuracy/watertight.h) of one family at one distance, every size: each must
// cross exactly one triangle along its length (hits_along). Any miss or double hit fails.
CaseResult judge_watertight(const JudgedTracer& tracer, const std::string& family, double distance, int rays_per_size);

// One hand-solved case (plugin/hand_solved.h): each of its rays' first hit as solved, within
// hand_solved_tolerance(the tracer's unit roundoff), with a normal of unit length facing the ray; a miss where it
// misses. Any difference fails, naming the first ray that shows it and what differed; a case that holds twinray's
// own rule warns instead. Skipped where the scene holds a kind the tracer lacks.
CaseResult judge_hand_solved(const JudgedTracer& tracer, const HandSolvedCase& hand_solved);

struct ConformCase {
    std::string suite;  // "hand-solved", "primary rays", "far from the origin", "extremes", "watertight"
    std::string name;   // within the suite
    std::function<CaseResult(const JudgedTracer&)> run;
};

struct NamedScene {
    std::string name;
    scene::Scene scene;
};

// Every hand-solved case, then the primary-ray case of each scene, then each scene moved 1e3, 1e5 and 1e7 away from
// the origin (camera, lights and all: numerics::transformed), then each scaled by 1e-4 and 1e6 and seen from 100 and
// 10 000 times as far (the field of view narrowed to frame the same image), then the watertight cases.
std::vector<ConformCase> conformance_cases(const std::vector<NamedScene>& scenes, int width, int height,
                                           int watertight_rays_per_size);

// The scenes `conform` judges when given none: a field of 300 spheres and a closed tessellated sphere seen from
// outside.
std::vector<NamedScene> built_in_conformance_scenes();

}  // namespace twinray::plugin
