// Attribution of differing pixels (accuracy/attribution.h): every pixel of every scene that differs between
// the tracers has a cause float rounding accounts for, and a tracer with a real bug leaves pixels unexplained.
#include "accuracy/attribution.h"
#include "reference/tracer.h"
#include "scene/loader.h"
#include "sse/cpu.h"
#include "sse/tracer.h"
#include "tests/scene_files.h"

#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

namespace {

namespace fs = std::filesystem;
using namespace twinray;

// Far below the warn threshold (1/255), so that thousands of pixels are judged, most of them the float
// tracer's ordinary drift.
constexpr double judged_above = 1e-6;

TEST(Attribution, EveryPixelOfEverySceneThatDiffersHasAnExplainedCause) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    for (const fs::path& path : test::scene_files()) {
        scene::Scene scene = scene::load_scene(path);
        RenderOptions options;
        options.threads = 2;
        Image expected = reference::render<double>(scene, options).image;
        const std::unique_ptr<tracing::AnyTracer> sse = tracing::make_tracer("sse", scene);
        Image actual = sse->render(options).image;
        accuracy::Attribution attribution = accuracy::attribute_pixels(scene, expected, actual, *sse, judged_above);
        std::printf("[ measured ] %-10s", path.stem().c_str());
        for (int c = 0; c < accuracy::cause_count; ++c) {
            std::printf(" %s %ld", accuracy::cause_name(static_cast<accuracy::Cause>(c)),
                        attribution.counts[static_cast<std::size_t>(c)]);
        }
        std::printf("\n");
        // The verdict rule twinray diff applies, here to many more pixels than its warn threshold lets in.
        EXPECT_EQ(accuracy::attribution_failure(attribution, static_cast<long>(expected.width()) * expected.height()),
                  "")
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

}  // namespace
