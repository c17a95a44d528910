// The SSE tracer held against the reference<double> on every scene in scenes/: per primary ray (same
// object; t, point and normal within a bound derived from float epsilon and the scene's scale) and per
// image (max absolute error, share of pixels over 1/255). Measured maxima are printed on every run.
#include "accuracy/ray_accuracy.h"
#include "compare/image_compare.h"
#include "compare/tolerances.h"
#include "image/image.h"
#include "reference/tracer.h"
#include "scene/loader.h"
#include "scene/portable_random.h"
#include "sse/cpu.h"
#include "sse/tracer.h"
#include "tests/generated_scene.h"
#include "tests/scene_builder.h"
#include "tests/scene_files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using RefTracer = twinray::reference::Tracer<double>;
using RefHit = twinray::reference::Hit<double>;
using RefVec = twinray::reference::Vec3<double>;
using RefRay = twinray::reference::Ray<double>;

constexpr double float_epsilon = std::numeric_limits<float>::epsilon();

// The bound on |t_sse − t_ref|, derived: single precision rounds the camera, the ray and every primitive
// parameter by about ε relative to the scene's largest coordinate S, and the ray's direction by about ε,
// so at distance t the float ray passes about ε·(S + t) from the double one. A surface met at angle θ
// to its normal turns that lateral offset into a shift along the ray of ε·(S + t)/|cos θ|, and each
// intersection formula adds a few ε of the same size through cancellation. The bound is that with a
// factor 64 of margin: 64·ε·(S + t)/|cos θ|. The hit point obeys the same bound.
constexpr double distance_bound_in_epsilons = 64;

using twinray::accuracy::angle_between;
using twinray::accuracy::band_pixels;
using twinray::accuracy::in_silhouette_band;
using twinray::accuracy::in_triangle_band;
using twinray::accuracy::largest_coordinate;
using twinray::accuracy::normal_bound_radians;
using twinray::test::scene_files;

// What the per-ray comparison measured over the rays it judged.
struct RayFindings {
    long rays = 0, banded = 0, disagreements = 0;
    double max_t_error = 0, max_point_error = 0, max_normal_error = 0, max_bound_share = 0;
    long other_triangle_in_edge_band = 0;  // the same mesh, the neighbouring triangle, within a shared edge's band
};

// Pixel (x, y)'s primary ray in both tracers: the same hit or miss, primitive and side, t and the hit point
// within the float bound, the normal within normal_bound_radians, or else the ray lies in the silhouette
// band. A disagreement outside the band is a test failure.
void judge_primary_ray(const RefTracer& reference, const twinray::sse::Tracer& sse, const twinray::scene::Scene& scene,
                       double scale, int x, int y, RayFindings& findings) {
    const int width = scene.width, height = scene.height;
    ++findings.rays;
    std::optional<RefHit> expected = reference.intersect(reference.primary_ray(x, y, width, height));
    std::optional<twinray::sse::Hit> actual = sse.intersect(sse.primary_ray(x, y, width, height));
    bool agrees = expected.has_value() == actual.has_value() && (!expected || expected->leaf == actual->leaf);
    if (agrees && expected) {
        double t_error = std::fabs(actual->t - expected->t);
        RefVec point(actual->point.x, actual->point.y, actual->point.z);
        RefVec normal(actual->normal.x, actual->normal.y, actual->normal.z);
        double point_error = twinray::reference::length(point - expected->point);
        double normal_error = angle_between(normal, expected->normal);
        double cos_incidence =
            std::fabs(twinray::reference::dot(expected->normal, reference.primary_ray(x, y, width, height).direction));
        double distance_bound = distance_bound_in_epsilons * float_epsilon * (scale + expected->t) / cos_incidence;
        findings.max_bound_share = std::max(findings.max_bound_share, std::max(t_error, point_error) / distance_bound);
        agrees = t_error <= distance_bound && point_error <= distance_bound && normal_error <= normal_bound_radians &&
                 actual->entering == expected->entering;
        if (agrees || !in_silhouette_band(reference, scene, x, y, width, height, expected)) {
            findings.max_t_error = std::max(findings.max_t_error, t_error);
            findings.max_point_error = std::max(findings.max_point_error, point_error);
            findings.max_normal_error = std::max(findings.max_normal_error, normal_error);
        }
    }
    if (agrees && expected && expected->triangle != actual->triangle) {
        // The same mesh, another triangle: only where the ray passes within the band of a shared edge.
        if (in_triangle_band(reference, scene, x, y, width, height, *expected)) {
            ++findings.other_triangle_in_edge_band;
            return;
        }
        ++findings.disagreements;
        ADD_FAILURE() << "pixel " << x << "," << y << ": " << scene.leaf_paths[expected->leaf] << " reference triangle "
                      << expected->triangle << ", sse triangle " << actual->triangle << ", away from any edge (rays "
                      << band_pixels << " pixel around it meet the reference's one)";
        return;
    }
    if (agrees) {
        return;
    }
    if (in_silhouette_band(reference, scene, x, y, width, height, expected)) {
        ++findings.banded;
        return;
    }
    ++findings.disagreements;
    ADD_FAILURE() << "pixel " << x << "," << y << ": reference "
                  << (expected ? scene.leaf_paths[expected->leaf] + " t=" + std::to_string(expected->t) : "miss")
                  << ", sse " << (actual ? scene.leaf_paths[actual->leaf] + " t=" + std::to_string(actual->t) : "miss");
}

// Judging stops after this many disagreements: the first ones say what is wrong.
constexpr long disagreements_reported = 10;

void expect_findings_within_bounds(const std::string& name, const RayFindings& findings, double scale) {
    std::printf(
        "[ measured ] %s: %ld rays, %ld of them in the %.0e-pixel band, %ld on another triangle within an edge's "
        "band, %ld disagreements; max |dt| %.3g, max |dp| %.3g, at most %.3f of the bound %.0f*eps*(S + t)/|cos| "
        "with S = %.3g; max normal angle %.3g rad (bound %.0e)\n",
        name.c_str(), findings.rays, findings.banded, band_pixels, findings.other_triangle_in_edge_band,
        findings.disagreements, findings.max_t_error, findings.max_point_error, findings.max_bound_share,
        distance_bound_in_epsilons, scale, findings.max_normal_error, normal_bound_radians);
    ::testing::Test::RecordProperty("max_t_error", std::to_string(findings.max_t_error));
    ::testing::Test::RecordProperty("band_rays", std::to_string(findings.banded));
    EXPECT_EQ(findings.disagreements, 0);
    EXPECT_LE(findings.max_bound_share, 1.0);
    EXPECT_LE(findings.max_normal_error, normal_bound_radians);
}

class Conformance : public ::testing::TestWithParam<fs::path> {
protected:
    void SetUp() override {
        if (!twinray::sse::cpu_supports_sse41()) {
            GTEST_SKIP() << twinray::sse::missing_sse41_message();
        }
        scene_ = twinray::scene::load_scene(GetParam());
    }
    twinray::scene::Scene scene_;
};

TEST_P(Conformance, EveryPrimaryRayHitsTheSameObjectWithinTheFloatBound) {
    RefTracer reference(scene_);
    twinray::sse::Tracer sse(scene_);
    const double scale = largest_coordinate(scene_);
    RayFindings findings;
    for (int y = 0; y < scene_.height && findings.disagreements < disagreements_reported; ++y) {
        for (int x = 0; x < scene_.width && findings.disagreements < disagreements_reported; ++x) {
            judge_primary_ray(reference, sse, scene_, scale, x, y, findings);
        }
    }
    expect_findings_within_bounds(GetParam().stem().string(), findings, scale);
}

// Thresholds per scene from tests/tolerances.json (the same numbers twinray diff judges by).
TEST_P(Conformance, RenderedImageAgreesWithTheReference) {
    twinray::RenderOptions options;
    twinray::Image expected = twinray::compare::clamped(twinray::reference::render<double>(scene_, options).image);
    twinray::Image actual = twinray::compare::clamped(twinray::sse::render(scene_, options).image);
    const std::string name = GetParam().stem().string();
    auto manifest =
        twinray::compare::ToleranceManifest::load(fs::path(TWINRAY_SOURCE_DIR) / "tests" / "tolerances.json");
    twinray::compare::Thresholds thresholds = manifest.for_scene(name).sse;
    twinray::compare::Metrics metrics = twinray::compare::measure(expected, actual, thresholds);
    double share = static_cast<double>(metrics.fail_pixels) / static_cast<double>(metrics.pixel_count);
    std::printf(
        "[ measured ] %s image: max abs error %.4f at %d,%d, %ld pixels (%.4f%%) over %.4g; allowed %.4g%%, max %.4g\n",
        name.c_str(), metrics.max_error, metrics.max_x, metrics.max_y, metrics.fail_pixels, 100 * share,
        thresholds.fail, thresholds.fail_percent, thresholds.hard_fail);
    RecordProperty("max_error", std::to_string(metrics.max_error));
    RecordProperty("share_over_fail", std::to_string(share));
    EXPECT_LE(100 * share, thresholds.fail_percent) << "see twinray diff " << GetParam().string() << " -o DIR";
    EXPECT_LE(metrics.max_error, thresholds.hard_fail) << "see twinray diff " << GetParam().string() << " -o DIR";
}

// Decisions no scene of scenes/ puts to the test, with rays whose every number is exact in float and double,
// so both tracers must decide alike: found by mutation testing (tests/mutants/), where a tracer breaking
// each of them still passed every scene.
struct ExactCase {
    const char* what;
    RefVec origin, direction;  // direction of unit length up to rounding; both tracers see the same one
    int leaf;                  // what the reference hits, as the contract says it must
};

void expect_both_tracers_hit(const twinray::scene::Scene& scene, const std::vector<ExactCase>& cases) {
    RefTracer reference(scene);
    twinray::sse::Tracer sse(scene);
    for (const ExactCase& c : cases) {
        RefVec direction = twinray::reference::normalize(c.direction);
        std::optional<RefHit> expected = reference.intersect({c.origin, direction});
        twinray::sse::Vec3 float_direction(direction);
        std::optional<twinray::sse::Hit> actual = sse.intersect({c.origin, float_direction});
        ASSERT_TRUE(expected.has_value()) << c.what << ": the reference misses";
        EXPECT_EQ(expected->leaf, c.leaf) << c.what << ": the reference hits " << scene.leaf_paths[expected->leaf];
        ASSERT_TRUE(actual.has_value()) << c.what << ": sse misses; the reference hits "
                                        << scene.leaf_paths[expected->leaf] << " at t=" << expected->t;
        EXPECT_EQ(actual->leaf, expected->leaf) << c.what << ": sse hits " << scene.leaf_paths[actual->leaf];
        EXPECT_NEAR(actual->t, expected->t, 4 * float_epsilon * expected->t) << c.what;
    }
}

// The tie rule (docs/scene-format.md): at equal t the object earlier in the file is hit.
TEST(ConformanceCases, CoincidentSurfacesAreHitOnTheEarlierObjectByBothTracers) {
    twinray::test::SceneBuilder builder;
    builder.object(twinray::test::sphere({0, 0, 0}, 1))
        .object(twinray::test::sphere({0, 0, 0}, 1))
        .object(twinray::test::box({2, -1, -1}, {4, 1, 1}))
        .object(twinray::test::box({2, -1, -1}, {4, 1, 1}))
        .object(twinray::test::plane({0, 1, 0}, -2))
        .object(twinray::test::plane({0, 1, 0}, -2));
    expect_both_tracers_hit(builder.build(), {{"two equal spheres, head on", {0, 0, 5}, {0, 0, -1}, 0},
                                              {"two equal spheres, off centre", {0.25, 0.5, 5}, {0, 0, -1}, 0},
                                              {"two equal boxes", {3, 0, 5}, {0, 0, -1}, 2},
                                              {"two equal planes", {-3, 1, 0}, {0, -1, 0}, 4}});
}

// A box's span is enter ≤ exit (docs/reference-tracer.md): a ray through an edge or a corner meets the box.
TEST(ConformanceCases, RaysTouchingABoxEdgeOrCornerHitItInBothTracers) {
    twinray::test::SceneBuilder builder;
    builder.object(twinray::test::box({-1, -1, -1}, {1, 1, 1}));
    // Each ray only touches the box: it enters one slab where it leaves another, at the same t exactly.
    expect_both_tracers_hit(builder.build(), {{"touching the edge x = -1, y = 1", {-2, 0, 0.5}, {1, 1, 0}, 0},
                                              {"touching the edge y = 1, z = 1", {0.25, 0, 2}, {0, 1, -1}, 0},
                                              {"touching the corner (1, 1, 1)", {2, 0, 0}, {-1, 1, 1}, 0}});
}

// Whether two first hits are the same in every bit of every field.
bool same_bits(const std::optional<RefHit>& a, const std::optional<RefHit>& b) {
    auto same = [](const auto& u, const auto& v) { return std::memcmp(&u, &v, sizeof u) == 0; };
    if (a.has_value() != b.has_value()) {
        return false;
    }
    return !a || (a->leaf == b->leaf && a->entering == b->entering && same(a->t, b->t) && same(a->point, b->point) &&
                  same(a->normal, b->normal) && same(a->spawn_offset, b->spawn_offset));
}

constexpr int large_scene_primitives = 10000;
constexpr int primitives_asked = 10500;  // the lattice nearest it has 10 389 (14 x 14 x 14 nodes)
constexpr int sampled_pixels = 1000;

// On scenes/ both tracers pick their BVH themselves; here the SSE tracer's BVH is held to the reference
// testing every object (the oracle as it was before either had a BVH) on generated scenes of over 10 000
// primitives (spheres and cylinders; CSG objects of spheres, boxes and cylinders), at pixels drawn at random, per
// ray as above. The reference's own BVH must give those pixels the same first hits, bit for bit.
TEST(ConformanceLargeScene, SampledPrimaryRaysThroughTheSseBvhAgreeWithTheBruteForceReference) {
    if (!twinray::sse::cpu_supports_sse41()) {
        GTEST_SKIP() << twinray::sse::missing_sse41_message();
    }
    for (const char* family : {"lattice", "csg"}) {
        twinray::scene::Scene scene = twinray::test::generated_scene(family, primitives_asked);
        RefTracer brute_force(scene, twinray::Accel::none);
        RefTracer reference_bvh(scene, twinray::Accel::bvh);
        twinray::sse::Tracer sse(scene, {}, twinray::Accel::bvh);
        const double scale = largest_coordinate(scene);
        twinray::SplitMix64 random(20240601);
        RayFindings findings;
        long object_hits = 0, bvh_differences = 0;  // object: a hit on anything but the floor, leaf 0
        for (int i = 0; i < sampled_pixels && findings.disagreements < disagreements_reported; ++i) {
            const int x = static_cast<int>(random.next() % static_cast<std::uint64_t>(scene.width));
            const int y = static_cast<int>(random.next() % static_cast<std::uint64_t>(scene.height));
            judge_primary_ray(brute_force, sse, scene, scale, x, y, findings);
            RefRay ray = brute_force.primary_ray(x, y, scene.width, scene.height);
            std::optional<RefHit> expected = brute_force.intersect(ray);
            object_hits += expected && expected->leaf != 0;
            if (!same_bits(expected, reference_bvh.intersect(ray)) && ++bvh_differences <= disagreements_reported) {
                ADD_FAILURE() << family << " pixel " << x << "," << y
                              << ": the reference's BVH finds another first hit than its brute force";
            }
        }
        const std::string name = std::string(family) + " of " + std::to_string(scene.leaf_paths.size()) +
                                 " primitives, SSE BVH against brute-force reference";
        expect_findings_within_bounds(name, findings, scale);
        std::printf(
            "[ measured ] %s: %ld of %ld sampled rays hit an object over the floor; reference BVH against brute "
            "force: %ld differ\n",
            family, object_hits, findings.rays, bvh_differences);
        EXPECT_GE(static_cast<long>(scene.leaf_paths.size()), large_scene_primitives) << family;
        EXPECT_GE(object_hits, sampled_pixels / 10)
            << family << ": a sample that mostly misses the objects proves little";
        EXPECT_EQ(bvh_differences, 0) << family;
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, Conformance, ::testing::ValuesIn(scene_files()),
                         [](const ::testing::TestParamInfo<fs::path>& param_info) {
                             return param_info.param.stem().string();
                         });

}  // namespace
