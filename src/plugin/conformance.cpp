#include "plugin/conformance.h"

#include "accuracy/watertight.h"
#include "io/formatted.h"
#include "numerics/numerics.h"
#include "reference/tracer.h"
#include "scene/geometry.h"
#include "scene/sphere_field.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>

namespace twinray::plugin {
namespace {

double percentile(std::vector<double> values, double share) {
    if (values.empty()) {
        return 0;
    }
    const auto rank = static_cast<std::size_t>(share * static_cast<double>(values.size() - 1));
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(rank), values.end());
    return values[rank];
}

// The kinds the scene holds that the plug-in lacks, as a skipped case; nothing where it has them all.
std::optional<CaseResult> lacking(const JudgedTracer& tracer, const scene::Scene& scene) {
    std::vector<std::string> missing = tracer.missing_kinds(scene);
    if (missing.empty()) {
        return std::nullopt;
    }
    std::string kinds;
    for (const std::string& kind : missing) {
        kinds += (kinds.empty() ? "" : ", ") + kind;
    }
    return CaseResult{Verdict::skipped, "the scene holds what the tracer does not intersect: " + kinds};
}

}  // namespace

const char* verdict_name(Verdict verdict) {
    switch (verdict) {
        case Verdict::pass: return "pass";
        case Verdict::warn: return "warn";
        case Verdict::fail: return "fail";
        case Verdict::skipped: return "skipped";
    }
    return "?";
}

std::vector<twinray_ray> primary_rays(const reference::Tracer<double>& oracle, int width, int height) {
    std::vector<twinray_ray> rays;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const reference::Ray<double> ray = oracle.primary_ray(x, y, width, height);
            rays.push_back(abi_ray(ray.origin, ray.direction, 0, std::numeric_limits<double>::infinity()));
        }
    }
    return rays;
}

CaseResult judge_primary_rays(const JudgedTracer& tracer, const scene::Scene& scene, int width, int height) {
    if (std::optional<CaseResult> skipped = lacking(tracer, scene)) {
        return *skipped;
    }
    const reference::Tracer<double> oracle(scene);
    const std::unique_ptr<JudgedScene> built = tracer.build(scene);
    const std::vector<twinray_ray> rays = primary_rays(oracle, width, height);
    std::vector<std::optional<reference::Hit<double>>> expected;
    for (const twinray_ray& ray : rays) {
        expected.push_back(oracle.intersect({origin_of(ray), direction_of(ray)}));
    }
    std::vector<Hit> hits(rays.size());
    built->intersect(rays, hits);
    std::size_t hit_disagreements = 0, object_disagreements = 0, agreed = 0;
    long first_disagreement = -1;
    std::vector<double> t_errors;
    double worst_angle = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit& hit = hits[i];
        const std::optional<reference::Hit<double>>& truth = expected[i];
        if (hit.hit != truth.has_value() || (hit.hit && hit.leaf != truth->leaf)) {
            (hit.hit != truth.has_value() ? hit_disagreements : object_disagreements) += 1;
            first_disagreement = first_disagreement < 0 ? static_cast<long>(i) : first_disagreement;
            continue;
        }
        if (!hit.hit) {
            continue;
        }
        ++agreed;
        const double scale = math::max_abs_component(origin_of(rays[i])) + truth->t;
        t_errors.push_back(std::fabs(hit.t - truth->t) / (scale * tracer.unit_roundoff()));
        // The oracle's normal faces the ray; the plug-in's is outward: compared on the ray's side.
        const scene::Vec3 direction = direction_of(rays[i]);
        scene::Vec3 normal = math::normalize(hit.normal);
        normal = math::dot(normal, direction) > 0 ? -normal : normal;
        const double cosine = std::clamp(math::dot(normal, truth->normal), -1.0, 1.0);
        worst_angle = std::max(worst_angle, std::acos(cosine));
    }
    const double rays_count = static_cast<double>(rays.size());
    const double disagreement_share = static_cast<double>(hit_disagreements + object_disagreements) / rays_count;
    const double t_max = t_errors.empty() ? 0 : *std::max_element(t_errors.begin(), t_errors.end());
    CaseResult result;
    result.verdict = t_max > t_error_warn || disagreement_share > disagreement_warn ? Verdict::fail
                     : t_max > t_error_pass || disagreement_share > 0               ? Verdict::warn
                                                                                    : Verdict::pass;
    result.detail = io::formatted(
        "%zu rays, %zu hits agreed; %zu hit/miss and %zu object disagreements%s; t error (u of |o|+t) p50 %.3g, "
        "p99 %.3g, max %.3g; normal error max %.3g rad",
        rays.size(), agreed, hit_disagreements, object_disagreements,
        first_disagreement < 0
            ? ""
            : io::formatted(" (the first at pixel %ld, %ld)", first_disagreement % width, first_disagreement / width)
                  .c_str(),
        percentile(t_errors, 0.5), percentile(t_errors, 0.99), t_max, worst_angle);
    return result;
}

CaseResult judge_hand_solved(const JudgedTracer& tracer, const HandSolvedCase& hand_solved) {
    if (std::optional<CaseResult> skipped = lacking(tracer, hand_solved.scene)) {
        return *skipped;
    }
    const std::unique_ptr<JudgedScene> built = tracer.build(hand_solved.scene);
    const double tolerance = hand_solved_tolerance(tracer.unit_roundoff());
    std::string first_difference;
    std::size_t differing = 0;
    std::optional<double> worst;
    for (const HandSolvedRay& ray : hand_solved.rays) {
        const RayCheck check = check_first_hit(ray, first_hit(*built, ray.origin, ray.direction), tolerance);
        if (check.worst_error) {
            worst = std::max(worst.value_or(0), *check.worst_error);
        }
        if (check.differences.empty()) {
            continue;
        }
        if (++differing == 1) {
            first_difference = ray_name(ray) + ": " + differences_text(check);
        }
    }
    const std::size_t rays = hand_solved.rays.size();
    if (differing == 0) {
        const std::string as_solved = io::formatted("%zu ray%s as solved by hand", rays, rays == 1 ? "" : "s");
        return {Verdict::pass, worst ? as_solved + io::formatted(", worst error %.3g of %.3g", *worst, tolerance)
                                     : as_solved + ", every one a miss"};
    }
    if (differing > 1) {
        first_difference += io::formatted(" (and %zu more of the %zu rays)", differing - 1, rays);
    }
    if (!hand_solved.own_rule.empty()) {
        return {Verdict::warn, first_difference + " (" + hand_solved.own_rule + ")"};
    }
    return {Verdict::fail, first_difference};
}

CaseResult judge_watertight(const JudgedTracer& tracer, const std::string& family, double distance, int rays_per_size) {
    accuracy::WatertightTally total;
    for (double size : accuracy::watertight_sizes()) {
        const accuracy::WatertightCase watertight =
            accuracy::make_watertight_case(family, distance, size, rays_per_size);
        if (std::optional<CaseResult> skipped = lacking(tracer, watertight.scene)) {
            return *skipped;
        }
        const std::unique_ptr<JudgedScene> built = tracer.build(watertight.scene);
        const accuracy::WatertightTally tally =
            accuracy::count_watertightness(watertight, [&](const accuracy::WatertightProbe& probe) {
                int triangles = 0;
                for (const Hit& hit : built->hits_along(probe.origin, probe.direction, 0, probe.length)) {
                    triangles += hit.triangle >= 0 ? 1 : 0;
                }
                return triangles;
            });
        total.rays += tally.rays;
        total.misses += tally.misses;
        total.double_hits += tally.double_hits;
    }
    const double per_million = 1e6 / static_cast<double>(std::max<std::uint64_t>(total.rays, 1));
    CaseResult result;
    result.verdict = total.misses + total.double_hits == 0 ? Verdict::pass : Verdict::fail;
    result.detail = io::formatted(
        "%llu rays at shared edges, vertices and faces, sizes 1e-4 to 1e4: %llu misses (%.0f per "
        "million), %llu double hits (%.0f per million)",
        static_cast<unsigned long long>(total.rays), static_cast<unsigned long long>(total.misses),
        static_cast<double>(total.misses) * per_million, static_cast<unsigned long long>(total.double_hits),
        static_cast<double>(total.double_hits) * per_million);
    return result;
}

std::vector<ConformCase> conformance_cases(const std::vector<NamedScene>& scenes, int width, int height,
                                           int watertight_rays_per_size) {
    std::vector<ConformCase> cases;
    for (const HandSolvedCase& hand_solved : hand_solved_cases()) {
        cases.push_back(
            {"hand-solved", hand_solved.suite + "." + hand_solved.name,
             [&hand_solved](const JudgedTracer& tracer) { return judge_hand_solved(tracer, hand_solved); }});
    }
    for (const NamedScene& named : scenes) {
        cases.push_back({"primary rays", named.name, [&named, width, height](const JudgedTracer& tracer) {
                             return judge_primary_rays(tracer, named.scene, width, height);
                         }});
    }
    // Each scene moved (numerics::transformed, camera and lights with it) and judged as primary rays: far from the
    // origin, then at the extremes of scale the tests hold the SSE tracer to (tests/extremes_scale_test.cpp) — far
    // smaller and far larger than its numbers' unit, and seen from so far that its rays travel t ≫ |p| to it.
    struct Moved {
        const char* suite;
        std::string how;
        double scale, shift, camera_distance;
    };
    const Moved moves[] = {{"far from the origin", "moved 1000 away", 1, 1e3, 1},
                           {"far from the origin", "moved 100000 away", 1, 1e5, 1},
                           {"far from the origin", "moved 1e+07 away", 1, 1e7, 1},
                           {"extremes", "scaled by 1e-4", 1e-4, 0, 1},
                           {"extremes", "scaled by 1e6", 1e6, 0, 1},
                           {"extremes", "seen from 100 times as far", 1, 0, 1e2},
                           {"extremes", "seen from 10 000 times as far", 1, 0, 1e4}};
    for (const Moved& move : moves) {
        for (const NamedScene& named : scenes) {
            cases.push_back(
                {move.suite, named.name + " " + move.how, [&named, width, height, move](const JudgedTracer& tracer) {
                     return judge_primary_rays(
                         tracer, numerics::transformed(named.scene, move.scale, move.shift, move.camera_distance),
                         width, height);
                 }});
        }
    }
    for (const std::string& family : accuracy::watertight_families()) {
        for (double distance : accuracy::watertight_distances()) {
            cases.push_back({"watertight", family + io::formatted(" at %g", distance),
                             [family, distance, watertight_rays_per_size](const JudgedTracer& tracer) {
                                 return judge_watertight(tracer, family, distance, watertight_rays_per_size);
                             }});
        }
    }
    return cases;
}

std::vector<NamedScene> built_in_conformance_scenes() {
    std::vector<NamedScene> scenes;
    scenes.push_back({"300 spheres", scene::sphere_field(300)});
    // The watertight suite's closed sphere of radius 1 at the origin, seen from outside, lit.
    scene::Scene mesh = accuracy::make_watertight_case("sphere", 1, 1, 1).scene;
    const scene::Bounds bounds = scene::vertex_bounds(*mesh.meshes.front().data);
    const scene::Vec3 centre = 0.5 * (bounds.low + bounds.high);
    mesh.camera.eye = centre + scene::Vec3{0.5, 1, 3};
    mesh.camera.look_at = centre;
    mesh.lights.push_back({centre + scene::Vec3{2, 3, 4}, {1, 1, 1}});
    scenes.push_back({"tessellated sphere", std::move(mesh)});
    return scenes;
}

}  // namespace twinray::plugin
