// `twinray generate`: every family's scene has the size its rule promises and is the same bytes for the
// same family, size and seed; the primitive families' scenes load with our loader and render with both
// tracers; the mesh families' meshes, read with nlohmann json, are closed and wound outward where they
// should be; bad requests are refused with the usual statuses and leave nothing behind.
#include "cli/exit_codes.h"
#include "cli/generate_scene.h"
#include "reference/tracer.h"
#include "run_twinray.h"
#include "sanitized_build.h"
#include "scene/loader.h"
#include "scene/mesh_file.h"
#include "sse/cpu.h"
#include "sse/tracer.h"
#include "test_output.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

using twinray::cli::generate_scene;
using twinray::cli::GeneratedScene;
using twinray::cli::max_generated_primitives;
using twinray::test::CommandResult;
using twinray::test::run_twinray;
using twinray::test::RunningTwinray;

// The families of primitives the loader reads, and those of one triangle mesh, checked from their JSON.
const std::vector<std::string> primitive_families = {"fractal", "field", "lattice", "csg"};
const std::vector<std::string> mesh_families = {"sphere-mesh",   "torus-mesh", "tetra", "sombrero",
                                                "triangle-soup", "mount",      "gears"};
const std::vector<std::string> closed_mesh_families = {"sphere-mesh", "torus-mesh", "tetra", "gears"};

std::vector<std::string> all_families() {
    std::vector<std::string> all = primitive_families;
    all.insert(all.end(), mesh_families.begin(), mesh_families.end());
    all.push_back("forest");
    return all;
}

struct Generated {
    GeneratedScene scene;
    std::string text;
};

Generated generate(const std::string& family, int size, std::uint64_t seed = 1) {
    Generated generated;
    generated.scene =
        generate_scene(family, size, seed, {[&](std::string_view piece) { generated.text.append(piece); }, {}});
    return generated;
}

std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The count nearest `size` among `achievable` (ascending) and not above the maximum; ties to the smaller.
std::int64_t nearest(const std::vector<std::int64_t>& achievable, int size) {
    std::int64_t best = achievable.front();
    for (std::int64_t count : achievable) {
        if (count <= max_generated_primitives && std::llabs(count - size) < std::llabs(best - size)) {
            best = count;
        }
    }
    return best;
}

// The rule of generate_scene.h and docs/performance.md, restated from the documentation, not the code.
std::int64_t promised_primitives(const std::string& family, int size) {
    if (family == "field") {
        return size;
    }
    if (family == "csg") {
        return size == 2 ? 3 : size;
    }
    std::vector<std::int64_t> achievable;
    if (family == "fractal") {
        for (std::int64_t depth = 0, power = 9; depth <= 7; ++depth, power *= 9) {
            achievable.push_back(1 + (power - 1) / 8);  // floor + (9^(depth+1) − 1) / 8 spheres
        }
    } else {
        for (std::int64_t n = 1; n <= 70; ++n) {
            for (auto [a, b, c] : {std::array{n, n, n}, std::array{n, n, n + 1}, std::array{n, n + 1, n + 1}}) {
                achievable.push_back(1 + 4 * a * b * c - a * b - b * c - c * a);
            }
        }
    }
    return nearest(achievable, size);
}

// The mesh families' rules of generate_scene.h, restated the same way.
std::int64_t promised_triangles(const std::string& family, int size) {
    if (family == "triangle-soup") {
        return size;
    }
    if (family == "tetra") {
        std::int64_t triangles = 4;
        while (4 * triangles <= size) {
            triangles *= 4;
        }
        return triangles;
    }
    std::vector<std::int64_t> achievable;
    if (family == "mount") {
        for (std::int64_t four_to_the_depth = 1; four_to_the_depth <= 1 << 20; four_to_the_depth *= 4) {
            achievable.push_back(2 * four_to_the_depth);
        }
        return nearest(achievable, size);
    }
    for (std::int64_t n = 1; n <= 1000; ++n) {
        if (family == "gears") {
            achievable.push_back(380 * n * n);
        } else if (family == "sphere-mesh" && n >= 2) {
            achievable.push_back(4 * n * (n - 1));
        } else if (family == "torus-mesh" && n >= 3) {
            achievable.push_back(6 * n * n);
        } else if (family == "sombrero") {
            achievable.push_back(2 * n * n);
        }
    }
    return nearest(achievable, size);
}

using Point = std::array<double, 3>;
using Triangle = std::array<std::size_t, 3>;

struct Mesh {
    std::vector<Point> vertices;
    std::vector<Triangle> triangles;
    std::vector<Point> normals;  // empty for a flat mesh
};

// Besides the floor and the mesh: SPD's mount has its pyramid of glass spheres.
int spheres_beside_the_mesh(const std::string& family) {
    return family == "mount" ? 4 : 0;
}

// A mesh family's scene read with nlohmann json, not our loader: its objects must be the floor, one mesh and
// only spheres after it.
Mesh read_mesh(const std::string& text) {
    const nlohmann::json scene = nlohmann::json::parse(text);
    const nlohmann::json& objects = scene.at("objects");
    EXPECT_GE(objects.size(), 2u);
    for (std::size_t i = 2; i < objects.size(); ++i) {
        EXPECT_EQ(objects.at(i).at("type"), "sphere") << "object " << i;
    }
    EXPECT_EQ(objects.at(0).at("type"), "plane");
    const nlohmann::json& object = objects.at(1);
    EXPECT_EQ(object.at("type"), "mesh");
    Mesh mesh;
    mesh.vertices = object.at("vertices").get<std::vector<Point>>();
    mesh.triangles = object.at("triangles").get<std::vector<Triangle>>();
    if (object.contains("normals")) {
        mesh.normals = object.at("normals").get<std::vector<Point>>();
        EXPECT_EQ(object.at("smooth"), true);
    }
    return mesh;
}

Point minus(const Point& a, const Point& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

Point cross(const Point& a, const Point& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double dot(const Point& a, const Point& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// The volume a closed mesh encloses, positive when its triangles are counter-clockwise seen from outside
// (the divergence theorem: the sum of the tetrahedra from the origin to each triangle).
double signed_volume(const Mesh& mesh) {
    double volume = 0;
    for (const auto& [a, b, c] : mesh.triangles) {
        volume += dot(mesh.vertices[a], cross(mesh.vertices[b], mesh.vertices[c])) / 6;
    }
    return volume;
}

class GenerateTest : public ::testing::Test {
protected:
    void SetUp() override { folder_ = twinray::test::fresh_directory(twinray::test::own_output_path("generate")); }
    std::string path(const std::string& name) const { return (folder_ / name).string(); }
    std::vector<std::string> files() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(folder_)) {
            names.push_back(entry.path().filename().string());
        }
        return names;
    }
    fs::path folder_;
};

// Test names may hold only letters, digits and underscores.
std::string test_name(const ::testing::TestParamInfo<std::string>& param_info) {
    std::string name = param_info.param;
    std::replace(name.begin(), name.end(), '-', '_');
    return name;
}

class EveryFamily : public GenerateTest, public ::testing::WithParamInterface<std::string> {};
class PrimitiveFamily : public GenerateTest, public ::testing::WithParamInterface<std::string> {};
class MeshFamily : public GenerateTest, public ::testing::WithParamInterface<std::string> {};
class ClosedMeshFamily : public GenerateTest, public ::testing::WithParamInterface<std::string> {};

INSTANTIATE_TEST_SUITE_P(Families, EveryFamily, ::testing::ValuesIn(all_families()), test_name);
INSTANTIATE_TEST_SUITE_P(Families, PrimitiveFamily, ::testing::ValuesIn(primitive_families), test_name);
INSTANTIATE_TEST_SUITE_P(Families, MeshFamily, ::testing::ValuesIn(mesh_families), test_name);
INSTANTIATE_TEST_SUITE_P(Families, ClosedMeshFamily, ::testing::ValuesIn(closed_mesh_families), test_name);

TEST_P(PrimitiveFamily, GeneratedScenesLoadAndHaveTheRequestedSize) {
    for (int size : {1, 2, 3, 10, 11, 99, 1000, 5000, 30000}) {
        Generated generated = generate(GetParam(), size);
        twinray::scene::Scene scene = twinray::scene::parse_scene(generated.text, GetParam());
        EXPECT_EQ(static_cast<std::int64_t>(scene.leaf_paths.size()), generated.scene.primitives) << size;
        EXPECT_EQ(generated.scene.primitives, promised_primitives(GetParam(), size)) << "--size " << size;
    }
}

TEST_P(EveryFamily, GenerateIsByteIdenticalForTheSameSeed) {
    for (const char* name : {"a.json", "b.json"}) {
        CommandResult result = run_twinray("generate " + GetParam() + " --size 500 --seed 7 -o " + path(name));
        ASSERT_EQ(result.exit_status, twinray::cli::exit_success) << result.output;
    }
    std::string written = read_bytes(path("a.json"));
    EXPECT_EQ(written, read_bytes(path("b.json")));
    EXPECT_EQ(written, generate(GetParam(), 500, 7).text) << "the command writes what generate_scene writes";
}

TEST_P(PrimitiveFamily, GenerateReportsHowManyPrimitivesItWrote) {
    CommandResult result = run_twinray("generate " + GetParam() + " --size 100 -o " + path("s.json"));
    ASSERT_EQ(result.exit_status, twinray::cli::exit_success) << result.output;
    std::size_t leaves = twinray::scene::load_scene(path("s.json")).leaf_paths.size();
    EXPECT_NE(result.output.find("wrote " + std::to_string(leaves) + " primitives"), std::string::npos)
        << result.output;
}

// A small scene of each family rendered by reference<double> and the SSE tracer at 40 × 30: the
// family's objects (not only its floor) must show, in the share of pixels that differ from the same
// view of the floor alone.
TEST_P(PrimitiveFamily, GeneratedScenesRenderWithBothTracers) {
    twinray::scene::Scene scene = twinray::scene::parse_scene(generate(GetParam(), 60).text, GetParam());
    // The floor is written first: leaf 0, objects[0].
    twinray::scene::Scene floor_only = scene;
    floor_only.objects.resize(1);
    floor_only.leaf_paths.clear();
    floor_only.leaf_paths.push_back(scene.leaf_paths[0]);
    floor_only.leaf_materials.resize(1);
    twinray::RenderOptions options;
    options.width = 40;
    options.height = 30;
    options.threads = 1;
    auto share_showing_objects = [&](const twinray::Image& image, const twinray::Image& floor) {
        int differing = 0;
        for (std::size_t i = 0; i < image.pixels().size(); ++i) {
            const twinray::Rgb& a = image.pixels()[i];
            const twinray::Rgb& b = floor.pixels()[i];
            float difference = std::max({std::fabs(a.r - b.r), std::fabs(a.g - b.g), std::fabs(a.b - b.b)});
            differing += difference > 0.02f ? 1 : 0;
        }
        return static_cast<double>(differing) / static_cast<double>(image.pixels().size());
    };
    EXPECT_GT(share_showing_objects(twinray::reference::render<double>(scene, options).image,
                                    twinray::reference::render<double>(floor_only, options).image),
              0.1)
        << "reference<double>";
    if (!twinray::sse::cpu_supports_sse41()) {
        GTEST_SKIP() << "no SSE4.1 on this CPU: the SSE tracer's render is not tested";
    }
    EXPECT_GT(share_showing_objects(twinray::sse::render(scene, options).image,
                                    twinray::sse::render(floor_only, options).image),
              0.1)
        << "sse";
}

// Up to 30 000 the JSON is read back; the largest size holds the rule's cap, counted as it is written.
TEST_P(MeshFamily, MeshScenesAreTheFloorAndOneMeshOfTheTrianglesTheRulePromises) {
    for (int size : {1, 2, 3, 10, 11, 99, 1000, 5000, 30000, 100000, max_generated_primitives}) {
        Generated generated = generate(GetParam(), size);
        EXPECT_EQ(generated.scene.primitives, 2 + spheres_beside_the_mesh(GetParam())) << "--size " << size;
        EXPECT_EQ(generated.scene.triangles, promised_triangles(GetParam(), size)) << "--size " << size;
        if (size > 30000) {
            continue;
        }
        Mesh mesh = read_mesh(generated.text);
        EXPECT_EQ(static_cast<std::int64_t>(mesh.triangles.size()), generated.scene.triangles) << "--size " << size;
        for (const Triangle& triangle : mesh.triangles) {
            for (std::size_t index : triangle) {
                ASSERT_LT(index, mesh.vertices.size()) << "--size " << size;
            }
        }
    }
}

// The curved meshes are smooth, with normals on the coordinates' grid, so each within a grid step of unit
// length; the tetrahedra and the soup are flat.
TEST_P(MeshFamily, CurvedMeshesHaveOneUnitNormalPerVertexAndFlatOnesNone) {
    const bool curved = GetParam() == "sphere-mesh" || GetParam() == "torus-mesh" || GetParam() == "sombrero";
    for (int size : {10, 1000, 20000}) {
        Mesh mesh = read_mesh(generate(GetParam(), size).text);
        ASSERT_EQ(mesh.normals.size(), curved ? mesh.vertices.size() : 0) << "--size " << size;
        for (const Point& normal : mesh.normals) {
            ASSERT_NEAR(std::sqrt(dot(normal, normal)), 1, 1e-3) << "--size " << size;
        }
    }
}

// Each directed edge once and its reverse once: every edge is shared by exactly two triangles that cross
// it in opposite directions, so the surface is closed and its winding consistent.
TEST_P(ClosedMeshFamily, EveryEdgeIsSharedByTwoTrianglesWoundOppositely) {
    for (int size : {1, 50, 1000, 20000}) {
        Mesh mesh = read_mesh(generate(GetParam(), size).text);
        std::map<std::pair<std::size_t, std::size_t>, int> directed_edges;
        for (const auto& [a, b, c] : mesh.triangles) {
            for (auto edge : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
                ++directed_edges[edge];
            }
        }
        int repeated = 0, unmatched = 0;
        for (const auto& [edge, uses] : directed_edges) {
            repeated += uses != 1 ? 1 : 0;
            unmatched += directed_edges.count({edge.second, edge.first}) != 1 ? 1 : 0;
        }
        EXPECT_EQ(repeated, 0) << "--size " << size;
        EXPECT_EQ(unmatched, 0) << "--size " << size;
    }
}

TEST_P(ClosedMeshFamily, ClosedMeshesAreWoundOutwardWithAPositiveVolume) {
    for (int size : {1, 50, 1000, 20000}) {
        EXPECT_GT(signed_volume(read_mesh(generate(GetParam(), size).text)), 0) << "--size " << size;
    }
}

// A sphere of radius 1 and a torus of radii 1 and 1/3: the mesh's volume approaches the solid's as its
// triangles shrink.
// One tree of 1 008 triangles (a trunk of 12 sides, three cones of 40 around and three rings), closed and wound
// outward, and exactly `size` instances of it, each placed by a turn about the vertical, an even scale in
// [0.7, 1.2] and a translation along the floor.
TEST_F(GenerateTest, ForestIsOneClosedTreeShapeAndExactlySizeInstancesOfIt) {
    for (int size : {1, 2, 10, 1000}) {
        Generated generated = generate("forest", size);
        EXPECT_EQ(generated.scene.primitives, size + 1) << "--size " << size;
        EXPECT_EQ(generated.scene.triangles, 1008) << "--size " << size;
        const twinray::scene::Scene scene = twinray::scene::parse_scene(generated.text, "<forest>");
        ASSERT_EQ(scene.mesh_shapes.size(), 1u);
        ASSERT_EQ(scene.meshes.size(), static_cast<std::size_t>(size));
        EXPECT_EQ(scene.primitive_count(), static_cast<std::size_t>(size) + 1 + 1008) << "--size " << size;
        for (const twinray::scene::Mesh& mesh : scene.meshes) {
            ASSERT_TRUE(mesh.placement.has_value());
            const double scale = std::cbrt(twinray::math::determinant(mesh.placement->linear));
            EXPECT_GE(scale, 0.7 - 1e-9);
            EXPECT_LE(scale, 1.2 + 1e-9);
            EXPECT_EQ(mesh.placement->translation.y, 0.0);
        }
        const twinray::scene::MeshData& tree = *scene.mesh_shapes[0].data;
        EXPECT_TRUE(twinray::scene::topology_of(tree).closed());
        Mesh mesh;
        for (const twinray::scene::Vec3& v : tree.vertices) {
            mesh.vertices.push_back({v.x, v.y, v.z});
        }
        for (const auto& t : tree.triangles) {
            mesh.triangles.push_back({t[0], t[1], t[2]});
        }
        EXPECT_GT(signed_volume(mesh), 0) << "wound outward";
    }
}

TEST_F(GenerateTest, SphereAndTorusMeshesEncloseTheirSolidsVolume) {
    const double pi = 3.141592653589793;
    const std::vector<std::pair<std::string, double>> solids = {{"sphere-mesh", 4 * pi / 3},
                                                                {"torus-mesh", 2 * pi * pi / 9}};
    for (const auto& [family, volume] : solids) {
        double coarse = signed_volume(read_mesh(generate(family, 1000).text));
        double fine = signed_volume(read_mesh(generate(family, 20000).text));
        EXPECT_LT(std::fabs(fine - volume), std::fabs(coarse - volume)) << family;
        EXPECT_NEAR(fine, volume, 0.005 * volume) << family;
    }
}

// Each level keeps four of the eight half-size copies: the volume halves with the depth. The regular
// tetrahedron of edge √3 holds √3³/(6√2).
TEST_F(GenerateTest, TetraHalvesTheTetrahedronsVolumeAtEachDepth) {
    double volume = std::sqrt(27.0) / (6 * std::sqrt(2.0));
    for (int size : {4, 16, 64, 256, 1024, 4096, 16384}) {
        EXPECT_NEAR(signed_volume(read_mesh(generate("tetra", size).text)), volume, 0.005 * volume) << size;
        volume /= 2;
    }
}

TEST_F(GenerateTest, SphereAndTorusMeshesShareEveryVertex) {
    for (const char* family : {"sphere-mesh", "torus-mesh"}) {
        for (int size : {1, 1000, 20000}) {
            std::vector<Point> vertices = read_mesh(generate(family, size).text).vertices;
            std::sort(vertices.begin(), vertices.end());
            EXPECT_EQ(std::adjacent_find(vertices.begin(), vertices.end()), vertices.end()) << family << " " << size;
        }
    }
}

// A height field over the floor: every triangle's front faces up, and no two triangles overlap seen from
// above (their areas projected on the floor add up to the square's, 6 × 6).
TEST_F(GenerateTest, SombreroIsOneSheetFacingUp) {
    for (int size : {2, 1000, 20000}) {
        Mesh mesh = read_mesh(generate("sombrero", size).text);
        double projected_area = 0;
        for (const auto& [a, b, c] : mesh.triangles) {
            Point normal = cross(minus(mesh.vertices[b], mesh.vertices[a]), minus(mesh.vertices[c], mesh.vertices[a]));
            ASSERT_GT(normal[1], 0) << size;
            projected_area += normal[1] / 2;
        }
        EXPECT_NEAR(projected_area, 36, 1e-6) << size;
    }
}

// The mountain's outline is the square |x|, |z| <= 3 and the floor is below every vertex. Each interior edge is
// shared by exactly two triangles crossing it in opposite directions, so the midpoints are shared and there
// are no cracks; the 4n edges crossed once lie along the outline; the fronts face up and tile the square.
TEST_F(GenerateTest, MountIsOneSheetFacingUpWhoseOnlyBoundaryIsItsOutline) {
    for (int size : {2, 8, 1000, 30000}) {
        Mesh mesh = read_mesh(generate("mount", size).text);
        const auto quads_per_side = static_cast<std::size_t>(std::llround(std::sqrt(mesh.triangles.size() / 2.0)));
        ASSERT_EQ(2 * quads_per_side * quads_per_side, mesh.triangles.size()) << size;
        EXPECT_EQ(mesh.vertices.size(), (quads_per_side + 1) * (quads_per_side + 1)) << size;
        std::map<std::pair<std::size_t, std::size_t>, int> directed_edges;
        double projected_area = 0;
        for (const auto& [a, b, c] : mesh.triangles) {
            for (auto edge : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
                ++directed_edges[edge];
            }
            Point normal = cross(minus(mesh.vertices[b], mesh.vertices[a]), minus(mesh.vertices[c], mesh.vertices[a]));
            ASSERT_GT(normal[1], 0) << size;
            projected_area += normal[1] / 2;
        }
        EXPECT_NEAR(projected_area, 36, 1e-6) << size;
        std::size_t repeated = 0, on_the_outline = 0, crossed_once_inside = 0;
        for (const auto& [edge, uses] : directed_edges) {
            repeated += uses != 1 ? 1 : 0;
            if (directed_edges.count({edge.second, edge.first}) == 0) {
                const Point& from = mesh.vertices[edge.first];
                const Point& to = mesh.vertices[edge.second];
                const bool along_outline =
                    (std::fabs(from[0]) == 3 && to[0] == from[0]) || (std::fabs(from[2]) == 3 && to[2] == from[2]);
                ++(along_outline ? on_the_outline : crossed_once_inside);
            }
        }
        EXPECT_EQ(repeated, 0u) << size;
        EXPECT_EQ(crossed_once_inside, 0u) << size;
        EXPECT_EQ(on_the_outline, 4 * quads_per_side) << size;
        for (const Point& vertex : mesh.vertices) {
            ASSERT_GT(vertex[1], 0) << size;
        }
    }
}

// Midpoint displacement makes a mountain, not a plain: from its outline at the foot, 0.05 above the floor, it
// rises to 2 at the square's centre (the first midpoint, which no later level moves), its heights varied at
// every scale but never above 2 + 0.6·(1 + 1/2 + 1/4 + …) = 3.2; another seed draws another mountain.
TEST_F(GenerateTest, MountRisesFromItsOutlineToASummitOverTheMiddle) {
    std::vector<std::vector<Point>> mountains;
    for (std::uint64_t seed : {1, 2, 3}) {
        Mesh mesh = read_mesh(generate("mount", 30000, seed).text);
        double highest = 0, outline_highest = 0, centre_height = 0;
        std::vector<double> heights;
        for (const Point& vertex : mesh.vertices) {
            highest = std::max(highest, vertex[1]);
            heights.push_back(vertex[1]);
            if (std::fabs(vertex[0]) == 3 || std::fabs(vertex[2]) == 3) {
                outline_highest = std::max(outline_highest, vertex[1]);
            }
            if (vertex[0] == 0 && vertex[2] == 0) {
                centre_height = vertex[1];
            }
        }
        EXPECT_EQ(outline_highest, 0.05) << seed;
        EXPECT_EQ(centre_height, 2) << seed;
        EXPECT_LT(highest, 3.2) << seed;
        std::sort(heights.begin(), heights.end());
        const auto distinct = std::unique(heights.begin(), heights.end()) - heights.begin();
        EXPECT_GT(distinct, static_cast<std::ptrdiff_t>(mesh.vertices.size() / 2)) << seed;
        mountains.push_back(mesh.vertices);
    }
    EXPECT_NE(mountains[0], mountains[1]);
    EXPECT_NE(mountains[1], mountains[2]);
}

// SPD's pyramid of four glass spheres: three touching around an axis and one resting on them, every one above
// the mountain (higher than any vertex within its radius and a grid step, which bounds the triangles there).
TEST_F(GenerateTest, MountsGlassSpheresAreAPyramidClearOfTheMountain) {
    for (int size : {8, 1000, 30000}) {
        const std::string text = generate("mount", size).text;
        const nlohmann::json scene = nlohmann::json::parse(text);
        Mesh mesh = read_mesh(text);
        const double cell = 6 / std::sqrt(mesh.triangles.size() / 2.0);
        std::vector<std::pair<Point, double>> spheres;
        for (const nlohmann::json& object : scene.at("objects")) {
            if (object.at("type") == "sphere") {
                spheres.emplace_back(object.at("center").get<Point>(), object.at("radius").get<double>());
                const nlohmann::json& material = scene.at("materials").at(object.at("material").get<std::string>());
                EXPECT_GT(material.at("transmission").get<double>(), 0.5) << size;
                EXPECT_EQ(material.at("ior").get<double>(), 1.5) << size;
            }
        }
        ASSERT_EQ(spheres.size(), 4u) << size;
        for (std::size_t i = 0; i < spheres.size(); ++i) {
            const auto& [center, radius] = spheres[i];
            for (std::size_t j = i + 1; j < spheres.size(); ++j) {
                const Point between = minus(spheres[j].first, center);
                EXPECT_NEAR(std::sqrt(dot(between, between)), 2 * radius, 2e-3) << size << ": " << i << ", " << j;
            }
            for (const Point& vertex : mesh.vertices) {
                if (std::fabs(vertex[0] - center[0]) <= radius + cell &&
                    std::fabs(vertex[2] - center[2]) <= radius + cell) {
                    ASSERT_LT(vertex[1], center[1] - radius) << size << ": sphere " << i;
                }
            }
        }
        EXPECT_GT(spheres[3].first[1], spheres[0].first[1] + spheres[0].second) << "the fourth rests on the three";
    }
}

// The outlines of one face: the edges of the face's triangles that no other of them shares, chained.
std::vector<std::vector<std::size_t>> outlines(const std::vector<Triangle>& face) {
    std::map<std::pair<std::size_t, std::size_t>, int> directed_edges;
    for (const auto& [a, b, c] : face) {
        for (auto edge : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
            ++directed_edges[edge];
        }
    }
    std::map<std::size_t, std::size_t> next;
    for (const auto& [edge, uses] : directed_edges) {
        if (directed_edges.count({edge.second, edge.first}) == 0) {
            EXPECT_EQ(next.count(edge.first), 0u) << "two outline edges leave vertex " << edge.first;
            next[edge.first] = edge.second;
        }
    }
    std::vector<std::vector<std::size_t>> loops;
    while (!next.empty()) {
        std::vector<std::size_t> loop = {next.begin()->first};
        for (std::size_t at = next.begin()->second; at != loop.front(); at = next.at(at)) {
            loop.push_back(at);
        }
        for (std::size_t corner : loop) {
            next.erase(corner);
        }
        loops.push_back(loop);
    }
    return loops;
}

// Each gear's top and bottom are one concave polygon of 96 corners (24 teeth, the two corners at each tooth's
// root reflex) cut into 94 triangles, all facing the polygon's way (up for the top, down for the bottom), whose
// areas add up to the polygon's: they cover it once, with no overlap and no gap.
TEST_F(GenerateTest, GearFacesAreConcavePolygonsTiledByTrianglesFacingTheirWay) {
    for (int size : {1, 1000, 20000}) {
        Mesh mesh = read_mesh(generate("gears", size).text);
        double top = mesh.vertices.front()[1], bottom = top;
        for (const Point& vertex : mesh.vertices) {
            top = std::max(top, vertex[1]);
            bottom = std::min(bottom, vertex[1]);
        }
        const std::size_t gears = mesh.triangles.size() / 380;
        for (double face_height : {top, bottom}) {
            SCOPED_TRACE(face_height == top ? "top" : "bottom");
            const double up = face_height == top ? 1 : -1;  // the side the face's front must face
            std::vector<Triangle> face;
            std::map<std::size_t, double> triangle_area_at_corner;  // each triangle's area, at its first corner
            for (const Triangle& triangle : mesh.triangles) {
                const auto& [a, b, c] = triangle;
                if (mesh.vertices[a][1] == face_height && mesh.vertices[b][1] == face_height &&
                    mesh.vertices[c][1] == face_height) {
                    face.push_back(triangle);
                    Point normal =
                        cross(minus(mesh.vertices[b], mesh.vertices[a]), minus(mesh.vertices[c], mesh.vertices[a]));
                    ASSERT_GT(up * normal[1], 0) << size;
                    triangle_area_at_corner[a] += up * normal[1] / 2;
                }
            }
            EXPECT_EQ(face.size(), 94 * gears) << size;
            const std::vector<std::vector<std::size_t>> loops = outlines(face);
            ASSERT_EQ(loops.size(), gears) << size;
            for (const std::vector<std::size_t>& loop : loops) {
                ASSERT_EQ(loop.size(), 96u) << size;
                double polygon_area = 0, triangles_area = 0;
                int reflex = 0;
                for (std::size_t i = 0; i < loop.size(); ++i) {
                    const Point& previous = mesh.vertices[loop[(i + loop.size() - 1) % loop.size()]];
                    const Point& corner = mesh.vertices[loop[i]];
                    const Point& next = mesh.vertices[loop[(i + 1) % loop.size()]];
                    polygon_area += up * cross(corner, next)[1] / 2;
                    reflex += up * cross(minus(corner, previous), minus(next, corner))[1] < 0 ? 1 : 0;
                    triangles_area += triangle_area_at_corner[loop[i]];
                }
                EXPECT_EQ(reflex, 48) << size;
                EXPECT_GT(polygon_area, 0) << size;
                EXPECT_NEAR(triangles_area, polygon_area, 1e-9 * polygon_area) << size;
            }
        }
    }
}

// Meshing: each gear's teeth reach past its neighbours' tips into their gaps (some of its corners lie within
// their tip circles), yet no outline edge of one crosses another's, seen from above.
TEST_F(GenerateTest, NeighbouringGearsMeshWithoutOverlapping) {
    for (int size : {1000, 4000}) {
        Mesh mesh = read_mesh(generate("gears", size).text);
        double top = 0;
        for (const Point& vertex : mesh.vertices) {
            top = std::max(top, vertex[1]);
        }
        std::vector<Triangle> top_face;
        for (const Triangle& triangle : mesh.triangles) {
            if (mesh.vertices[triangle[0]][1] == top && mesh.vertices[triangle[1]][1] == top &&
                mesh.vertices[triangle[2]][1] == top) {
                top_face.push_back(triangle);
            }
        }
        struct Gear {
            std::vector<Point> outline;
            Point centre;
            double tip_radius;
        };
        std::vector<Gear> gears;
        for (const std::vector<std::size_t>& loop : outlines(top_face)) {
            Gear gear{{}, {0, 0, 0}, 0};
            for (std::size_t corner : loop) {
                gear.outline.push_back(mesh.vertices[corner]);
                for (int axis : {0, 2}) {
                    gear.centre[axis] += mesh.vertices[corner][axis] / static_cast<double>(loop.size());
                }
            }
            for (const Point& corner : gear.outline) {
                const Point out = minus(corner, gear.centre);
                gear.tip_radius = std::max(gear.tip_radius, std::hypot(out[0], out[2]));
            }
            gears.push_back(gear);
        }
        // The sign of the turn a → b → c seen from above.
        auto turn = [](const Point& a, const Point& b, const Point& c) { return cross(minus(b, a), minus(c, a))[1]; };
        int neighbour_pairs = 0;
        for (const Gear& one : gears) {
            for (const Gear& other : gears) {
                const Point between = minus(other.centre, one.centre);
                const double distance = std::hypot(between[0], between[2]);
                if (&one == &other || distance > one.tip_radius + other.tip_radius) {
                    continue;
                }
                ++neighbour_pairs;
                int reaching_in = 0;
                for (const Point& corner : one.outline) {
                    const Point out = minus(corner, other.centre);
                    reaching_in += std::hypot(out[0], out[2]) < other.tip_radius ? 1 : 0;
                }
                EXPECT_GT(reaching_in, 0) << size;
                for (std::size_t i = 0; i < one.outline.size(); ++i) {
                    const Point& a = one.outline[i];
                    const Point& b = one.outline[(i + 1) % one.outline.size()];
                    for (std::size_t j = 0; j < other.outline.size(); ++j) {
                        const Point& c = other.outline[j];
                        const Point& d = other.outline[(j + 1) % other.outline.size()];
                        const bool crossing = turn(a, b, c) * turn(a, b, d) <= 0 && turn(c, d, a) * turn(c, d, b) <= 0;
                        ASSERT_FALSE(crossing) << size << ": edges " << i << " and " << j;
                    }
                }
            }
        }
        // Each of the g × g gears and its neighbours along the rows and columns, counted from both sides.
        const int per_side = static_cast<int>(std::lround(std::sqrt(static_cast<double>(gears.size()))));
        EXPECT_EQ(neighbour_pairs, 4 * per_side * (per_side - 1)) << size;
    }
}

// FNV-1a, written out so that the recorded values below mean the same on every platform.
std::uint64_t fnv1a(const std::string& text) {
    std::uint64_t hash = 0xcbf29ce484222325ULL;
    for (unsigned char byte : text) {
        hash = (hash ^ byte) * 0x100000001b3ULL;
    }
    return hash;
}

// The same request gives the same file on any x86-64 machine, compiler and standard library: these
// are the bytes of g++ 12 and libstdc++ on Debian 12. A deliberate change to a family changes them:
// update the values with the change, and say so in its commit.
TEST_F(GenerateTest, GeneratedFilesAreTheRecordedBytes) {
    const std::vector<std::pair<std::string, std::uint64_t>> recorded = {
        {"fractal", 0xd8588e66c5435676ULL},
        {"field", 0x1c91f0708718db69ULL},
        {"lattice", 0x297d443de9126fe9ULL},
        {"csg", 0x8522c9de8f2ae505ULL},
        // The mesh families: the sphere's, the torus's and the sombrero's vertices hold sine_cosine's bits.
        {"sphere-mesh", 0xd113f2e41aba729cULL},
        {"torus-mesh", 0x3e6ece61b6358ffdULL},
        {"tetra", 0xa70ec72b63980dfaULL},
        {"sombrero", 0x5506656a6874c8e9ULL},
        {"triangle-soup", 0x2c327230d7695e39ULL},
        // mount's heights are sums and halves of splitmix64's doubles; gears' faces are the ear clipper's.
        {"mount", 0xa2d087384e902c6eULL},
        {"gears", 0x5fd2f4fc20dbb6b0ULL},
        // forest's tree holds sine_cosine's bits, its placements splitmix64's doubles.
        {"forest", 0x542f96d34a17bc4cULL},
    };
    for (const auto& [family, hash] : recorded) {
        EXPECT_EQ(fnv1a(generate(family, 300, 1).text), hash) << family;
    }
}

TEST_F(GenerateTest, DifferentSeedsGiveDifferentFields) {
    for (const char* family : {"field", "csg", "triangle-soup", "mount"}) {
        Generated one = generate(family, 400, 1);
        Generated two = generate(family, 400, 2);
        EXPECT_NE(one.text, two.text) << family;
        EXPECT_EQ(one.scene.primitives, two.scene.primitives) << family;
        EXPECT_EQ(one.scene.triangles, two.scene.triangles) << family;
    }
}

TEST_F(GenerateTest, NumbersAreWrittenOnTheGridInTheirShortestForm) {
    std::string text;
    twinray::cli::SceneTextWriter out({[&](std::string_view piece) { text.append(piece); }, {}}, 3);
    twinray::scene::Scene header;
    header.camera = {{0, 1, 5}, {0, 0, 0}, {0, 1, 0}, 50};
    out.begin(header);
    out.sphere({0.1, -0.00004, 2.0000004}, 1.0 / 3);
    out.box({-1e-9, 1234.5678, -7}, {1, 1234.6, 0.25});
    out.end();
    EXPECT_NE(text.find(R"({"type": "sphere", "center": [0.1, 0, 2], "radius": 0.333})"), std::string::npos) << text;
    EXPECT_NE(text.find(R"({"type": "box", "min": [0, 1234.568, -7], "max": [1, 1234.6, 0.25]})"), std::string::npos)
        << text;
    EXPECT_EQ(twinray::scene::parse_scene(text, "<written>").leaf_paths.size(), 2u);
}

TEST_F(GenerateTest, GenerateRefusesUnknownFamilyWithExitCode) {
    CommandResult result = run_twinray("generate sphereflake -o " + path("s.json"));
    EXPECT_EQ(result.exit_status, twinray::cli::exit_usage) << result.output;
    for (const std::string& family : all_families()) {
        EXPECT_NE(result.output.find(family), std::string::npos) << "the message lists the families:\n"
                                                                 << result.output;
    }
    EXPECT_TRUE(files().empty());
}

// Each family's description starts a line of the help, "  forest  one tree ...", and the family option lists them all.
TEST_F(GenerateTest, GenerateHelpDescribesEveryFamilyOnALineOfItsOwn) {
    CommandResult result = run_twinray("generate --help");
    ASSERT_EQ(result.exit_status, 0) << result.output;
    const std::vector<std::string> families = all_families();
    std::string listed;
    for (std::size_t i = 0; i < families.size(); ++i) {
        listed += (i == 0 ? "" : i + 1 == families.size() ? " or " : ", ") + families[i];
        EXPECT_NE(result.output.find("\n  " + families[i] + "  "), std::string::npos)
            << families[i] << " is not described in:\n"
            << result.output;
    }
    EXPECT_NE(result.output.find(listed + "\n"), std::string::npos) << "no \"" << listed << "\" in:\n" << result.output;
}

TEST_F(GenerateTest, GenerateRefusesSizesOutsideOneToTheMaximum) {
    for (const char* size : {"0", "-3", "1000001", "many"}) {
        CommandResult result = run_twinray(std::string("generate field --size ") + size + " -o " + path("s.json"));
        EXPECT_EQ(result.exit_status, twinray::cli::exit_usage) << size << ": " << result.output;
        EXPECT_NE(result.output.find("--size"), std::string::npos) << result.output;
    }
    EXPECT_TRUE(files().empty());
}

TEST_F(GenerateTest, GenerateRefusesSeedsThatAreNotWhole64BitNumbers) {
    for (const char* seed : {"-1", "18446744073709551616", "1.5", "x"}) {
        CommandResult result = run_twinray(std::string("generate field --seed ") + seed + " -o " + path("s.json"));
        EXPECT_EQ(result.exit_status, twinray::cli::exit_usage) << seed << ": " << result.output;
        EXPECT_NE(result.output.find("0..18446744073709551615"), std::string::npos) << result.output;
    }
    EXPECT_TRUE(files().empty());
    CommandResult largest = run_twinray("generate field --seed 18446744073709551615 --size 10 -o " + path("s.json"));
    EXPECT_EQ(largest.exit_status, twinray::cli::exit_success) << largest.output;
}

// --mesh-file obj and ply: the scene names a file beside it, and the loader reads from it the very doubles,
// triangles and normals the inline scene holds, so the renders are the same bits.
TEST_P(MeshFamily, AMeshFileHoldsTheSameVerticesTrianglesAndNormalsAsTheInlineMesh) {
    CommandResult inline_result =
        run_twinray("generate " + GetParam() + " --size 2000 --seed 3 -o " + path("inline.json"));
    ASSERT_EQ(inline_result.exit_status, 0) << inline_result.output;
    const twinray::scene::Scene inline_scene = twinray::scene::load_scene(path("inline.json"));
    ASSERT_EQ(inline_scene.meshes.size(), 1u);
    const twinray::scene::MeshData& expected = *inline_scene.meshes[0].data;
    for (const std::string format : {"obj", "ply"}) {
        SCOPED_TRACE(format);
        CommandResult result = run_twinray("generate " + GetParam() + " --size 2000 --seed 3 --mesh-file " + format +
                                           " -o " + path(format + "_scene.json"));
        ASSERT_EQ(result.exit_status, 0) << result.output;
        EXPECT_NE(result.output.find("its mesh to " + path(format + "_scene." + format)), std::string::npos)
            << result.output;
        EXPECT_NE(read_bytes(path(format + "_scene.json")).find("\"file\": \"" + format + "_scene." + format + "\""),
                  std::string::npos);
        const twinray::scene::Scene scene = twinray::scene::load_scene(path(format + "_scene.json"));
        ASSERT_EQ(scene.meshes.size(), 1u);
        const twinray::scene::MeshData& read = *scene.meshes[0].data;
        EXPECT_EQ(read.triangles, expected.triangles);
        EXPECT_EQ(read.smooth, expected.smooth);
        ASSERT_EQ(read.vertices.size(), expected.vertices.size());
        for (std::size_t i = 0; i < read.vertices.size(); ++i) {
            ASSERT_EQ(read.vertices[i], expected.vertices[i]) << "vertex " << i;
        }
        ASSERT_EQ(read.normals.size(), expected.normals.size());
        for (std::size_t i = 0; i < read.normals.size(); ++i) {
            ASSERT_EQ(read.normals[i], expected.normals[i]) << "normal " << i;
        }
        EXPECT_EQ(read.degenerate, expected.degenerate);
    }
}

TEST_F(GenerateTest, MeshFileIsRefusedForAFamilyWithoutAMeshAndWhereItWouldBeTheSceneItself) {
    CommandResult no_mesh = run_twinray("generate field --mesh-file obj -o " + path("s.json"));
    EXPECT_EQ(no_mesh.exit_status, twinray::cli::exit_usage) << no_mesh.output;
    EXPECT_NE(no_mesh.output.find("--mesh-file applies to the mesh families"), std::string::npos) << no_mesh.output;
    CommandResult same_file = run_twinray("generate tetra --mesh-file obj -o " + path("s.obj"));
    EXPECT_EQ(same_file.exit_status, twinray::cli::exit_usage) << same_file.output;
    CommandResult unknown = run_twinray("generate tetra --mesh-file stl -o " + path("s.json"));
    EXPECT_EQ(unknown.exit_status, twinray::cli::exit_usage) << unknown.output;
    EXPECT_TRUE(files().empty());
}

// A full disk while the mesh file is written: status 3, neither file nor a temporary left.
TEST_F(GenerateTest, MeshFileFailingPartWayLeavesNeitherFile) {
    RunningTwinray generate_process(
        {"generate", "sphere-mesh", "--size", "200000", "--mesh-file", "obj", "-o", path("s.json")},
        {.file_size_bytes = 64 * 1024});
    CommandResult result = generate_process.wait();
    EXPECT_EQ(result.exit_status, twinray::cli::exit_output_error) << result.output;
    EXPECT_NE(result.output.find("s.obj"), std::string::npos) << result.output;
    EXPECT_TRUE(files().empty());
}

TEST_F(GenerateTest, GenerateIntoAMissingFolderFailsWithStatusThree) {
    CommandResult result = run_twinray("generate lattice -o " + path("missing/s.json"));
    EXPECT_EQ(result.exit_status, twinray::cli::exit_output_error) << result.output;
    EXPECT_NE(result.output.find("does not exist"), std::string::npos) << result.output;
}

// A full disk part-way through (RLIMIT_FSIZE, as failure_test's DiskFullTest): status 3, the old file
// kept, no temporary left.
TEST_F(GenerateTest, GenerateFailingPartWayKeepsTheOldFileAndLeavesNoTemporary) {
    std::ofstream(path("s.json")) << "the old scene";
    RunningTwinray generate_process({"generate", "field", "--size", "100000", "-o", path("s.json")},
                                    {.file_size_bytes = 64 * 1024});
    CommandResult result = generate_process.wait();
    EXPECT_EQ(result.exit_status, twinray::cli::exit_output_error) << result.output;
    EXPECT_NE(result.output.find("File too large"), std::string::npos) << result.output;
    EXPECT_EQ(read_bytes(path("s.json")), "the old scene");
    EXPECT_EQ(files(), std::vector<std::string>{"s.json"});
}

// The largest size is streamed, never held: a million primitives (about 100 MB of text) in the
// memory of a small one.
// A mesh's lists too are streamed, not held whole.
TEST_F(GenerateTest, GenerateWritesTheLargestSizeInLittleMemory) {
#ifdef TWINRAY_SANITIZED_BUILD
    GTEST_SKIP() << "a sanitizer's shadow memory is not the program's: the budget holds for uninstrumented builds";
#endif
    const std::vector<std::pair<std::string, std::string>> largest = {
        {"csg", "wrote 1000000 primitives"},
        {"sphere-mesh", "wrote 2 primitives (sphere-mesh, 998000 triangles"},
    };
    for (const auto& [family, report] : largest) {
        RunningTwinray generate_process(
            {"generate", family, "--size", std::to_string(max_generated_primitives), "-o", path("s.json")});
        CommandResult result = generate_process.wait();
        ASSERT_EQ(result.exit_status, twinray::cli::exit_success) << result.output;
        EXPECT_NE(result.output.find(report), std::string::npos) << result.output;
        EXPECT_GT(fs::file_size(path("s.json")), 50'000'000u) << family;
        EXPECT_LT(generate_process.peak_memory_bytes(), 32L << 20) << family;
    }
}

}  // namespace
