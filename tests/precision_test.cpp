// The SSE tracer's speed/accuracy knobs (src/sse/precision.h): each one really changes the
// instructions' results, stays within a stated bound, and the default stays exact. Built with
// -msse4.1 (it calls the kernels' helpers directly). No test here measures speed.
#include "sse/precision.h"
#include "accuracy/ray_accuracy.h"
#include "compare/image_compare.h"
#include "reference/tracer.h"
#include "scene/loader.h"
#include "scene/portable_random.h"
#include "scene/sphere_field.h"
#include "sse/cpu.h"
#include "sse/tracer.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <vector>

namespace {

namespace fs = std::filesystem;
using twinray::sse::Precision;
using twinray::sse::vfloat4;
using FastReciprocal = twinray::sse::PrecisionPolicy<true, false, false, false>;
using FastInverseSqrt = twinray::sse::PrecisionPolicy<false, true, false, false>;
using AosDotProduct = twinray::sse::PrecisionPolicy<false, false, true, false>;

// Seeded, portable floats in [low, high).
class Floats {
public:
    explicit Floats(std::uint64_t seed) : random_(seed) {}
    float next(float low, float high) { return static_cast<float>(random_.uniform(low, high)); }

private:
    twinray::SplitMix64 random_;
};

vfloat4 four(Floats& random, float low, float high) {
    return vfloat4(
        _mm_setr_ps(random.next(low, high), random.next(low, high), random.next(low, high), random.next(low, high)));
}

// MXCSR's control bits (rounding, masks, FTZ, DAZ), without the six sticky exception flags that any
// arithmetic may raise.
unsigned mxcsr_controls() {
    return _mm_getcsr() & ~0x3Fu;
}

class PrecisionTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (!twinray::sse::cpu_supports_sse41()) {
            GTEST_SKIP() << twinray::sse::missing_sse41_message();
        }
    }
};

// rcpps (12 bits) + one Newton step: about 22 bits, against the correctly rounded IEEE quotient.
// Bound: 2^-20 relative (8 units of float's 2^-23), a stated margin over the Newton step's
// (1.5·2^-12)² plus its own two roundings.
TEST_F(PrecisionTest, ReciprocalAndInverseSquareRootWithANewtonStepAreWithinTwoToTheMinusTwenty) {
    Floats random(11);
    double worst_reciprocal = 0, worst_inverse_sqrt = 0;
    long inexact = 0;
    for (int i = 0; i < 100000; ++i) {
        vfloat4 x = four(random, 1e-3f, 1e3f);
        vfloat4 fast = twinray::sse::reciprocal<FastReciprocal>(x);
        vfloat4 fast_rsqrt = twinray::sse::inverse_sqrt<FastInverseSqrt>(x);
        for (int lane = 0; lane < 4; ++lane) {
            double exact = 1.0 / static_cast<double>(x.lane(lane));
            double exact_rsqrt = 1.0 / std::sqrt(static_cast<double>(x.lane(lane)));
            worst_reciprocal = std::max(worst_reciprocal, std::fabs(fast.lane(lane) - exact) / exact);
            worst_inverse_sqrt =
                std::max(worst_inverse_sqrt, std::fabs(fast_rsqrt.lane(lane) - exact_rsqrt) / exact_rsqrt);
            inexact += fast.lane(lane) != 1.0f / x.lane(lane) ? 1 : 0;
        }
    }
    std::printf(
        "[ measured ] rcp+Newton worst relative error %.3g (%ld of 400000 differ from IEEE 1/x), "
        "rsqrt+Newton %.3g; bound %.3g\n",
        worst_reciprocal, inexact, worst_inverse_sqrt, std::ldexp(1.0, -20));
    EXPECT_GT(inexact, 0) << "rcp + Newton gave the IEEE quotient everywhere: the knob changes nothing";
    EXPECT_LE(worst_reciprocal, std::ldexp(1.0, -20));
    EXPECT_LE(worst_inverse_sqrt, std::ldexp(1.0, -20));
}

// dpps adds (p0 + p1) + (p2 + p3) with p3 = 0: the SoA order, so transposing costs time, not accuracy.
TEST_F(PrecisionTest, DppsDotProductsRoundExactlyAsTheStructureOfArraysOnes) {
    Floats random(12);
    long differ = 0;
    for (int i = 0; i < 100000; ++i) {
        const twinray::sse::Vec3x4 a{four(random, -10, 10), four(random, -10, 10), four(random, -10, 10)};
        const twinray::sse::Vec3x4 b{four(random, -10, 10), four(random, -10, 10), four(random, -10, 10)};
        vfloat4 aos = twinray::sse::dot<AosDotProduct>(a, b);
        vfloat4 soa = twinray::sse::dot<twinray::sse::ExactPrecision>(a, b);
        for (int lane = 0; lane < 4; ++lane) {
            differ += aos.lane(lane) != soa.lane(lane) ? 1 : 0;
        }
    }
    EXPECT_EQ(differ, 0) << "of 400000 dot products";
}

TEST_F(PrecisionTest, FlushDenormalsFlushesInsideItsScopeAndRestoresTheModeAfter) {
    volatile float tiny = 1e-30f, scale = 1e-10f;  // their product, 1e-40, is a float denormal
    unsigned before = mxcsr_controls();
    float flushed;
    {
        twinray::sse::ScopedFlushDenormals flush(true);
        flushed = tiny * scale;
    }
    float kept = tiny * scale;
    EXPECT_EQ(flushed, 0.0f);
    EXPECT_GT(kept, 0.0f);
    EXPECT_EQ(mxcsr_controls(), before);
}

TEST_F(PrecisionTest, RenderingWithFlushedDenormalsLeavesTheCallersModeUnchanged) {
    twinray::scene::Scene scene = twinray::scene::sphere_field(20);
    twinray::RenderOptions options;
    options.width = 64;
    options.threads = 2;
    unsigned before = mxcsr_controls();
    twinray::sse::render(scene, options, {.flush_denormals = true});
    EXPECT_EQ(mxcsr_controls(), before);
}

TEST_F(PrecisionTest, AKnobCombinationThatIsNotBuiltIsRefusedNamingTheBuiltOnes) {
    twinray::scene::Scene scene = twinray::scene::sphere_field(3);
    Precision two_knobs{.fast_rcp = true, .fast_rsqrt = true};
    EXPECT_FALSE(twinray::sse::precision_is_built(two_knobs));
    try {
        twinray::sse::Tracer tracer(scene, two_knobs);
        FAIL() << "rcp+rsqrt alone was accepted";
    } catch (const std::invalid_argument& error) {
        EXPECT_NE(std::string(error.what()).find("built: exact, rcp"), std::string::npos) << error.what();
    }
    EXPECT_TRUE(twinray::sse::precision_is_built({.fast_rcp = true, .flush_denormals = true}));
}

// Each knob against the exact SSE tracer on a real scene, per primary ray (the accuracy code the bench
// reports with) and per image. The approximations change some t (the knob is live), and stay within
// loose stated bounds: t relative error 1e-4 on rays that hit the same object for rcp and rsqrt (their
// 22-bit results, through a few operations), 1e-2 for the textbook quadratic (cancellation at this
// scene's distances of a few radii to tens of radii); hit/miss changes on at most 0.1% of rays (the
// silhouettes); image max error 0.1 and at most 1% of pixels over 1/255.
struct KnobCase {
    const char* name;
    Precision precision;
    double t_relative_bound;
    bool must_change_t;
    const char* scene = "complete2.json";  // in scenes/: one the knob changes (mt changes triangles only)
};

class KnobAgainstExact : public PrecisionTest, public ::testing::WithParamInterface<KnobCase> {};

TEST_P(KnobAgainstExact, ChangesSomeResultsYetStaysWithinItsBound) {
    const KnobCase& knob = GetParam();
    twinray::scene::Scene scene = twinray::scene::load_scene(fs::path(TWINRAY_SOURCE_DIR) / "scenes" / knob.scene);
    const int width = 200, height = scene.height * width / scene.width;
    twinray::sse::Tracer exact(scene), fast(scene, knob.precision);
    auto expected =
        twinray::accuracy::all_first_hits(twinray::accuracy::first_hits_of(exact, width, height), width, height);
    twinray::accuracy::RayAccuracy rays =
        twinray::accuracy::measure_rays(expected, twinray::accuracy::first_hits_of(fast, width, height), width, height);

    twinray::RenderOptions options;
    options.width = width;
    options.threads = 1;
    twinray::Image exact_image = twinray::compare::clamped(twinray::sse::render(scene, options).image);
    twinray::Image fast_image = twinray::compare::clamped(twinray::sse::render(scene, options, knob.precision).image);
    twinray::compare::Thresholds one_level;
    one_level.fail = one_level.warn = 1.0 / 255.0;
    twinray::compare::Metrics image = twinray::compare::measure(exact_image, fast_image, one_level);
    double over_share = static_cast<double>(image.fail_pixels) / static_cast<double>(image.pixel_count);
    std::printf(
        "[ measured ] %s vs exact: t rel max %.3g (p50 %.3g), normal max %.3g deg, hit/miss %ld, other object "
        "%ld of %ld rays; image max %.4g, RMS %.3g, %.4f%% over 1/255\n",
        knob.name, rays.t_relative_max, rays.t_relative_p50, rays.normal_angle_max_degrees, rays.hit_miss_disagreements,
        rays.other_object, rays.rays, image.max_error, image.rms_error, 100 * over_share);
    if (knob.must_change_t) {
        EXPECT_GT(rays.t_relative_max, 0.0) << "no ray's t changed: the knob is not live";
        EXPECT_GT(image.rms_error, 0.0) << "the image did not change: the knob is not live";
    }
    EXPECT_LE(rays.t_relative_max, knob.t_relative_bound);
    EXPECT_LE(static_cast<double>(rays.hit_miss_disagreements + rays.other_object),
              1e-3 * static_cast<double>(rays.rays));
    EXPECT_LE(image.max_error, 0.1);
    EXPECT_LE(over_share, 0.01);
}

INSTANTIATE_TEST_SUITE_P(
    Knobs, KnobAgainstExact,
    ::testing::Values(KnobCase{"rcp", {.fast_rcp = true}, 1e-4, true},
                      KnobCase{"rsqrt", {.fast_rsqrt = true}, 1e-4, true},
                      KnobCase{"textbook", {.textbook_quadratic = true}, 1e-2, true},
                      KnobCase{"mt", {.moller_trumbore = true}, 1e-4, true, "meshes.json"},
                      KnobCase{
                          "fast",
                          {.fast_rcp = true, .fast_rsqrt = true, .textbook_quadratic = true, .flush_denormals = true},
                          1e-2,
                          true}),
    [](const ::testing::TestParamInfo<KnobCase>& knob) { return std::string(knob.param.name); });

// The dpps tracer renders the very image of the exact one (its dot products round alike).
TEST_F(PrecisionTest, DppsRenderIsBitIdenticalToTheExactOne) {
    twinray::scene::Scene scene = twinray::scene::load_scene(fs::path(TWINRAY_SOURCE_DIR) / "scenes" / "showcase.json");
    twinray::RenderOptions options;
    options.width = 160;
    twinray::Image exact = twinray::sse::render(scene, options).image;
    twinray::Image dpps = twinray::sse::render(scene, options, {.dpps = true}).image;
    ASSERT_EQ(exact.width(), dpps.width());
    long differ = 0;
    for (int y = 0; y < exact.height(); ++y) {
        for (int x = 0; x < exact.width(); ++x) {
            differ += std::memcmp(&exact.at(x, y), &dpps.at(x, y), sizeof(exact.at(x, y))) != 0 ? 1 : 0;
        }
    }
    EXPECT_EQ(differ, 0);
}

// Haines, Günther and Akenine-Möller (Ray Tracing Gems ch. 7): in float, the textbook discriminant
// b² − c of a unit sphere thousands of radii away is the difference of two numbers near d², whose ulp
// is larger than r²: it tells hit from miss at random. The cancellation-free r² − |f − b·d|² does not.
// Rays pass the sphere's centre at lateral offsets from 0 to 2 radii (never within 1% of the rim);
// reference<double> says which hit.
TEST_F(PrecisionTest, TextbookQuadraticMisjudgesAUnitSphereFiveThousandRadiiAwayAndTheStableFormDoesNot) {
    twinray::test::SceneBuilder builder;
    builder.object(twinray::test::sphere({0, 0, -5000}, 1));
    twinray::scene::Scene scene = builder.build();
    twinray::reference::Tracer<double> oracle(scene);
    twinray::sse::Tracer stable(scene), textbook(scene, {.textbook_quadratic = true});
    long stable_wrong = 0, textbook_wrong = 0, rays = 0;
    for (int i = 0; i < 200; ++i) {
        double offset = 2.0 * (i + 0.5) / 200;
        if (std::fabs(offset - 1.0) < 0.01) {
            continue;
        }
        twinray::reference::Vec3<double> direction =
            twinray::reference::normalize(twinray::reference::Vec3<double>{offset, 0, -5000});
        bool truth = oracle.intersect({{0, 0, 0}, direction}).has_value();
        twinray::sse::Ray ray{
            {0, 0, 0},
            {static_cast<float>(direction[0]), static_cast<float>(direction[1]), static_cast<float>(direction[2])}};
        stable_wrong += stable.intersect(ray).has_value() != truth ? 1 : 0;
        textbook_wrong += textbook.intersect(ray).has_value() != truth ? 1 : 0;
        ++rays;
    }
    std::printf("[ measured ] unit sphere 5000 radii away, %ld rays: stable form wrong on %ld, textbook on %ld\n", rays,
                stable_wrong, textbook_wrong);
    EXPECT_EQ(stable_wrong, 0);
    EXPECT_GT(textbook_wrong, rays / 10);
}

}  // namespace
