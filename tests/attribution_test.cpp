// Attribution of differing pixels (accuracy/attribution.h): every pixel of every scene that differs between
// the tracers has a cause float rounding accounts for, and a tracer with a real bug leaves pixels unexplained.
#include "accuracy/attribution.h"
#include "reference/tracer.h"
#include "scene/loader.h"
#include "scene/placement.h"
#include "sse/cpu.h"
#include "sse/tracer.h"
#include "tests/scene_files.h"

#include <cstdio>
#include <filesystem>
#include <memory>

#include <gtest/gtest.h>

namespace {

namespace fs = std::filesystem;
using namespace twinray;

// Far below the warn threshold (1/255), so that thousands of pixels are judged, most of them the float
// tracer's ordinary drift.
constexpr double judged_above = 1e-6;

// Every pixel of `rendered` (the SSE tracer's render of it) that differs from the reference's render of `truth`,
// attributed against `truth`.
accuracy::Attribution attribute_renders(const scene::Scene& truth, const scene::Scene& rendered) {
    RenderOptions options;
    options.threads = 2;
    Image expected = reference::render<double>(truth, options).image;
    const std::unique_ptr<tracing::AnyTracer> sse = tracing::make_tracer("sse", rendered);
    Image actual = sse->render(options).image;
    return accuracy::attribute_pixels(truth, expected, actual, *sse, judged_above);
}

// The scene with its first mesh's vertices moved by `dx` along x: a tracer's error no rounding explains.
scene::Scene with_first_mesh_moved(const scene::Scene& scene, double dx) {
    scene::Scene moved = scene;
    auto vertices = std::make_shared<scene::MeshData>(*moved.meshes.front().data);
    for (scene::Vec3& vertex : vertices->vertices) {
        vertex.x += dx;
    }
    moved.meshes.front().data = vertices;
    return moved;
}

long count_of(const accuracy::Attribution& attribution, accuracy::Cause cause) {
    return attribution.counts[static_cast<std::size_t>(cause)];
}

TEST(Attribution, EveryPixelOfEverySceneThatDiffersHasAnExplainedCause) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    for (const fs::path& path : test::scene_files()) {
        const scene::Scene scene = scene::load_scene(path);
        const accuracy::Attribution attribution = attribute_renders(scene, scene);
        std::printf("[ measured ] %-10s", path.stem().c_str());
        for (int c = 0; c < accuracy::cause_count; ++c) {
            const auto cause = static_cast<accuracy::Cause>(c);
            std::printf(" %s %ld", accuracy::cause_name(cause), count_of(attribution, cause));
        }
        std::printf("\n");
        // The verdict rule twinray diff applies, here to many more pixels than its warn threshold lets in.
        EXPECT_EQ(accuracy::attribution_failure(attribution, static_cast<long>(scene.width) * scene.height), "")
            << path.stem();
        for (std::size_t i = 0; i < std::min<std::size_t>(5, attribution.unexplained.size()); ++i) {
            const accuracy::AttributedPixel& p = attribution.unexplained[i];
            ADD_FAILURE() << path.stem() << " pixel " << p.x << "," << p.y << " (error " << p.error << "): unexplained "
                          << p.cause.what << " at depth " << p.cause.depth << ", ray " << p.cause.deviation
                          << " rad off, band " << p.cause.band;
        }
    }
}

// The classes are not a blanket: an SSE tracer given glass of another index of refraction (a bug in Snell's
// law would look like this) or a light moved by 0.05 (a bug in the light vector) leaves pixels unexplained.
TEST(Attribution, ATracerWithAWrongModelLeavesPixelsUnexplained) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    scene::Scene scene = scene::load_scene(fs::path(TWINRAY_SOURCE_DIR) / "scenes" / "showcase.json");
    scene::Scene other_glass = scene;
    for (scene::Material& material : other_glass.materials) {
        material.ior += material.transmission > 0 ? 0.01 : 0.0;
    }
    scene::Scene moved_light = scene;
    moved_light.lights.front().position.x += 0.05;
    reference::Tracer<double> reference(scene);
    for (const auto& [name, wrong] :
         {std::pair{"ior + 0.01", &other_glass}, std::pair{"light moved 0.05", &moved_light}}) {
        sse::Tracer tracer(*wrong);
        long judged = 0, unexplained = 0;
        for (int y = 0; y < scene.height; y += 2) {
            for (int x = 0; x < scene.width; x += 2) {
                RayTree expected, actual;
                reference.trace(reference.primary_ray(x, y, scene.width, scene.height), 1, nullptr, &expected);
                tracer.trace(tracer.primary_ray(x, y, scene.width, scene.height), 1, nullptr, &actual);
                if (!first_divergence(expected, actual)) {
                    continue;
                }
                ++judged;
                unexplained +=
                    accuracy::attribute(scene, reference, expected, actual).cause == accuracy::Cause::unexplained;
            }
        }
        std::printf("[ measured ] %s: %ld of %ld diverging pixels unexplained\n", name, unexplained, judged);
        EXPECT_GT(unexplained, judged / 2) << name;
    }
}

// A badly conditioned plate of tests/data/attribution/: every pixel that differs between the tracers has `cause`, as
// the trip into the plate's space explains it, and none is unexplained.
scene::Scene expect_the_trip_explains(const char* file, accuracy::Cause cause) {
    const scene::Scene placed =
        scene::load_scene(fs::path(TWINRAY_SOURCE_DIR) / "tests" / "data" / "attribution" / file);
    const accuracy::Attribution attribution = attribute_renders(placed, placed);
    std::printf("[ measured ] %s, an instance of condition number %.3g: %ld %s, %ld unexplained pixels\n", file,
                scene::condition_number(placed.meshes.front().placement->transform()), count_of(attribution, cause),
                accuracy::cause_name(cause), count_of(attribution, accuracy::Cause::unexplained));
    EXPECT_GT(count_of(attribution, cause), 100);
    EXPECT_EQ(count_of(attribution, accuracy::Cause::unexplained), 0);
    return placed;
}

// The plate written in the world (the first mesh of `in_world`) has no trip: moved by 3 units for the SSE tracer, it
// leaves pixels unexplained.
void expect_a_plate_moved_in_the_world_unexplained(const scene::Scene& in_world, const char* what) {
    const accuracy::Attribution without_trip = attribute_renders(in_world, with_first_mesh_moved(in_world, 3));
    std::printf("[ measured ] %s, moved 3 units: %ld unexplained pixels\n", what,
                count_of(without_trip, accuracy::Cause::unexplained));
    EXPECT_GT(count_of(without_trip, accuracy::Cause::unexplained), 100);
}

// A plate scaled by 1e4 after a turn of 45° (κ ≈ 1.4e4), its far end seen from 8 700 away: float's trip into the
// plate's space moves a ray there by units in the world (docs/numerics.md, "Transforms"), and the SSE tracer meets the
// plate up to 2 units past its end. Every pixel that differs is a silhouette that trip explains. The same plate written
// in the world has no trip: moved by 3 units for the SSE tracer, its end leaves pixels unexplained.
TEST(Attribution, ABadlyConditionedInstancesEndIsExplainedByTheTripIntoItsSpace) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    const scene::Scene placed =
        expect_the_trip_explains("badly_conditioned_instance.json", accuracy::Cause::silhouette);
    expect_a_plate_moved_in_the_world_unexplained(scene::flattened(placed), "the plate in the world");
}

// The same plate casting a shadow: a shadow ray from the floor to the light passes the plate's end 7 000 units from
// its origin, float's trip moves it there by units, and the SSE tracer's shadow lies in streaks units off the
// reference's. The ray tree does not record the leaf that blocked a shadow ray: the slack is that of the placed leaves
// whose box the ray passes. The plate written in the world has none, and a second plate far off (whose box no shadow
// ray in view passes) lends it none: moved by 3 units for the SSE tracer, its shadow leaves pixels unexplained (all
// were explained while the shifted shadow origins sank under the floor, which then blocked them).
TEST(Attribution, ABadlyConditionedInstancesShadowIsExplainedByTheTripIntoItsSpace) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    const scene::Scene placed = expect_the_trip_explains("badly_conditioned_shadow.json", accuracy::Cause::shadow);
    scene::Scene in_world = placed;
    in_world.meshes.front() = scene::flattened(placed).meshes.front();
    ASSERT_TRUE(in_world.meshes.back().placement.has_value());
    expect_a_plate_moved_in_the_world_unexplained(in_world, "the plate in the world, a placed one far off");
}

}  // namespace
