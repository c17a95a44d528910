// Expectations on the reference tracer's first hit, shared by the intersection and CSG tests: a hit
// worked out by hand, checked together with the invariants every hit has.
#pragma once

#include "reference/tracer.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <optional>

namespace twinray::test {

using reference::Hit;
using V = reference::Vec3<double>;

constexpr double hit_tolerance = 1e-12;

inline std::optional<Hit<double>> first_hit(const scene::Scene& scene, V origin, V direction) {
    reference::Tracer<double> tracer(scene);
    return tracer.intersect({origin, reference::normalize(direction)});
}

struct Expected {
    double t;
    V point;
    V normal;
    int leaf;
    bool entering;
};

// Checks the hit of the ray along `direction`, including the invariants every hit has: the normal is
// of unit length and faces the ray, and the point lies at distance t along the ray.
inline void check_hit(const std::optional<Hit<double>>& hit, V direction, const Expected& expected) {
    ASSERT_TRUE(hit.has_value()) << "expected a hit at t = " << expected.t;
    EXPECT_NEAR(hit->t, expected.t, hit_tolerance);
    TWINRAY_EXPECT_VEC_NEAR(hit->point, expected.point, hit_tolerance);
    TWINRAY_EXPECT_VEC_NEAR(hit->normal, expected.normal, hit_tolerance);
    EXPECT_NEAR(reference::length(hit->normal), 1.0, hit_tolerance);
    EXPECT_LE(reference::dot(hit->normal, reference::normalize(direction)), 0.0) << "the normal must face the ray";
    EXPECT_EQ(hit->leaf, expected.leaf);
    EXPECT_EQ(hit->entering, expected.entering);
}

}  // namespace twinray::test

#define EXPECT_HIT(scene, origin, direction, ...)                                                             \
    do {                                                                                                      \
        SCOPED_TRACE("ray from " #origin " along " #direction);                                               \
        twinray::test::check_hit(twinray::test::first_hit(scene, origin, direction), direction, __VA_ARGS__); \
    } while (false)

#define EXPECT_MISS(scene, origin, direction)                                                                  \
    do {                                                                                                       \
        auto miss_ = twinray::test::first_hit(scene, origin, direction);                                       \
        EXPECT_FALSE(miss_.has_value()) << "ray from " #origin " along " #direction " hit at t = " << miss_->t \
                                        << ", leaf " << miss_->leaf;                                           \
    } while (false)
