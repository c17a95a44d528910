// Transforms that a primitive of the same kind holds exactly are no approximation: a scene whose objects are
// placed by translations on a binary grid, scales by powers of two and turns by multiples of 90° renders bit for
// bit as the same scene written in world coordinates, in each tracer (docs/scene-format.md, "Transforms").
#include "reference/tracer.h"
#include "scene/loader.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>

namespace twinray {
namespace {

const std::string header = R"({
  "format": "twinray-scene/1",
  "image": { "width": 96, "height": 72 },
  "camera": { "eye": [0.3, 3, 6], "look_at": [0, 0.5, -1] },
  "max_depth": 6,
  "materials": {
    "glass": { "color": [1, 1, 1], "ambient": 0, "diffuse": 0.05, "phong": 0.8, "phong_size": 60, "reflection": 0.1,
               "transmission": 0.85, "ior": 1.5 },
    "mirror": { "color": [0.9, 0.9, 0.9], "diffuse": 0.4, "reflection": 0.5 },
    "red": { "color": [0.9, 0.2, 0.1], "diffuse": 0.7, "phong": 0.4, "phong_size": 30 }
  },
  "lights": [ { "position": [-3, 6, 4] }, { "position": [4, 3, 2], "color": [0.4, 0.4, 0.5] } ],
  "objects": [)";

// Each object placed, and beside it the same object as world coordinates give it (worked out by hand: a turn by
// 90° about z takes (x, y, z) to (−y, x, z), about x to (x, −z, y), by −90° about x to (x, z, −y)).
const std::string placed_objects = R"(
    { "type": "plane", "normal": [0, 0, 1], "offset": 1, "material": "mirror",
      "transform": [{"rotate": [-90, 0, 0]}, {"translate": [0, -1, 0]}] },
    { "type": "sphere", "center": [0.5, 0, 0], "radius": 0.25, "material": "glass",
      "transform": [{"scale": 4}, {"translate": [-1.5, 0.25, -2]}] },
    { "type": "box", "min": [0, 0, 0], "max": [1, 0.5, 0.25], "material": "red",
      "transform": [{"rotate": [0, 0, 90]}, {"scale": 2}, {"translate": [1.5, 0, 0.5]}] },
    { "type": "cylinder", "base": [0, 0, 0], "cap": [0, 1, 0], "radius": 0.25, "material": "red",
      "transform": [{"rotate": [90, 0, 0]}, {"scale": 2}, {"translate": [-2, 0.5, 0]}] },
    { "type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "triangles": [[0, 1, 2]], "material": "glass",
      "transform": [{"rotate": {"axis": [0, 0, 2], "deg": 180}}, {"scale": 0.5}, {"translate": [1, 1.5, -1]}] },
    { "type": "difference", "material": "red", "transform": [{"translate": [0, 0, -3]}], "children": [
      { "type": "box", "min": [-1, 0, -1], "max": [1, 2, 1] },
      { "type": "sphere", "center": [0, 0, 0], "radius": 1, "transform": [{"scale": 0.5}, {"translate": [0, 2, 0]}] } ] }
  ]
})";

const std::string world_objects = R"(
    { "type": "plane", "normal": [0, 1, 0], "offset": 0, "material": "mirror" },
    { "type": "sphere", "center": [0.5, 0.25, -2], "radius": 1, "material": "glass" },
    { "type": "box", "min": [0.5, 0, 0.5], "max": [1.5, 2, 1], "material": "red" },
    { "type": "cylinder", "base": [-2, 0.5, 0], "cap": [-2, 0.5, 2], "radius": 0.5, "material": "red" },
    { "type": "mesh", "vertices": [[1, 1.5, -1], [0.5, 1.5, -1], [1, 1, -1]], "triangles": [[0, 1, 2]],
      "material": "glass" },
    { "type": "difference", "material": "red", "children": [
      { "type": "box", "min": [-1, 0, -4], "max": [1, 2, -2] },
      { "type": "sphere", "center": [0, 2, -3], "radius": 0.5 } ] }
  ]
})";

// The number of pixels whose colour differs in any bit; the first one is printed.
int differing_pixels(const Image& a, const Image& b, const char* tracer) {
    int count = 0;
    for (int y = 0; y < a.height(); ++y) {
        for (int x = 0; x < a.width(); ++x) {
            if (std::memcmp(&a.at(x, y), &b.at(x, y), sizeof(Rgb)) != 0) {
                if (count++ == 0) {
                    std::printf(
                        "[ measured ] %s: pixel %d,%d is (%.9g, %.9g, %.9g) placed, (%.9g, %.9g, %.9g) in world\n",
                        tracer, x, y, a.at(x, y).r, a.at(x, y).g, a.at(x, y).b, b.at(x, y).r, b.at(x, y).g,
                        b.at(x, y).b);
                }
            }
        }
    }
    return count;
}

class ExactTransforms : public ::testing::Test {
protected:
    scene::Scene placed_ = scene::parse_scene(header + placed_objects, "<placed>");
    scene::Scene world_ = scene::parse_scene(header + world_objects, "<world>");
    RenderOptions options_ = single_thread();

    static RenderOptions single_thread() {
        RenderOptions options;
        options.threads = 1;
        return options;
    }
};

TEST_F(ExactTransforms, TheReferenceRendersAPlacedSceneBitForBitAsItsWorldCoordinates) {
    EXPECT_EQ(differing_pixels(reference::render<double>(placed_, options_).image,
                               reference::render<double>(world_, options_).image, "reference"),
              0);
    EXPECT_EQ(differing_pixels(reference::render<float>(placed_, options_).image,
                               reference::render<float>(world_, options_).image, "reference-float"),
              0);
}

TEST_F(ExactTransforms, TheSseTracerRendersAPlacedSceneBitForBitAsItsWorldCoordinates) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    EXPECT_EQ(differing_pixels(sse::render(placed_, options_).image, sse::render(world_, options_).image, "sse"), 0);
}

// The same scene as world coordinates hold it is also what both tracers hold: nothing stays in object space.
TEST_F(ExactTransforms, NoPrimitiveOfTheExactSceneStaysInObjectSpace) {
    for (const scene::Object& object : placed_.objects) {
        EXPECT_EQ(object.shape.index(), world_.objects[&object - placed_.objects.data()].shape.index());
    }
    EXPECT_EQ(placed_.meshes.at(0).data->vertices, world_.meshes.at(0).data->vertices);
}

}  // namespace
}  // namespace twinray
