// Instances of mesh shapes (docs/scene-format.md, "Shapes and instances"): how the loader resolves them, that an
// instance placed exactly (translations on a binary grid, seen from an eye on it, scales by powers of two, turns by
// multiples of 90°) meets the same triangles at the same t as the mesh written in world coordinates, bit for bit but
// where a tracer's arithmetic takes the axes in another order (below), and that the BVH over instances answers as
// brute force does.
#include "reference/tracer.h"
#include "scene/loader.h"
#include "sse/cpu.h"
#include "sse/tracer.h"
#include "tests/gltf_files.h"
#include "tests/scene_json.h"
#include "tests/test_output.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace twinray {
namespace {

// The eye on the grid too: o − t from an eye off it rounds, and then L⁻¹(o − t) − v may round again where o − v did
// once (0.3 − 2, then 0.5 + 1.7 passes a power of two).
const std::string header = test::json::lit_scene_opening(80, 60, {0.25, 3, 7});

// An octahedron, closed and wound outward, its vertices on a binary grid; smooth, so that its shading normals are
// carried out of object space too.
const std::string octahedron = R"({"type": "mesh", "smooth": true,
    "vertices": [[0.5, 0, 0], [-0.5, 0, 0], [0, 0.5, 0], [0, -0.5, 0], [0, 0, 0.5], [0, 0, -0.5]],
    "triangles": [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])";

// The same scene twice: instances of the octahedron (moved by a binary grid's steps, scaled by 2, 4 and 0.5, turned
// by 90° about y and 180° about x), and the octahedra they place written out in world coordinates (worked out by
// hand: vertex · scale, turned, + offset; the turns must come out as exact permutations, and a turn the other way
// would name other triangles).
const std::string instanced = header + R"(
  "shapes": { "gem": )" + octahedron +
                              R"(} },
  "objects": [
    { "type": "plane", "normal": [0, 1, 0], "offset": -1, "material": "blue" },
    { "type": "instance", "shape": "gem", "material": "red", "transform": [{"translate": [-1.5, 0.25, -0.5]}] },
    { "type": "instance", "shape": "gem", "material": "glass",
      "transform": [{"scale": 2}, {"translate": [1, 0.5, -2]}] },
    { "type": "instance", "shape": "gem", "transform": [{"scale": [4, 0.5, 2]}, {"translate": [0, -0.75, 1]}] },
    { "type": "instance", "shape": "gem", "material": "red",
      "transform": [{"rotate": [0, 90, 0]}, {"translate": [2, 0.25, 1.5]}] },
    { "type": "instance", "shape": "gem",
      "transform": [{"scale": 0.5}, {"rotate": {"axis": [1, 0, 0], "deg": 180}},
                    {"translate": [-2.5, 0.5, 1.5]}] }
  ]
})";

const std::string flattened = header + R"(
  "objects": [
    { "type": "plane", "normal": [0, 1, 0], "offset": -1, "material": "blue" },
    { "type": "mesh", "material": "red", "smooth": true,
      "vertices": [[-1, 0.25, -0.5], [-2, 0.25, -0.5], [-1.5, 0.75, -0.5], [-1.5, -0.25, -0.5], [-1.5, 0.25, 0],
                   [-1.5, 0.25, -1]],
      "triangles": [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]] },
    { "type": "mesh", "material": "glass", "smooth": true,
      "vertices": [[2, 0.5, -2], [0, 0.5, -2], [1, 1.5, -2], [1, -0.5, -2], [1, 0.5, -1], [1, 0.5, -3]],
      "triangles": [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]] },
    { "type": "mesh", "smooth": true,
      "vertices": [[2, -0.75, 1], [-2, -0.75, 1], [0, -0.5, 1], [0, -1, 1], [0, -0.75, 2], [0, -0.75, 0]],
      "triangles": [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]] },
    { "type": "mesh", "material": "red", "smooth": true,
      "vertices": [[2, 0.25, 1], [2, 0.25, 2], [2, 0.75, 1.5], [2, -0.25, 1.5], [2.5, 0.25, 1.5], [1.5, 0.25, 1.5]],
      "triangles": [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]] },
    { "type": "mesh", "smooth": true,
      "vertices": [[-2.25, 0.5, 1.5], [-2.75, 0.5, 1.5], [-2.5, 0.25, 1.5], [-2.5, 0.75, 1.5], [-2.5, 0.5, 1.25],
                   [-2.5, 0.5, 1.75]],
      "triangles": [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]] }
  ]
})";

// The SSE tracer's watertight test carries each ray into a frame chosen by its direction's largest component: an
// uneven scale (objects[3]'s) can choose another axis in object space than in the world, and t then rounds its own
// way. Evenly scaled, moved and turned instances choose the same axis, permuted, and every step of the test is the
// world's scaled by powers of 2 or negated. The reference's t, ((a − o)·n) / (d·n), sums x, y and z in that order: a
// quarter turn (objects[4]'s) sums the same products in another order, so its t may round otherwise; a half turn only
// negates them.
constexpr int uneven_leaf = 3;          // objects[3], scaled by [4, 0.5, 2]
constexpr int quarter_turned_leaf = 4;  // objects[4], turned by 90° about y

struct Compared {
    int rays = 0, hits = 0, mismatches = 0;
    // The largest |Δ| of a geometric normal's component, or of a shading normal's where they are compared (below), and
    // the leaf it is on.
    double worst_normal = 0;
    int worst_normal_leaf = -1;
    double worst_t = 0;  // the largest |Δt|/t on leaves whose t need not be bit for bit
};

// Every pixel's primary ray, first hit against first hit: the same leaf and triangle at the same t, bit for bit
// where exact(leaf), else within 8 ulps. Shading normals are compared where the scale is even and t bit for bit: under
// an uneven scale the instance carries its shape's vertex normals through L⁻ᵀ, where the flattened mesh weighs its own
// triangles, and a t a few ulps off moves the point the normals are weighed at (tens of ulps of the normal on a gem
// half a unit across).
template <typename Primary, typename InstancedHit, typename FlattenedHit>
Compared compare_first_hits(const scene::Scene& scene, Primary&& primary, InstancedHit&& instanced_hit,
                            FlattenedHit&& flattened_hit, bool (*exact)(int leaf)) {
    Compared out;
    for (int y = 0; y < scene.height; ++y) {
        for (int x = 0; x < scene.width; ++x) {
            const auto ray = primary(x, y);
            const auto a = instanced_hit(ray), b = flattened_hit(ray);
            ++out.rays;
            using T = decltype(a->t);
            const double t_error = a && b ? std::fabs(double(a->t) - double(b->t)) / double(b->t) : 0.0;
            if (a && b && !exact(a->leaf)) {
                out.worst_t = std::max(out.worst_t, t_error);
            }
            const bool same_t = a && b &&
                                (exact(a->leaf) ? std::memcmp(&a->t, &b->t, sizeof(a->t)) == 0
                                                : t_error <= 8 * std::numeric_limits<T>::epsilon());
            if (a.has_value() != b.has_value() ||
                (a && (!same_t || a->leaf != b->leaf || a->triangle != b->triangle || a->entering != b->entering))) {
                if (out.mismatches++ == 0) {
                    std::printf(
                        "[ measured ] pixel %d,%d: instanced %s t %.17g leaf %d triangle %d, flattened %s t "
                        "%.17g leaf %d triangle %d\n",
                        x, y, a ? "hit" : "miss", a ? double(a->t) : 0.0, a ? a->leaf : -1, a ? a->triangle : -1,
                        b ? "hit" : "miss", b ? double(b->t) : 0.0, b ? b->leaf : -1, b ? b->triangle : -1);
                }
                continue;
            }
            if (a) {
                ++out.hits;
                for (int axis = 0; axis < 3; ++axis) {
                    const double shading =
                        a->leaf == uneven_leaf || !exact(a->leaf)
                            ? 0.0
                            : std::fabs(double(a->shading_normal[axis]) - double(b->shading_normal[axis]));
                    const double error =
                        std::max(std::fabs(double(a->normal[axis]) - double(b->normal[axis])), shading);
                    if (error > out.worst_normal) {
                        out.worst_normal = error;
                        out.worst_normal_leaf = a->leaf;
                    }
                }
            }
        }
    }
    return out;
}

class ExactInstances : public ::testing::Test {
protected:
    scene::Scene instanced_ = scene::parse_scene(instanced, "<instanced>");
    scene::Scene flattened_ = scene::parse_scene(flattened, "<flattened>");

    template <typename T>
    void expect_same_first_hits(const char* name) {
        const reference::Tracer<T> a(instanced_), b(flattened_);
        Compared compared = compare_first_hits(
            instanced_, [&](int x, int y) { return a.primary_ray(x, y, instanced_.width, instanced_.height); },
            [&](const reference::Ray<T>& ray) { return a.intersect(ray); },
            [&](const reference::Ray<T>& ray) { return b.intersect(ray); },
            [](int leaf) { return leaf != quarter_turned_leaf; });
        report(name, compared, std::numeric_limits<T>::epsilon());
    }

    static void report(const char* name, const Compared& compared, double epsilon) {
        std::printf(
            "[ measured ] %s: %d rays, %d hits on both, %d differ; normals within %.3g (%.2f ulps, on objects[%d]), "
            "t where not bit for bit (the uneven scale in sse, the quarter turn in the reference) within %.2f ulps\n",
            name, compared.rays, compared.hits, compared.mismatches, compared.worst_normal,
            compared.worst_normal / epsilon, compared.worst_normal_leaf, compared.worst_t / epsilon);
        EXPECT_EQ(compared.mismatches, 0) << name;
        EXPECT_GT(compared.hits, compared.rays / 4) << name << ": the scene must be hit";
        // A normal comes back through L⁻ᵀ and is made unit again: a few roundings of a unit vector. A shading normal
        // is also weighed at the point carried into the shape's space, L⁻¹(p − t), which rounds once more, by as much
        // as the normals bend across the gem: 4.5 ulps in double on objects[5], a gem half the shape's size.
        EXPECT_LE(compared.worst_normal, 6 * epsilon) << name;
    }
};

TEST_F(ExactInstances, AMeshShapeIsReadOnceAndEachInstanceIsOneLeafNamedAfterIt) {
    ASSERT_EQ(instanced_.mesh_shapes.size(), 1u);
    ASSERT_EQ(instanced_.meshes.size(), 5u);
    EXPECT_EQ(instanced_.meshes[0].data, instanced_.meshes[2].data);
    EXPECT_EQ(instanced_.leaf_paths[1], "objects[1]");
    EXPECT_EQ(instanced_.leaf_name(1), "objects[1] (shapes.gem)");
    EXPECT_EQ(instanced_.leaf_name(0), "objects[0]");
    // The floor, five instances and the shape's eight triangles once; flattened, each mesh's eight.
    EXPECT_EQ(instanced_.primitive_count(), 1u + 5u + 8u);
    EXPECT_EQ(flattened_.primitive_count(), 1u + 5u * 8u);
    EXPECT_EQ(instanced_.leaf_materials, flattened_.leaf_materials);
}

// A shape's own material wins over its instances'; where it names none, each instance's applies.
TEST(Instances, AShapesMaterialWinsAndAnInstancesAppliesWhereItNamesNone) {
    const scene::Scene scene = scene::parse_scene(header + R"(
      "shapes": { "red_gem": {"type": "mesh", "material": "red", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                              "triangles": [[0, 1, 2]]},
                  "ball": {"type": "sphere", "center": [0, 0, 0], "radius": 1} },
      "objects": [
        { "type": "instance", "shape": "red_gem", "material": "blue" },
        { "type": "instance", "shape": "ball", "material": "blue", "transform": [{"scale": [1, 2, 1]}] },
        { "type": "union", "material": "glass", "children": [
          { "type": "instance", "shape": "ball", "transform": [{"translate": [0, 3, 0]}] },
          { "type": "sphere", "center": [0, 5, 0], "radius": 1 } ] }
      ]})",
                                                  "<materials>");
    const auto index = [&](const std::string& name) {
        return static_cast<int>(std::find(scene.material_names.begin(), scene.material_names.end(), name) -
                                scene.material_names.begin());
    };
    ASSERT_EQ(scene.leaf_materials.size(), 4u);
    EXPECT_EQ(scene.leaf_materials[0], index("red"));
    EXPECT_EQ(scene.leaf_materials[1], index("blue"));
    EXPECT_EQ(scene.leaf_materials[2], index("glass"));
    // A sphere shape's instance is the shape read in its place, under its transform: here an ellipsoid.
    EXPECT_TRUE(std::holds_alternative<scene::Transformed<scene::Sphere>>(scene.objects.at(0).shape));
    EXPECT_EQ(scene.leaf_paths[2], "objects[2].children[0] (shapes.ball)");
}

TEST_F(ExactInstances, TheReferenceMeetsExactInstancesAtTheFlattenedMeshesTBitForBitAQuarterTurnWithinUlps) {
    expect_same_first_hits<double>("reference");
    expect_same_first_hits<float>("reference-float");
}

TEST_F(ExactInstances, TheSseTracerMeetsEvenlyScaledOrTurnedInstancesAtTheFlattenedMeshesTBitForBit) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    const sse::Tracer a(instanced_), b(flattened_);
    Compared compared = compare_first_hits(
        instanced_, [&](int x, int y) { return a.primary_ray(x, y, instanced_.width, instanced_.height); },
        [&](const sse::Ray& ray) { return a.intersect(ray); }, [&](const sse::Ray& ray) { return b.intersect(ray); },
        [](int leaf) { return leaf != uneven_leaf; });
    report("sse", compared, std::numeric_limits<float>::epsilon());
}

// The number of pixels whose colour differs in any bit; the first one is printed.
int differing_pixels(const Image& a, const Image& b, const char* what) {
    int count = 0;
    for (int y = 0; y < a.height(); ++y) {
        for (int x = 0; x < a.width(); ++x) {
            if (std::memcmp(&a.at(x, y), &b.at(x, y), sizeof(Rgb)) != 0 && count++ == 0) {
                std::printf(
                    "[ measured ] %s: pixel %d,%d is (%.9g, %.9g, %.9g) with the BVH, (%.9g, %.9g, %.9g) "
                    "without\n",
                    what, x, y, a.at(x, y).r, a.at(x, y).g, a.at(x, y).b, b.at(x, y).r, b.at(x, y).g, b.at(x, y).b);
            }
        }
    }
    return count;
}

// The BVH over instances (and each shape's own) only skips what a ray cannot meet: images, shadows through the
// glass instance included, are those of brute force bit for bit.
TEST_F(ExactInstances, TheBvhOverInstancesRendersAsBruteForceBitForBit) {
    RenderOptions with_bvh, brute_force;
    with_bvh.threads = brute_force.threads = 1;
    with_bvh.accel = Accel::bvh;
    brute_force.accel = Accel::none;
    EXPECT_EQ(differing_pixels(reference::render<double>(instanced_, with_bvh).image,
                               reference::render<double>(instanced_, brute_force).image, "reference"),
              0);
    if (sse::cpu_supports_sse41()) {
        EXPECT_EQ(differing_pixels(sse::render(instanced_, with_bvh).image, sse::render(instanced_, brute_force).image,
                                   "sse"),
                  0);
    }
}

// A render that gives up the scene's objects, meshes and leaf paths (the render command's,
// sse::Tracer::give_up_geometry) finds them empty afterwards and draws the image the tracer draws from a scene it
// keeps, bit for bit, with its BVH and without.
TEST_F(ExactInstances, TheSseTracerGivenUpTheGeometryRendersTheSameImage) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    for (Accel accel : {Accel::bvh, Accel::none}) {
        RenderOptions options;
        options.threads = 1;
        options.accel = accel;
        scene::Scene given = instanced_;
        const sse::Tracer giving_up(given, sse::Tracer::give_up_geometry, {}, accel);
        EXPECT_TRUE(given.objects.empty() && given.meshes.empty() && given.leaf_paths.empty());
        EXPECT_EQ(differing_pixels(sse::render(instanced_, options).image, sse::render(giving_up, given, options).image,
                                   accel == Accel::bvh ? "sse, bvh" : "sse, brute force"),
                  0);
    }
}

// A shape whose box reaches past float's range (one vertex at 1.86e290) is still met where its ordinary triangles are:
// its instance's box in the SSE tracer was centre ± half extent, ∞ − ∞ made its faces NaN, and a turned instance was
// missed with and without the BVH (a fuzz input: tests/data/fuzz_regressions/bvh_differential). Both SSE walks now
// meet its first triangle as the reference does.
TEST(Instances, AShapeReachingPastFloatsRangeIsMetWhereItsOrdinaryTrianglesAre) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    const scene::Scene scene = scene::parse_scene(header + R"(
      "shapes": { "far_reaching": {"type": "mesh", "vertices": [[-4, -2, 1], [4, -1.40625, 0], [-1, -1.640625, -2],
                                                                 [2, -3, 1.859375e290]],
                                   "triangles": [[0, 1, 2], [0, 2, 3]]} },
      "objects": [ { "type": "instance", "shape": "far_reaching", "transform": [{"rotate": [0, 0, 30]}] } ]})",
                                                  "<far reaching>");
    const scene::Vec3 origin{-1, -3, -0.0001734375}, direction{0, 1, 0};
    const auto expected = reference::Tracer<double>(scene).intersect({origin, direction});
    ASSERT_TRUE(expected.has_value());
    ASSERT_EQ(expected->triangle, 0);
    for (Accel accel : {Accel::none, Accel::bvh}) {
        const auto hit = sse::Tracer(scene, {}, accel).intersect({origin, sse::Vec3(direction)});
        const char* walk = accel == Accel::bvh ? "bvh" : "brute force";
        ASSERT_TRUE(hit.has_value()) << walk << ": the reference meets triangle 0 at t " << expected->t;
        EXPECT_EQ(hit->leaf, 0) << walk;
        EXPECT_EQ(hit->triangle, 0) << walk;
        EXPECT_NEAR(hit->t, expected->t, 1e-5 * expected->t) << walk;
    }
}

// ---------------------------------------------------------------------------------------------------
// A glTF file's nodes (tests/gltf_files.h: one octahedron placed by three nodes under a parent that halves and lifts
// them): instances of one mesh shape at the top level, one mesh placed by them in `shapes`.

// `scene_text` written beside three_gems.gltf and loaded from there, at most `max_primitives`.
scene::Scene load_beside_gltf(const std::string& name, const std::string& scene_text,
                              std::size_t max_primitives = scene::max_scene_primitives) {
    const std::filesystem::path dir = test::fresh_directory(test::own_output_path("instance_gltf"));
    std::ofstream(dir / "three_gems.gltf") << test::octahedron_gltf(test::three_gems_nodes, "[0]");
    return scene::parse_scene(scene_text, (dir / name).string(), max_primitives);
}

const std::string gltf_gems = header + R"(
  "objects": [
    { "type": "plane", "normal": [0, 1, 0], "offset": -1, "material": "blue" },
    { "type": "mesh", "file": "three_gems.gltf", "smooth": true, "material": "red" }
  ]
})";

// The same, written by hand: the node's TRS, then its parent's.
const std::string hand_gems = header + R"(
  "shapes": { "gem": )" + octahedron +
                              R"(} },
  "objects": [
    { "type": "plane", "normal": [0, 1, 0], "offset": -1, "material": "blue" },
    { "type": "instance", "shape": "gem", "material": "red",
      "transform": [{"translate": [-1.5, 0.25, -0.5]}, {"scale": 0.5}, {"translate": [0, 0.5, 0]}] },
    { "type": "instance", "shape": "gem", "material": "red",
      "transform": [{"scale": 2}, {"translate": [1, 0.5, -2]}, {"scale": 0.5}, {"translate": [0, 0.5, 0]}] },
    { "type": "instance", "shape": "gem", "material": "red",
      "transform": [{"rotate": [0, 90, 0]}, {"translate": [0, -0.75, 1]}, {"scale": 0.5}, {"translate": [0, 0.5, 0]}] }
  ]
})";

TEST(GltfInstances, AMeshThreeNodesPlaceIsOneShapeAndThreeInstancesAtTheNodesWorldTransforms) {
    const scene::Scene scene = load_beside_gltf("gems.json", gltf_gems);
    ASSERT_EQ(scene.mesh_shapes.size(), 1u);
    EXPECT_EQ(scene.mesh_shapes[0].name, "three_gems.gltf mesh 0");
    EXPECT_EQ(scene.mesh_shapes[0].data->triangles.size(), 8u);
    ASSERT_EQ(scene.meshes.size(), 3u);
    for (const scene::Mesh& mesh : scene.meshes) {
        EXPECT_EQ(mesh.data, scene.mesh_shapes[0].data) << "each instance shares the one shape";
        ASSERT_TRUE(mesh.placement);
        EXPECT_EQ(mesh.placement->shape, 0);
    }
    EXPECT_EQ(scene.leaf_name(1), "objects[1] node \"Left\" (three_gems.gltf mesh 0)");
    EXPECT_EQ(scene.leaf_name(2), "objects[1] node \"Big\" (three_gems.gltf mesh 0)");
    EXPECT_EQ(scene.leaf_name(3), "objects[1] node \"Turned\" (three_gems.gltf mesh 0)");
    const auto expect_placed = [&](int instance, std::array<scene::Vec3, 3> rows, scene::Vec3 translation) {
        const scene::Placement& placed = *scene.meshes[static_cast<std::size_t>(instance)].placement;
        for (int r = 0; r < 3; ++r) {
            EXPECT_EQ(placed.linear.row[r], rows[static_cast<std::size_t>(r)]) << "instance " << instance;
        }
        EXPECT_EQ(placed.translation, translation) << "instance " << instance;
    };
    expect_placed(0, {{{0.5, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5}}}, {-0.75, 0.625, -0.25});
    expect_placed(1, {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}, {0.5, 0.75, -1});
    expect_placed(2, {{{0, 0, 0.5}, {0, 0.5, 0}, {-0.5, 0, 0}}}, {0, 0.125, 0.5});
    // The floor, the shape's eight triangles once and each instance one.
    EXPECT_EQ(scene.primitive_count(), 1u + 8u + 3u);
}

TEST(GltfInstances, BothTracersRenderTheFileAsTheSameInstancesWrittenByHandBitForBit) {
    const scene::Scene from_file = load_beside_gltf("gems.json", gltf_gems);
    const scene::Scene by_hand = scene::parse_scene(hand_gems, "<hand>");
    RenderOptions options;
    options.threads = 1;
    EXPECT_EQ(differing_pixels(reference::render<double>(from_file, options).image,
                               reference::render<double>(by_hand, options).image, "reference"),
              0);
    if (sse::cpu_supports_sse41()) {
        EXPECT_EQ(differing_pixels(sse::render(from_file, options).image, sse::render(by_hand, options).image, "sse"),
                  0);
    }
}

TEST(GltfInstances, InShapesTheNodesMeshesArePlacedIntoOneMeshExactly) {
    const scene::Scene scene = load_beside_gltf("gem_shape.json", header + R"(
      "shapes": { "gems": { "type": "mesh", "file": "three_gems.gltf" } },
      "objects": [ { "type": "instance", "shape": "gems" }, { "type": "instance", "shape": "gems" } ]
    })");
    ASSERT_EQ(scene.mesh_shapes.size(), 1u);
    const scene::MeshData& mesh = *scene.mesh_shapes[0].data;
    // Each node's copy of the octahedron, in the nodes' order, by the world transforms worked out by hand.
    const auto left = [](scene::Vec3 p) { return scene::Vec3{0.5 * p.x - 0.75, 0.5 * p.y + 0.625, 0.5 * p.z - 0.25}; };
    const auto big = [](scene::Vec3 p) { return scene::Vec3{p.x + 0.5, p.y + 0.75, p.z - 1}; };
    const auto turned = [](scene::Vec3 p) { return scene::Vec3{0.5 * p.z, 0.5 * p.y + 0.125, -0.5 * p.x + 0.5}; };
    std::vector<scene::Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    for (scene::Vec3 (*place)(scene::Vec3) : {+left, +big, +turned}) {
        const auto first = static_cast<std::uint32_t>(vertices.size());
        for (const auto& [x, y, z] : test::octahedron_vertices) {
            vertices.push_back(place({x, y, z}));
        }
        for (const auto& [a, b, c] : test::octahedron_triangles) {
            triangles.push_back({first + a, first + b, first + c});
        }
    }
    EXPECT_EQ(mesh.vertices, vertices);
    EXPECT_EQ(mesh.triangles, triangles);
    EXPECT_EQ(mesh.file, "three_gems.gltf");
    // The shape's 24 triangles once and two instances.
    EXPECT_EQ(scene.primitive_count(), 24u + 2u);
}

// The refusal of `scene_text` beside three_gems.gltf, at most `max_primitives`.
scene::SceneError refusal_beside_gltf(const std::string& scene_text, std::size_t max_primitives) {
    try {
        load_beside_gltf("refused.json", scene_text, max_primitives);
    } catch (const scene::SceneError& error) {
        return error;
    }
    ADD_FAILURE() << "loaded, not refused";
    return scene::SceneError("", "", "");
}

TEST(GltfInstances, WhatTheNodesPlacePastThePrimitiveLimitIsRefusedNamingTheFile) {
    const std::string over =
        ": more than the limit of 10 primitives (about 165 bytes of memory each when rendered; no "
        "scene may hold more than 4194304)";
    // Instanced: the floor, then 8 triangles and 3 instances, one more than 11 allows.
    scene::SceneError error = refusal_beside_gltf(gltf_gems, 11);
    EXPECT_EQ(error.location(), "objects[1].file");
    EXPECT_EQ(error.problem(), "three_gems.gltf: its 1 meshes of 8 triangles and the 3 nodes that place them" + over);
    // Placed into one mesh: 24 triangles.
    error = refusal_beside_gltf(header + R"(
      "shapes": { "gems": { "type": "mesh", "file": "three_gems.gltf" } },
      "objects": [ { "type": "plane", "normal": [0, 1, 0], "offset": -1 } ] })",
                                11);
    EXPECT_EQ(error.location(), "shapes.gems.file");
    EXPECT_EQ(error.problem(), "three_gems.gltf: its nodes place 3 meshes of 24 triangles and 18 vertices in all" +
                                   std::string(": more than the limit of 11 primitives (about 165 bytes of memory each "
                                               "when rendered; no scene may hold more than 4194304)"));
    EXPECT_EQ(load_beside_gltf("fits.json", gltf_gems, 12).primitive_count(), 12u);
}

TEST(GltfInstances, ANodeTransformPastTheConditionLimitIsRefusedNamingTheFileAndNode) {
    const std::filesystem::path dir = test::fresh_directory(test::own_output_path("instance_gltf"));
    std::ofstream(dir / "flat.gltf") << test::octahedron_gltf(
        R"([{"name": "Flat", "mesh": 0, "scale": [1, 1e-6, 1]}, {"name": "Fine", "mesh": 0}])", "[0, 1]");
    const std::string conditioned = "the transform is too badly conditioned: its condition number";
    for (const char* where : {"objects", "shapes"}) {
        SCOPED_TRACE(where);
        const std::string scene_text =
            std::string(where) == "objects"
                ? header + R"("objects": [ { "type": "mesh", "file": "flat.gltf" } ] })"
                : header + R"("shapes": { "flat": { "type": "mesh", "file": "flat.gltf" } }, "objects": [] })";
        try {
            scene::parse_scene(scene_text, (dir / "flat.json").string());
            ADD_FAILURE() << "loaded, not refused";
        } catch (const scene::SceneError& error) {
            EXPECT_EQ(error.location(), std::string(where) == "objects" ? "objects[0].file" : "shapes.flat.file");
            EXPECT_TRUE(error.problem().starts_with("flat.gltf: node \"Flat\": " + conditioned)) << error.problem();
        }
    }
    // Under an object's own transform the composed one is judged: a thousandth of z twice (each alone passes).
    std::ofstream(dir / "thin.gltf") << test::octahedron_gltf(
        R"([{"name": "Thin", "mesh": 0, "scale": [1, 1, 0.001]}, {"name": "Fine", "mesh": 0}])", "[0, 1]");
    try {
        scene::parse_scene(header + R"("objects": [ { "type": "mesh", "file": "thin.gltf",
                                                      "transform": [{"scale": [1, 1, 0.001]}] } ] })",
                           (dir / "thinner.json").string());
        ADD_FAILURE() << "loaded, not refused";
    } catch (const scene::SceneError& error) {
        EXPECT_EQ(error.location(), "objects[0].file");
        EXPECT_TRUE(
            error.problem().starts_with("thin.gltf: node \"Thin\", followed by the object's transform: " + conditioned))
            << error.problem();
    }
}

}  // namespace
}  // namespace twinray
