#include "plugin/hand_solved.h"

#include "io/formatted.h"
#include "plugin/hand_solved_cases.h"
#include "scene/scene_builder.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

namespace twinray::plugin {
namespace {

std::string vector_text(const scene::Vec3& v) {
    return io::formatted("(%.9g, %.9g, %.9g)", v.x, v.y, v.z);
}

// Written so that a NaN is never within the tolerance.
bool within(double error, double tolerance) {
    return error <= tolerance;
}

}  // namespace

namespace hand_solved {

HandSolvedRay hit(V origin, V direction, const FirstHit& expected) {
    return {origin, direction, expected};
}

HandSolvedRay miss(V origin, V direction) {
    return {origin, direction, std::nullopt};
}

// A builder holding only the far-away decoy sphere no ray comes near, so that what is added next is leaf 1.
scene::builder::SceneBuilder with_a_decoy() {
    scene::builder::SceneBuilder builder;
    builder.object(scene::builder::sphere({-1000, 1000, 1000}, 1));
    return builder;
}

scene::Scene after_a_decoy(scene::Object object) {
    return with_a_decoy().object(std::move(object)).build();
}

scene::Scene after_a_decoy(scene::Mesh mesh) {
    return with_a_decoy().add(std::move(mesh)).build();
}

}  // namespace hand_solved

const std::vector<HandSolvedCase>& hand_solved_cases() {
    static const std::vector<HandSolvedCase> cases = [] {
        std::vector<HandSolvedCase> all;
        hand_solved::add_primitive_cases(all);
        hand_solved::add_csg_cases(all);
        hand_solved::add_mesh_cases(all);
        hand_solved::add_transformed_cases(all);
        return all;
    }();
    return cases;
}

RayCheck check_first_hit(const HandSolvedRay& ray, const std::optional<FirstHit>& found, double tolerance) {
    RayCheck check;
    const std::optional<FirstHit>& expected = ray.expected;
    if (!expected || !found) {
        if (found) {
            check.differences.push_back(
                io::formatted("a hit at t = %.9g, leaf %d, expected a miss", found->t, found->leaf));
        } else if (expected) {
            check.differences.push_back(io::formatted("a miss, expected a hit at t = %.9g", expected->t));
        }
        return check;
    }
    const double t_error = std::fabs(found->t - expected->t);
    const double point_error = math::max_abs_component(found->point - expected->point);
    const double normal_error = math::max_abs_component(found->normal - expected->normal);
    const double length_error = std::fabs(math::length(found->normal) - 1);
    const std::string beyond = io::formatted(" > %.3g", tolerance);
    if (!within(t_error, tolerance)) {
        check.differences.push_back(
            io::formatted("t %.9g expected %.9g, error %.3g", found->t, expected->t, t_error).append(beyond));
    }
    if (!within(point_error, tolerance)) {
        check.differences.push_back("point " + vector_text(found->point) + " expected " + vector_text(expected->point) +
                                    io::formatted(", error %.3g", point_error) + beyond);
    }
    if (!within(normal_error, tolerance)) {
        check.differences.push_back("normal " + vector_text(found->normal) + " expected " +
                                    vector_text(expected->normal) + io::formatted(", error %.3g", normal_error) +
                                    beyond);
    }
    if (!within(length_error, tolerance)) {
        check.differences.push_back(
            io::formatted("|normal| %.9g, error %.3g", math::length(found->normal), length_error) + beyond);
    }
    const double facing = math::dot(found->normal, math::normalize(ray.direction));
    if (!(facing <= 0)) {
        check.differences.push_back(io::formatted("the normal faces away from the ray (cosine %.3g)", facing));
    }
    if (found->leaf != expected->leaf) {
        check.differences.push_back(io::formatted("leaf %d, expected %d", found->leaf, expected->leaf));
    }
    if (found->triangle != expected->triangle) {
        check.differences.push_back(io::formatted("triangle %d, expected %d", found->triangle, expected->triangle));
    }
    if (found->entering != expected->entering) {
        check.differences.push_back(expected->entering ? "leaving, expected entering" : "entering, expected leaving");
    }
    check.worst_error = std::fmax(std::fmax(t_error, point_error), std::fmax(normal_error, length_error));
    return check;
}

std::string differences_text(const RayCheck& check) {
    std::string text;
    for (const std::string& difference : check.differences) {
        text += (text.empty() ? "" : "; ") + difference;
    }
    return text;
}

std::string ray_name(const HandSolvedRay& ray) {
    return "ray from " + vector_text(ray.origin) + " along " + vector_text(ray.direction);
}

std::optional<FirstHit> first_hit(const JudgedScene& scene, const scene::Vec3& origin, const scene::Vec3& direction) {
    const scene::Vec3 unit = math::normalize(direction);
    const twinray_ray ray = abi_ray(origin, unit, 0, std::numeric_limits<double>::infinity());
    Hit hit;
    scene.intersect({&ray, 1}, {&hit, 1});
    if (!hit.hit) {
        return std::nullopt;
    }
    const scene::Vec3 facing = math::dot(hit.normal, unit) > 0 ? -hit.normal : hit.normal;
    return FirstHit{hit.t, origin + unit * hit.t, facing, hit.leaf, hit.entering, hit.triangle};
}

}  // namespace twinray::plugin
