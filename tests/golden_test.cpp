// The reference tracer against its stored images (golden/): any change to the reference's output shows
// here, with an error map, and is accepted only on purpose (`twinray golden --update`).
#include "compare/image_compare.h"
#include "compare/tolerances.h"
#include "image/image_file.h"
#include "reference/tracer.h"
#include "scene/loader.h"
#include "tests/scene_files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using twinray::test::scene_files;

class Golden : public ::testing::TestWithParam<fs::path> {};

TEST_P(Golden, ReferenceRenderMatchesItsGoldenImage) {
    const std::string name = GetParam().stem().string();
    const fs::path golden = fs::path(TWINRAY_SOURCE_DIR) / "golden" / (name + ".png");
    const std::string update = "twinray golden --update scenes/" + name +
                               ".json (from the repository root), or "
                               "cmake --build --preset release --target update-golden for every scene";
    ASSERT_TRUE(fs::exists(golden)) << golden << " is missing; create it with: " << update;

    twinray::scene::Scene scene = twinray::scene::load_scene(GetParam());
    twinray::Image actual = twinray::compare::quantized_8bit(twinray::reference::render<double>(scene, {}).image);
    twinray::Image expected = twinray::compare::read_image(golden);
    ASSERT_EQ(actual.width(), expected.width()) << "golden image size differs; if intended: " << update;
    ASSERT_EQ(actual.height(), expected.height()) << "golden image size differs; if intended: " << update;

    auto manifest =
        twinray::compare::ToleranceManifest::load(fs::path(TWINRAY_SOURCE_DIR) / "tests" / "tolerances.json");
    twinray::compare::Thresholds thresholds = manifest.for_scene(name).golden;
    twinray::compare::Metrics metrics = twinray::compare::measure(expected, actual, thresholds);
    twinray::compare::Verdict verdict = twinray::compare::judge(metrics, thresholds);
    std::printf("[ measured ] %s golden: %ld pixels changed by a level or more, max %.0f/255 at %d,%d -> %s\n",
                name.c_str(), metrics.fail_pixels, metrics.max_error * 255.0, metrics.max_x, metrics.max_y,
                twinray::compare::to_string(verdict));
    RecordProperty("changed_pixels", std::to_string(metrics.fail_pixels));
    if (verdict == twinray::compare::Verdict::fail) {
        fs::path folder = fs::path(TWINRAY_TEST_OUTPUT_DIR) / "golden";
        fs::create_directories(folder);
        twinray::write_image(actual, folder / (name + "_actual.png"));
        twinray::write_image(
            twinray::compare::error_heat_map(expected, actual, twinray::compare::HeatMapScale::linear(4.0 / 255.0)),
            folder / (name + "_error.png"));
        ADD_FAILURE() << name << ": the reference render differs from " << golden << " (" << metrics.fail_pixels
                      << " pixels, max " << metrics.max_error * 255.0 << "/255 at " << metrics.max_x << ","
                      << metrics.max_y << "). Actual image and error map: " << folder.string() << "/" << name
                      << "_{actual,error}.png. "
                      << "If the change is intended: " << update;
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, Golden, ::testing::ValuesIn(scene_files()),
                         [](const ::testing::TestParamInfo<fs::path>& param_info) {
                             return param_info.param.stem().string();
                         });

}  // namespace
