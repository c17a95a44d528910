// Far from the origin (docs/numerics.md): every scene of scenes/ and tests/data/extremes/ moved with its
// camera by 1e3 … 1e7 along every axis. The SSE tracer compiles each scene relative to its eye, so its
// float numbers are distances from the camera and the image is the untranslated scene's, within that
// scene's own tolerance of reference<double>, for every built precision knob. reference<float> keeps world
// coordinates on purpose (the naive baseline) and is only printed. Small images keep the suite quick.
#include "compare/image_compare.h"
#include "compare/tolerances.h"
#include "numerics/numerics.h"
#include "reference/tracer.h"
#include "scene/geometry.h"
#include "scene/loader.h"
#include "scene/placement.h"
#include "sse/cpu.h"
#include "sse/tracer.h"
#include "tests/scene_files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace {

namespace fs = std::filesystem;
using twinray::Vec3d;
using twinray::numerics::TracerKind;

constexpr double shifts[] = {1e3, 1e5, 1e6, 1e7};
constexpr int image_width = 64;
constexpr double float_unit_roundoff = std::numeric_limits<float>::epsilon() / 2;

// scenes/ (sorted), then tests/data/extremes/ (sorted).
std::vector<fs::path> far_scene_files() {
    std::vector<fs::path> extremes;
    for (const auto& entry : fs::directory_iterator(fs::path(TWINRAY_SOURCE_DIR) / "tests/data/extremes")) {
        extremes.push_back(entry.path());
    }
    std::sort(extremes.begin(), extremes.end());
    std::vector<fs::path> files = twinray::test::scene_files();
    files.insert(files.end(), extremes.begin(), extremes.end());
    return files;
}

twinray::RenderOptions small_image(const twinray::scene::Scene& scene) {
    twinray::RenderOptions options;
    options.width = image_width;
    options.height =
        std::max(1, static_cast<int>(std::lround(static_cast<double>(image_width) * scene.height / scene.width)));
    return options;
}

// The radius of the primitive's bounding sphere; 0 for a plane (unbounded: its size is its distance).
double size_of(const twinray::scene::Object& primitive) {
    return std::visit(
        [](const auto& shape) {
            if constexpr (twinray::scene::is_primitive<std::decay_t<decltype(shape)>>) {
                double radius = twinray::scene::bounding_sphere(shape).radius;
                return std::isfinite(radius) ? radius : 0.0;
            } else {
                return 0.0;
            }
        },
        primitive.shape);
}

// A transformed primitive's normal goes through L⁻ᵀ: an object-space error of u turns it by up to κ(L)·u
// (scene::condition_number, 1 for a primitive in world coordinates), the derived bound of docs/numerics.md.
double normal_condition_of(const twinray::scene::Object& primitive) {
    return std::visit(
        [](const auto& shape) {
            if constexpr (requires { shape.to_world(); }) {
                return twinray::scene::condition_number(shape.to_world());
            } else {
                return 1.0;
            }
        },
        primitive.shape);
}

class FarFromTheOrigin : public ::testing::TestWithParam<fs::path> {
protected:
    void SetUp() override {
        if (!twinray::sse::cpu_supports_sse41()) {
            GTEST_SKIP() << twinray::sse::missing_sse41_message();
        }
        scene_ = twinray::scene::load_scene(GetParam());
        auto manifest =
            twinray::compare::ToleranceManifest::load(fs::path(TWINRAY_SOURCE_DIR) / "tests" / "tolerances.json");
        tolerance_ = manifest.for_scene(GetParam().stem().string()).sse;
    }
    twinray::scene::Scene scene_;
    twinray::compare::Thresholds tolerance_;
};

// The untranslated scene's tolerance (tests/tolerances.json, as the conformance suite applies it) at every
// translation and every built knob, with and without ftz.
// Not the lattice: at 64 pixels its 5 424 thin rods are sub-pixel and it misses the tolerance where it
// stands, before any move: the exact tracer by 5 of 3 072 pixels over 1/255 (0.16%, explained silhouettes;
// 0.08% at its own 240 pixels), the textbook quadratic by 2.2% (cancellation on primitives 100 times smaller
// than their distance). The two tests below hold it far from the origin.
// Nor the textbook quadratic on the ellipsoid of eccentricity 1e4: in its object space every ray starts 1e4 radii
// from the sphere, where b² − c cancels (docs/sse-tracer.md); it misses the tolerance unmoved (79% of pixels).
TEST_P(FarFromTheOrigin, SseImageStaysWithinTheUntranslatedScenesToleranceForEveryKnob) {
    if (GetParam().stem() == "lattice") {
        GTEST_SKIP() << "the lattice misses its tolerance at 64 pixels unmoved (see the comment above)";
    }
    const bool textbook_cancels = GetParam().stem() == "ellipsoid_eccentric";
    for (double shift : shifts) {
        twinray::scene::Scene moved = twinray::numerics::transformed(scene_, 1, shift);
        twinray::RenderOptions options = small_image(moved);
        twinray::Image expected = twinray::compare::clamped(twinray::reference::render<double>(moved, options).image);
        twinray::compare::Metrics naive = twinray::compare::measure(
            expected, twinray::compare::clamped(twinray::reference::render<float>(moved, options).image), tolerance_);
        std::printf("[ measured ] %s moved %g: reference-float %.2f%% of pixels over %.4g, max %.4f\n",
                    GetParam().stem().c_str(), shift, 100.0 * naive.fail_pixels / naive.pixel_count, tolerance_.fail,
                    naive.max_error);
        for (const twinray::sse::Precision& precision : twinray::sse::every_built_precision()) {
            if (textbook_cancels && precision.textbook_quadratic) {
                continue;
            }
            twinray::compare::Metrics metrics = twinray::compare::measure(
                expected, twinray::compare::clamped(twinray::sse::render(moved, options, precision).image), tolerance_);
            double percent = 100.0 * metrics.fail_pixels / metrics.pixel_count;
            std::printf("[ measured ] %s moved %g: sse %s %.2f%% of pixels over %.4g, max %.4f\n",
                        GetParam().stem().c_str(), shift, twinray::sse::precision_name(precision).c_str(), percent,
                        tolerance_.fail, metrics.max_error);
            EXPECT_LE(percent, tolerance_.fail_percent)
                << "moved " << shift << ", " << twinray::sse::precision_name(precision);
            EXPECT_LE(metrics.max_error, tolerance_.hard_fail)
                << "moved " << shift << ", " << twinray::sse::precision_name(precision);
        }
    }
}

// Per primary ray, against the exact crossing (long double) of the SSE tracer's own ray with the leaf it
// hit: S = size + distance from the camera (the primitive's bounding radius, 0 for a plane, plus t).
// Relative to the eye every float the tracer holds is within u·S of its true value, and the
// intersection formulas add a few γ(n)·S: |Δt|·|cos θ| ≤ 16·u·S, and the normal within
// 16·u·S/(size·|cos θ|) rad (a curved normal is (p − centre)/radius; a plane's is exact within u: its
// bound is taken with size = S). Before
// re-basing S was the distance from the world's origin: at 1e7, 16·u·S ≈ 9.5, larger than the scenes.
// Both tests below measure against numerics' exact geometry, written per primitive type; it has no meshes
// yet, whose hits far from the origin the watertightness suite judges (1 to 1e7, accuracy/watertight.h).
#define TWINRAY_SKIP_MESHES_FOR_EXACT_GEOMETRY()                                                              \
    if (scene_.has_meshes()) {                                                                                \
        GTEST_SKIP() << "numerics' exact geometry has no meshes yet (tests/watertight_test.cpp judges them)"; \
    }

TEST_P(FarFromTheOrigin, PrimaryHitsAreWithinSixteenUnitRoundoffsOfSizePlusDistanceFromTheCamera) {
    TWINRAY_SKIP_MESHES_FOR_EXACT_GEOMETRY();
    std::vector<const twinray::scene::Object*> leaves = twinray::numerics::leaf_objects(scene_);
    double worst_t_share = 0, worst_normal_share = 0;
    long checked = 0;
    for (double shift : shifts) {
        twinray::scene::Scene moved = twinray::numerics::transformed(scene_, 1, shift);
        std::vector<const twinray::scene::Object*> moved_leaves = twinray::numerics::leaf_objects(moved);
        twinray::sse::Tracer tracer(moved);
        twinray::RenderOptions options = small_image(moved);
        for (int y = 0; y < options.height; ++y) {
            for (int x = 0; x < options.width; ++x) {
                twinray::sse::Ray ray = tracer.primary_ray(x, y, options.width, options.height);
                std::optional<twinray::sse::Hit> hit = tracer.intersect(ray);
                if (!hit) {
                    continue;
                }
                const twinray::scene::Object& leaf = *moved_leaves[static_cast<std::size_t>(hit->leaf)];
                Vec3d direction(ray.direction);
                twinray::numerics::ExactSpan span = twinray::numerics::exact_span(leaf, ray.origin, direction);
                if (!span.valid) {
                    continue;  // a silhouette ray that the exact line misses: the grazing band
                }
                long double t = hit->t;
                long double exact_t = std::fabs(span.enter - t) < std::fabs(span.exit - t) ? span.enter : span.exit;
                Vec3d exact_point = ray.origin + static_cast<double>(exact_t) * direction;
                Vec3d exact_normal = twinray::numerics::exact_normal(leaf, exact_point);
                double cos_incidence = std::fabs(twinray::math::dot(exact_normal, direction));
                if (cos_incidence < 1e-3) {
                    continue;  // grazing: t along the surface is ill-conditioned, the band of the grazing test
                }
                double size = size_of(*leaves[static_cast<std::size_t>(hit->leaf)]);
                double distance_and_size = size + static_cast<double>(exact_t);
                double bound = 16 * float_unit_roundoff * distance_and_size;
                double t_share = static_cast<double>(std::fabs(t - exact_t)) * cos_incidence / bound;
                Vec3d normal(hit->normal);
                Vec3d across = twinray::math::cross(normal, exact_normal);
                double normal_angle = std::atan2(std::sqrt(twinray::math::dot(across, across)),
                                                 std::fabs(twinray::math::dot(normal, exact_normal)));
                double normal_share = normal_angle * (size > 0 ? size : distance_and_size) * cos_incidence /
                                      (bound * normal_condition_of(leaf));
                EXPECT_LE(t_share, 1.0) << "moved " << shift << ", pixel " << x << "," << y;
                EXPECT_LE(normal_share, 1.0) << "moved " << shift << ", pixel " << x << "," << y;
                worst_t_share = std::max(worst_t_share, t_share);
                worst_normal_share = std::max(worst_normal_share, normal_share);
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 0);
    std::printf(
        "[ measured ] %s: %ld primary hits at 1e3 … 1e7; |dt| at most %.3f and the normal %.3f of the "
        "bound 16·u·(size + distance from the camera), times κ(L) for a transformed normal\n",
        GetParam().stem().c_str(), checked, worst_t_share, worst_normal_share);
}

// pbrt-v4's criterion (numerics::measure): no shadow, reflected or refracted ray re-hits the surface it
// leaves, against the geometry the SSE tracer holds (rounded to float relative to its eye). Prints each
// tracer's largest primary hit-point error (distance from the true surface, in scene units) beside it.
TEST_P(FarFromTheOrigin, NoSecondaryRayReHitsTheSurfaceItLeaves) {
    TWINRAY_SKIP_MESHES_FOR_EXACT_GEOMETRY();
    for (double shift : shifts) {
        twinray::scene::Scene moved = twinray::numerics::transformed(scene_, 1, shift);
        twinray::numerics::Measurement naive = twinray::numerics::measure(moved, TracerKind::reference_float, 16, 1);
        twinray::numerics::Measurement m = twinray::numerics::measure(moved, TracerKind::sse, 16, 1);
        EXPECT_EQ(m.acne, 0) << "moved " << shift << ": " << m.acne << " of " << m.secondary;
        std::printf(
            "[ measured ] %s moved %g: sse %d secondary rays, %d self-hits, %d leaks, hit points off by "
            "%.2g; reference-float %d self-hits, hit points off by %.2g\n",
            GetParam().stem().c_str(), shift, m.secondary, m.acne, m.leaks, m.max_error, naive.acne, naive.max_error);
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, FarFromTheOrigin, ::testing::ValuesIn(far_scene_files()),
                         [](const ::testing::TestParamInfo<fs::path>& param_info) {
                             return param_info.param.stem().string();
                         });

}  // namespace
