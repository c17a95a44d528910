// The scene loader against the contract (docs/scene-format.md): every refusal rule has a malformed file that breaks
// it and nothing else, every shipped scene loads, and the values the loader fills in (defaults, the
// normalised plane normal, material inheritance, leaf numbering, the image size) are the documented ones.
#include "scene/loader.h"
#include "scene/scene_stream.h"
#include "scene/sphere_field.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace twinray::scene {
namespace {

const std::filesystem::path source_dir = TWINRAY_SOURCE_DIR;
const std::filesystem::path malformed_dir = source_dir / "tests" / "data" / "malformed";
const std::filesystem::path scenes_dir = source_dir / "scenes";

std::string repeated(std::string_view text, int count) {
    std::string result;
    for (int i = 0; i < count; ++i) {
        result += text;
    }
    return result;
}

// gtest parameter names allow only letters, digits and underscores.
std::string test_name_from(const std::filesystem::path& file) {
    std::string name = file.stem().string();
    std::replace_if(
        name.begin(), name.end(), [](unsigned char c) { return !std::isalnum(c); }, '_');
    return name;
}

// ---------------------------------------------------------------------------------------------------
// Refusals: one malformed file per rule.

struct Malformed {
    std::string file;
    std::string location;
    std::string problem_fragment;
};

void PrintTo(const Malformed& malformed, std::ostream* out) {
    *out << malformed.file;
}

const std::vector<Malformed> malformed_scenes = {
    // JSON syntax: the location is where the parser stopped, counted from 1.
    {"syntax_truncated.json", "line 5, column 1", "unexpected end of input"},
    {"syntax_trailing_garbage.json", "line 7, column 1", "expected end of input"},
    {"syntax_single_quotes.json", "line 4, column 7", "invalid literal"},
    {"syntax_comment.json", "line 3, column 3", "invalid literal"},
    {"syntax_empty.json", "line 1, column 1", "unexpected end of input"},
    {"syntax_not_utf8.json", "line 3, column 23", "ill-formed UTF-8"},
    // Numbers are finite: JSON cannot spell NaN, and 1e999 overflows a double.
    {"syntax_nan.json", "line 4, column 56", "invalid literal"},
    {"syntax_number_overflow.json", "line 4, column 60", "numbers must be finite"},
    {"duplicate_key.json", "objects[0].radius", "duplicate key \"radius\""},
    {"duplicate_material_name.json", "materials.glass", "duplicate key \"glass\""},
    {"json_nested_too_deep.json", "background" + repeated("[0]", 199), "nested deeper than 200 levels"},
    {"root_not_object.json", "(root)", "expected an object, got an array of 1 element"},
    // The top level.
    {"unknown_top_level_key.json", "backgroud", "unknown key \"backgroud\"; allowed keys for a scene: camera, objects"},
    {"format_wrong_version.json", "format", "must be \"twinray-scene/1\", got \"twinray-scene/2\""},
    {"camera_missing.json", "camera", "missing required key \"camera\""},
    {"objects_missing.json", "objects", "missing required key \"objects\""},
    {"objects_not_array.json", "objects", "expected an array of objects, got an object"},
    // image: integers 1..16384; 640.5 is not an integer, true is not a number.
    {"image_not_object.json", "image", "expected an object"},
    {"image_unknown_key.json", "image.widht", "unknown key \"widht\"; allowed keys for image: width, height"},
    {"image_width_zero.json", "image.width", "must be an integer from 1 to 16384, got 0"},
    {"image_height_too_large.json", "image.height", "must be an integer from 1 to 16384, got 16385"},
    {"image_width_fractional.json", "image.width", "must be an integer from 1 to 16384, got 640.5"},
    {"image_height_boolean.json", "image.height", "expected a number, got true"},
    // camera.
    {"camera_unknown_key.json", "camera.fov", "allowed keys for the camera: eye, look_at, up, fov_deg"},
    {"camera_missing_eye.json", "camera.eye", "missing required key \"eye\""},
    {"camera_missing_look_at.json", "camera.look_at", "missing required key \"look_at\""},
    {"camera_eye_equals_look_at.json", "camera.look_at", "must differ from eye"},
    {"camera_view_direction_overflows.json", "camera.look_at", "look_at - eye overflows a double"},
    {"camera_up_parallel.json", "camera.up", "is parallel to the view direction"},
    {"camera_default_up_parallel.json", "camera.up", "the default up [0, 1, 0] is parallel"},
    {"camera_fov_zero.json", "camera.fov_deg", "must be > 0 and < 180, got 0"},
    {"camera_fov_180.json", "camera.fov_deg", "must be > 0 and < 180, got 180"},
    {"camera_eye_two_numbers.json", "camera.eye", "expected an array of 3 numbers, got 2 elements"},
    {"camera_look_at_string_component.json", "camera.look_at[1]", "expected a number, got \"1\""},
    // Scene-wide values.
    {"background_negative_component.json", "background[2]", "must be >= 0, got -0.5"},
    {"ambient_light_not_array.json", "ambient_light", "expected an array of 3 numbers, got 1"},
    {"max_depth_zero.json", "max_depth", "must be an integer from 1 to 64, got 0"},
    {"max_depth_too_large.json", "max_depth", "must be an integer from 1 to 64, got 65"},
    {"max_depth_fractional.json", "max_depth", "must be an integer from 1 to 64, got 2.5"},
    {"max_depth_string.json", "max_depth", "expected a number, got \"5\""},
    {"min_weight_negative.json", "min_weight", "must be >= 0, got -0.01"},
    {"min_weight_string.json", "min_weight", "expected a number, got \"0.01\""},
    // materials.
    {"materials_not_object.json", "materials", "expected an object"},
    {"material_not_object.json", "materials.glass", "expected an object, got 1.5"},
    {"material_unknown_key.json", "materials.glass.refraction",
     "unknown key \"refraction\"; allowed keys for a material: color, ambient, diffuse, phong, phong_size, "
     "reflection, transmission, ior"},
    {"material_ambient_negative.json", "materials.matte.ambient", "must be >= 0, got -0.25"},
    {"material_diffuse_negative.json", "materials.matte.diffuse", "must be >= 0, got -0.25"},
    {"material_phong_negative.json", "materials.matte.phong", "must be >= 0, got -0.25"},
    {"material_reflection_negative.json", "materials.matte.reflection", "must be >= 0, got -0.25"},
    {"material_transmission_negative.json", "materials.matte.transmission", "must be >= 0, got -0.25"},
    {"material_phong_size_zero.json", "materials.shiny.phong_size", "must be > 0, got 0"},
    {"material_ior_negative.json", "materials.glass.ior", "must be > 0, got -1.5"},
    {"material_color_negative.json", "materials.red.color[1]", "must be >= 0, got -0.1"},
    {"material_color_two_numbers.json", "materials.red.color", "expected an array of 3 numbers, got 2 elements"},
    // lights.
    {"lights_not_array.json", "lights", "expected an array of lights, got an object"},
    {"light_not_object.json", "lights[0]", "expected an object, got an array of 3 elements"},
    {"light_missing_position.json", "lights[1].position", "missing required key \"position\""},
    {"light_unknown_key.json", "lights[0].intensity", "allowed keys for a light: position, color"},
    {"light_color_negative.json", "lights[0].color[0]", "must be >= 0, got -1"},
    {"light_position_four_numbers.json", "lights[0].position", "expected an array of 3 numbers, got 4 elements"},
    // objects: a type, exactly its own keys, valid values.
    {"object_not_object.json", "objects[1]", "expected an object, got \"sphere\""},
    {"object_missing_type.json", "objects[0].type",
     "missing required key \"type\"; allowed types: plane, sphere, cylinder, box, union, intersection, difference, "
     "mesh"},
    {"object_unknown_type.json", "objects[0].type", "unknown object type \"torus\"; allowed types: plane"},
    {"object_type_not_string.json", "objects[0].type", "expected a string, got 2"},
    {"sphere_unknown_key.json", "objects[0].radus",
     "unknown key \"radus\"; allowed keys for a sphere: type, center, radius, material"},
    {"sphere_with_plane_key.json", "objects[0].normal", "unknown key \"normal\"; allowed keys for a sphere"},
    {"sphere_missing_radius.json", "objects[2].radius",
     "missing required key \"radius\"; required keys for a sphere: type, center, radius"},
    {"sphere_radius_negative.json", "objects[0].radius", "must be > 0, got -1"},
    {"sphere_radius_zero.json", "objects[0].radius", "must be > 0, got 0"},
    {"sphere_center_not_array.json", "objects[0].center", "expected an array of 3 numbers, got \"origin\""},
    {"plane_normal_zero.json", "objects[0].normal", "must be non-zero"},
    {"plane_missing_offset.json", "objects[0].offset", "missing required key \"offset\""},
    {"cylinder_base_equals_cap.json", "objects[0].cap", "must differ from base, both are [1, 0, 2]"},
    {"cylinder_radius_zero.json", "objects[0].radius", "must be > 0, got 0"},
    {"cylinder_missing_cap.json", "objects[0].cap", "missing required key \"cap\""},
    {"box_min_equals_max_on_y.json", "objects[0].max", "on y min is 1 and max is 1"},
    {"box_min_above_max_on_z.json", "objects[0].max", "on z min is 3 and max is 2"},
    // CSG: at least two children, nesting (with paths through it) up to 64 levels.
    {"csg_missing_children.json", "objects[0].children", "missing required key \"children\""},
    {"csg_one_child.json", "objects[0].children", "expected at least 2 objects, got 1"},
    {"csg_too_many_primitives.json", "objects[1]", "at most 64 primitives"},
    {"csg_children_not_array.json", "objects[0].children", "expected an array of objects, got an object"},
    {"csg_unknown_key_on_node.json", "objects[0].radius",
     "unknown key \"radius\"; allowed keys for a difference: type, children, material"},
    {"csg_nested_bad_radius.json", "objects[1].children[1].children[0].radius", "must be > 0, got -2"},
    {"csg_nested_unknown_key.json", "objects[0].children[1].colour",
     "allowed keys for a box: type, min, max, material"},
    {"csg_nested_too_deep.json", "objects[0]" + repeated(".children[0]", 64), "nested deeper than 64 levels"},
    // Material names must exist in materials.
    {"material_name_unknown.json", "objects[1].material", "unknown material \"glas\"; materials defined: floor, glass"},
    {"material_name_unknown_nested.json", "objects[0].children[1].material", "unknown material \"chrome\""},
    {"material_name_without_materials.json", "objects[0].material", "the scene defines no materials"},
    {"material_name_not_string.json", "objects[0].material", "expected a string, got 1"},
    // Meshes: indices of existing vertices, three a triangle, at least one triangle, one non-zero normal per
    // vertex, never a CSG child.
    {"mesh_index_out_of_range.json", "objects[1].triangles[0][2]",
     "must be a vertex index, an integer from 0 to 2 (the mesh has 3 vertices), got 3"},
    {"mesh_index_not_integer.json", "objects[1].triangles[0][1]", "must be a vertex index"},
    {"mesh_index_negative.json", "objects[1].triangles[0][1]", "got -1"},
    {"mesh_triangle_two_indices.json", "objects[1].triangles[0]", "expected 3 vertex indices, got 2"},
    {"mesh_no_triangles.json", "objects[1].triangles", "a mesh needs at least one triangle, got none"},
    {"mesh_missing_vertices.json", "objects[1].vertices",
     "missing required key \"vertices\"; a mesh gives \"vertices\" and \"triangles\", or a \"file\""},
    {"mesh_vertex_two_numbers.json", "objects[1].vertices[1]", "expected an array of 3 numbers"},
    {"mesh_normals_count.json", "objects[1].normals", "expected one normal per vertex (3), got 1"},
    {"mesh_normal_zero.json", "objects[1].normals[1]", "a normal must be non-zero"},
    {"mesh_smooth_not_boolean.json", "objects[1].smooth", "expected true or false, got 1"},
    {"mesh_unknown_key.json", "objects[1].faces",
     "unknown key \"faces\"; allowed keys for a mesh: type, vertices, triangles, normals, file, smooth, material, "
     "transform"},
    {"mesh_as_csg_child.json", "objects[1].children[1]", "a mesh may not be a CSG child"},
    // A mesh file, beside the scene file: readable, alone, well-formed (its own location kept in the problem).
    {"mesh_file_missing.json", "objects[1].file", "no_such_model.obj"},
    {"mesh_file_and_vertices.json", "objects[1].vertices", "a mesh gives either a \"file\" or its vertices"},
    {"mesh_file_malformed.json", "objects[1].file", "out_of_range.obj: line"},
    // Transforms: a list of one-key steps, each well-formed, their composition finite and well conditioned (also
    // with the CSG ancestors' transforms), never singular.
    {"transform_not_array.json", "objects[0].transform", "expected a list of transform steps"},
    {"transform_step_two_keys.json", "objects[0].transform[0]", "this one holds translate, scale"},
    {"transform_step_empty.json", "objects[0].transform[0]", "got an empty object"},
    {"transform_step_unknown_key.json", "objects[0].transform[0].rotation",
     "unknown key \"rotation\"; allowed keys for a transform step: translate, scale, rotate, matrix"},
    {"transform_scale_zero.json", "objects[0].transform[0].scale[1]", "a scale factor must be non-zero"},
    {"transform_scale_two_factors.json", "objects[0].transform[0].scale", "expected a number or 3 factors"},
    {"transform_rotate_zero_axis.json", "objects[0].transform[0].rotate.axis", "a rotation's axis must be non-zero"},
    {"transform_rotate_axis_without_angle.json", "objects[0].transform[0].rotate.deg", "missing required key \"deg\""},
    {"transform_matrix_singular.json", "objects[0].transform[0].matrix", "the matrix is singular"},
    {"transform_matrix_row_of_three.json", "objects[0].transform[0].matrix[1]", "expected 4 numbers, got 3"},
    {"transform_matrix_two_rows.json", "objects[0].transform[0].matrix", "expected 3 rows of 4 numbers"},
    {"transform_badly_conditioned.json", "objects[0].transform",
     "too badly conditioned: its condition number ‖L‖·‖L⁻¹‖ (Frobenius) is 1414213.5623748628, the limit is 1e+05"},
    {"transform_overflows.json", "objects[0].transform", "overflow double"},
    {"transform_csg_composed_badly_conditioned.json", "objects[0].children[0].transform", "too badly conditioned"},
    {"transform_mesh_singular.json", "objects[0].transform[0].matrix", "the matrix is singular"},
    // Shapes and instances.
    {"shapes_not_object.json", "shapes", "expected an object, got an array"},
    {"instance_unknown_shape.json", "objects[0].shape", "unknown shape \"bal\"; shapes declared: ball"},
    {"instance_without_shapes.json", "objects[0].shape", "no \"shapes\" were read before \"objects\""},
    {"instance_shapes_after_objects.json", "objects[0].shape", "a scene declares its shapes before its objects"},
    {"instance_shape_not_string.json", "objects[0].shape", "expected a string"},
    {"instance_in_shape.json", "shapes.pair.children[0]", "a shape may not hold an instance"},
    {"instance_as_shape.json", "shapes.again", "a shape may not be an instance"},
    {"instance_of_mesh_in_csg.json", "objects[0].children[0]", "may not be a CSG child"},
    {"instance_badly_conditioned.json", "objects[0].transform", "too badly conditioned"},
    {"instance_shape_bad_primitive.json", "shapes.ball.radius", "must be > 0"},
};

class MalformedScene : public ::testing::TestWithParam<Malformed> {};

TEST_P(MalformedScene, IsRefusedWithItsPathAndWhatIsAllowed) {
    const Malformed& expected = GetParam();
    const std::filesystem::path file = malformed_dir / expected.file;
    try {
        load_scene(file);
        ADD_FAILURE() << file << " was accepted";
    } catch (const SceneError& error) {
        EXPECT_EQ(error.location(), expected.location) << error.what();
        EXPECT_NE(error.problem().find(expected.problem_fragment), std::string::npos)
            << "expected the problem to contain: " << expected.problem_fragment << "\nactual message: " << error.what();
        EXPECT_TRUE(std::string_view(error.what()).starts_with(file.string() + ": ")) << error.what();
        EXPECT_EQ(error.file(), file.string());
    }
}

INSTANTIATE_TEST_SUITE_P(OneRuleBrokenPerFile, MalformedScene, ::testing::ValuesIn(malformed_scenes),
                         [](const auto& test) { return test_name_from(test.param.file); });

TEST(MalformedSceneTable, CoversEveryFileInTheMalformedDirectory) {
    std::set<std::string> listed;
    for (const Malformed& malformed : malformed_scenes) {
        listed.insert(malformed.file);
    }
    for (const auto& entry : std::filesystem::directory_iterator(malformed_dir)) {
        EXPECT_TRUE(listed.contains(entry.path().filename().string()))
            << entry.path() << " has no row in malformed_scenes, so nothing checks why it is refused";
    }
    EXPECT_EQ(listed.size(), malformed_scenes.size()) << "a file is listed twice";
}

// ---------------------------------------------------------------------------------------------------
// Every shipped scene loads.

std::vector<std::filesystem::path> shipped_scenes() {
    std::vector<std::filesystem::path> files;
    std::error_code missing_directory;
    for (const auto& entry : std::filesystem::directory_iterator(scenes_dir, missing_directory)) {
        if (entry.path().extension() == ".json") {
            files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

class ShippedScene : public ::testing::TestWithParam<std::filesystem::path> {};

TEST_P(ShippedScene, Loads) {
    try {
        load_scene(GetParam());
    } catch (const SceneError& error) {
        ADD_FAILURE() << error.what();
    }
}

INSTANTIATE_TEST_SUITE_P(ScenesDirectory, ShippedScene, ::testing::ValuesIn(shipped_scenes()),
                         [](const auto& test) { return test_name_from(test.param); });
// An empty directory instantiates nothing; ScenesDirectoryIsNotEmpty below reports that instead.
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(ShippedScene);

TEST(ShippedScenes, ScenesDirectoryIsNotEmpty) {
    EXPECT_FALSE(shipped_scenes().empty())
        << "no scenes/*.json in " << scenes_dir << ": the test that every shipped scene loads has nothing to check";
}

// ---------------------------------------------------------------------------------------------------
// What the loader fills in.

Scene parse(std::string_view text) {
    return parse_scene(text, "<test>");
}

constexpr std::string_view camera_block = R"("camera": { "eye": [0, 1, 5], "look_at": [0, 1, 0] })";

Scene parse_with_camera(std::string_view blocks) {
    return parse("{ " + std::string(camera_block) + ", " + std::string(blocks) + " }");
}

void expect_default_material(const Material& material) {
    EXPECT_EQ(material.color, (Vec3{1, 1, 1}));
    EXPECT_EQ(material.ambient, 0.1);
    EXPECT_EQ(material.diffuse, 0.6);
    EXPECT_EQ(material.phong, 0);
    EXPECT_EQ(material.phong_size, 40);
    EXPECT_EQ(material.reflection, 0);
    EXPECT_EQ(material.transmission, 0);
    EXPECT_EQ(material.ior, 1);
}

TEST(SceneLoader, MinimalSceneGetsEveryDefault) {
    const Scene scene = parse_with_camera(R"("objects": [])");
    EXPECT_EQ(scene.width, 320);
    EXPECT_EQ(scene.height, 240);
    EXPECT_EQ(scene.camera.eye, (Vec3{0, 1, 5}));
    EXPECT_EQ(scene.camera.look_at, (Vec3{0, 1, 0}));
    EXPECT_EQ(scene.camera.up, (Vec3{0, 1, 0}));
    EXPECT_EQ(scene.camera.fov_deg, 50);
    EXPECT_EQ(scene.background, (Vec3{0, 0, 0}));
    EXPECT_EQ(scene.ambient_light, (Vec3{1, 1, 1}));
    EXPECT_EQ(scene.max_depth, 5);
    EXPECT_FALSE(scene.min_weight.has_value());
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.material_names, std::vector<std::string>{"(default)"});
    expect_default_material(scene.materials[0]);
    EXPECT_TRUE(scene.lights.empty());
    EXPECT_TRUE(scene.objects.empty());
    EXPECT_TRUE(scene.leaf_paths.empty());
}

TEST(SceneLoader, OmittedMaterialAndLightKeysTakeTheirDefaults) {
    const Scene scene = parse_with_camera(R"("materials": { "plain": {} },
                                             "lights": [ { "position": [1, 2, 3] } ], "objects": [])");
    ASSERT_EQ(scene.materials.size(), 2u);
    expect_default_material(scene.materials[1]);
    ASSERT_EQ(scene.lights.size(), 1u);
    EXPECT_EQ(scene.lights[0].position, (Vec3{1, 2, 3}));
    EXPECT_EQ(scene.lights[0].color, (Vec3{1, 1, 1}));
}

TEST(SceneLoader, GivenValuesReplaceTheDefaults) {
    const Scene scene = parse(R"({
        "format": "twinray-scene/1",
        "image": { "width": 64, "height": 48 },
        "camera": { "eye": [1, 2, 3], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 30 },
        "background": [0.1, 0.2, 0.3], "ambient_light": [0.5, 0.5, 0.5], "max_depth": 12, "min_weight": 0.004,
        "materials": { "m": { "color": [0.5, 0.25, 0], "ambient": 0.2, "diffuse": 0.7, "phong": 0.3,
                              "phong_size": 20, "reflection": 0.4, "transmission": 0.5, "ior": 1.33 } },
        "lights": [ { "position": [5, 8, -6], "color": [0.5, 1, 2] } ],
        "objects": [] })");
    EXPECT_EQ(scene.width, 64);
    EXPECT_EQ(scene.height, 48);
    EXPECT_EQ(scene.camera.up, (Vec3{0, 0, 1}));
    EXPECT_EQ(scene.camera.fov_deg, 30);
    EXPECT_EQ(scene.background, (Vec3{0.1, 0.2, 0.3}));
    EXPECT_EQ(scene.ambient_light, (Vec3{0.5, 0.5, 0.5}));
    EXPECT_EQ(scene.max_depth, 12);
    EXPECT_EQ(scene.min_weight, 0.004);
    const Material& m = scene.materials.at(1);
    EXPECT_EQ(m.color, (Vec3{0.5, 0.25, 0}));
    EXPECT_EQ(m.ambient, 0.2);
    EXPECT_EQ(m.diffuse, 0.7);
    EXPECT_EQ(m.phong, 0.3);
    EXPECT_EQ(m.phong_size, 20);
    EXPECT_EQ(m.reflection, 0.4);
    EXPECT_EQ(m.transmission, 0.5);
    EXPECT_EQ(m.ior, 1.33);
    EXPECT_EQ(scene.lights.at(0).color, (Vec3{0.5, 1, 2}));
}

TEST(SceneLoader, IntegersWrittenWithAZeroFractionAreAccepted) {
    const Scene scene = parse_with_camera(R"("image": { "width": 640.0, "height": 4.8e2 }, "max_depth": 5.0,
                                             "objects": [])");
    EXPECT_EQ(scene.width, 640);
    EXPECT_EQ(scene.height, 480);
    EXPECT_EQ(scene.max_depth, 5);
}

TEST(SceneLoader, RangeLimitsThemselvesAreAccepted) {
    const Scene scene = parse_with_camera(R"("image": { "width": 1, "height": 16384 }, "max_depth": 64,
                                             "materials": { "black": { "color": [0, 0, 0], "ambient": 0 } },
                                             "objects": [])");
    EXPECT_EQ(scene.width, 1);
    EXPECT_EQ(scene.height, 16384);
    EXPECT_EQ(scene.max_depth, 64);
}

TEST(SceneLoader, PlaneNormalIsNormalisedAndOffsetKept) {
    const Scene scene = parse_with_camera(R"("objects": [
        { "type": "plane", "normal": [0, 2, 0], "offset": 3 },
        { "type": "plane", "normal": [3, 0, -4], "offset": -1.5 },
        { "type": "plane", "normal": [1e300, 0, 1e300], "offset": 0 } ])");
    const auto& upward = std::get<Plane>(scene.objects.at(0).shape);
    EXPECT_EQ(upward.normal, (Vec3{0, 1, 0}));
    EXPECT_EQ(upward.offset, 3);
    const auto& slanted = std::get<Plane>(scene.objects.at(1).shape);
    EXPECT_DOUBLE_EQ(slanted.normal[0], 0.6);
    EXPECT_EQ(slanted.normal[1], 0);
    EXPECT_DOUBLE_EQ(slanted.normal[2], -0.8);
    EXPECT_EQ(slanted.offset, -1.5);
    // Squaring 1e300 would overflow; the unit normal must still come out.
    const auto& huge = std::get<Plane>(scene.objects.at(2).shape);
    EXPECT_DOUBLE_EQ(huge.normal[0], std::sqrt(0.5));
    EXPECT_DOUBLE_EQ(huge.normal[2], std::sqrt(0.5));
}

TEST(SceneLoader, PrimitivesKeepTheirValues) {
    const Scene scene = parse_with_camera(R"("objects": [
        { "type": "sphere", "center": [1, 2, 3], "radius": 0.5 },
        { "type": "cylinder", "base": [0, 0, 0], "cap": [0, 2, 0], "radius": 0.25 },
        { "type": "box", "min": [-1, -2, -3], "max": [1, 2, 3] } ])");
    const auto& sphere = std::get<Sphere>(scene.objects.at(0).shape);
    EXPECT_EQ(sphere.center, (Vec3{1, 2, 3}));
    EXPECT_EQ(sphere.radius, 0.5);
    const auto& cylinder = std::get<Cylinder>(scene.objects.at(1).shape);
    EXPECT_EQ(cylinder.base, (Vec3{0, 0, 0}));
    EXPECT_EQ(cylinder.cap, (Vec3{0, 2, 0}));
    EXPECT_EQ(cylinder.radius, 0.25);
    const auto& box = std::get<Box>(scene.objects.at(2).shape);
    EXPECT_EQ(box.min, (Vec3{-1, -2, -3}));
    EXPECT_EQ(box.max, (Vec3{1, 2, 3}));
}

// Where a primitive of the same kind holds the placed one, the loader places it in double: a translation on a
// binary grid, a power-of-two scale and a turn by 90° (exact: cos 90° is taken as 0, not 6e-17) leave every
// value exact.
TEST(SceneLoader, TransformsThatAPrimitiveKindHoldsArePlacedExactly) {
    const Scene scene = parse_with_camera(R"("objects": [
        { "type": "sphere", "center": [1, 0, 0], "radius": 0.5,
          "transform": [{"scale": 2}, {"rotate": [0, 0, 90]}, {"translate": [0.25, -3, 8]}] },
        { "type": "cylinder", "base": [0, 0, 0], "cap": [0, 2, 0], "radius": 0.25,
          "transform": [{"rotate": {"axis": [1, 0, 0], "deg": -90}}, {"scale": 0.5}] },
        { "type": "box", "min": [-1, -2, -3], "max": [1, 2, 3],
          "transform": [{"rotate": [0, 90, 0]}, {"scale": [2, -1, 4]}, {"translate": [1, 1, 1]}] },
        { "type": "plane", "normal": [0, 1, 0], "offset": 1,
          "transform": [{"rotate": [90, 0, 0]}, {"scale": 4}, {"translate": [0, 0, 0.5]}] } ])");
    const auto& sphere = std::get<Sphere>(scene.objects.at(0).shape);
    EXPECT_EQ(sphere.center, (Vec3{0.25, -1, 8}));
    EXPECT_EQ(sphere.radius, 1);
    const auto& cylinder = std::get<Cylinder>(scene.objects.at(1).shape);
    EXPECT_EQ(cylinder.base, (Vec3{0, 0, 0}));
    EXPECT_EQ(cylinder.cap, (Vec3{0, 0, -1}));
    EXPECT_EQ(cylinder.radius, 0.125);
    // About y by 90°, x goes to −z and z to x: [−3, 3] × [−2, 2] × [−1, 1], then scaled and moved.
    const auto& box = std::get<Box>(scene.objects.at(2).shape);
    EXPECT_EQ(box.min, (Vec3{-5, -1, -3}));
    EXPECT_EQ(box.max, (Vec3{7, 3, 5}));
    // y = 1 turned about x to z = 1, scaled to z = 4, moved to z = 4.5.
    const auto& plane = std::get<Plane>(scene.objects.at(3).shape);
    EXPECT_EQ(plane.normal, (Vec3{0, 0, 1}));
    EXPECT_EQ(plane.offset, 4.5);
}

// An uneven scale of a sphere or cylinder, or a turn of a box off the axes, stays in object space with the whole
// transform, its steps composed in list order (each applied after the ones before it).
TEST(SceneLoader, TransformsNoPrimitiveKindHoldsStayInObjectSpaceComposedInListOrder) {
    const Scene scene = parse_with_camera(R"("objects": [
        { "type": "sphere", "center": [0, 0, 0], "radius": 1,
          "transform": [{"scale": [2, 1, 1]}, {"translate": [1, 0, 0]}] },
        { "type": "sphere", "center": [0, 0, 0], "radius": 1,
          "transform": [{"translate": [1, 0, 0]}, {"scale": [2, 1, 1]}] },
        { "type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": [{"rotate": [0, 0, 45]}] } ])");
    const auto& scaled_then_moved = std::get<Transformed<Sphere>>(scene.objects.at(0).shape);
    EXPECT_EQ(scaled_then_moved.to_world().point_to_world({1, 0, 0}), (Vec3{3, 0, 0}));
    const auto& moved_then_scaled = std::get<Transformed<Sphere>>(scene.objects.at(1).shape);
    EXPECT_EQ(moved_then_scaled.to_world().point_to_world({1, 0, 0}), (Vec3{4, 0, 0}));
    EXPECT_EQ(moved_then_scaled.to_world().point_to_object({4, 0, 0}), (Vec3{1, 0, 0}));
    const auto& turned = std::get<Transformed<Box>>(scene.objects.at(2).shape);
    Vec3 corner = turned.to_world().point_to_world({1, 0, 0});
    EXPECT_NEAR(corner[0], std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(corner[1], std::sqrt(0.5), 1e-15) << "counter-clockwise about z, seen from +z";
}

// A CSG node's transform applies to each child after the child's own; a mesh's to its vertices (and, through the
// inverse transpose, its normals), so a mirror keeps each triangle's vertex order and so turns its front.
TEST(SceneLoader, ACsgNodesTransformFollowsItsChildrensAndAMeshsMovesItsVertices) {
    const Scene scene = parse_with_camera(R"("objects": [
        { "type": "union", "transform": [{"translate": [0, 10, 0]}], "children": [
            { "type": "sphere", "center": [0, 0, 0], "radius": 1, "transform": [{"scale": 2}] },
            { "type": "sphere", "center": [0, 0, 0], "radius": 1, "transform": [{"translate": [0, -10, 0]}] } ] },
        { "type": "mesh", "vertices": [[0, 0, 1], [1, 0, 1], [0, 1, 1]], "triangles": [[0, 1, 2]],
          "normals": [[0, 0, 1], [0, 0, 1], [0, 3, 4]], "transform": [{"scale": [1, 1, -1]}] } ])");
    const auto& csg = std::get<Csg>(scene.objects.at(0).shape);
    EXPECT_EQ(std::get<Sphere>(csg.children.at(0).shape).center, (Vec3{0, 10, 0}));
    EXPECT_EQ(std::get<Sphere>(csg.children.at(0).shape).radius, 2);
    EXPECT_EQ(std::get<Sphere>(csg.children.at(1).shape).center, (Vec3{0, 0, 0}));
    const MeshData& mesh = *scene.meshes.at(0).data;
    EXPECT_EQ(mesh.vertices.at(1), (Vec3{1, 0, -1}));
    EXPECT_EQ(mesh.triangles.at(0), (std::array<std::uint32_t, 3>{0, 1, 2}));
    EXPECT_EQ(mesh.normals.at(0), (Vec3{0, 0, -1}));
    EXPECT_EQ(mesh.normals.at(2), (Vec3{0, 0.6, -0.8}));
}

TEST(SceneLoader, NamedMaterialsFollowTheDefaultInFileOrder) {
    const Scene scene = parse_with_camera(R"("materials": { "zinc": { "diffuse": 0.2 }, "amber": { "diffuse": 0.9 } },
                                             "objects": [])");
    EXPECT_EQ(scene.material_names, (std::vector<std::string>{"(default)", "zinc", "amber"}));
    EXPECT_EQ(scene.materials.at(1).diffuse, 0.2);
    EXPECT_EQ(scene.materials.at(2).diffuse, 0.9);
}

// Leaves in document order:            material, and why:
//   0 objects[0]                        default (nothing names one)
//   1 objects[1].children[0]            b, its own
//   2 objects[1].children[1].children[0]                 a, from the union two levels up
//   3 objects[1].children[1].children[1].children[0]     c, from the difference just above
//   4 objects[1].children[1].children[1].children[1]     a, its own, overriding the difference's c
//   5 objects[2]                        c, its own
constexpr std::string_view nested_csg_scene = R"({
    "camera": { "eye": [0, 1, 5], "look_at": [0, 1, 0] },
    "materials": { "a": { "diffuse": 0.1 }, "b": { "diffuse": 0.2 }, "c": { "diffuse": 0.3 } },
    "objects": [
        { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
        { "type": "union", "material": "a", "children": [
            { "type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "b" },
            { "type": "intersection", "children": [
                { "type": "box", "min": [0, 0, 0], "max": [1, 1, 1] },
                { "type": "difference", "material": "c", "children": [
                    { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
                    { "type": "cylinder", "base": [0, 0, 0], "cap": [0, 1, 0], "radius": 1, "material": "a" } ] } ] } ] },
        { "type": "plane", "normal": [0, 1, 0], "offset": 0, "material": "c" }
    ] })";

const Object& child(const Object& csg, std::size_t index) {
    return std::get<Csg>(csg.shape).children.at(index);
}

TEST(SceneLoader, PrimitiveUsesOwnMaterialElseNearestNamingAncestorElseDefault) {
    const Scene scene = parse(nested_csg_scene);
    const int a = 1, b = 2, c = 3;
    EXPECT_EQ(scene.leaf_materials, (std::vector<int>{0, b, a, c, a, c}));
    const Object& intersection = child(scene.objects.at(1), 1);
    const Object& difference = child(intersection, 1);
    EXPECT_EQ(scene.objects.at(0).material, 0);
    EXPECT_EQ(child(scene.objects.at(1), 0).material, b);
    EXPECT_EQ(child(intersection, 0).material, a);
    EXPECT_EQ(child(difference, 0).material, c);
    EXPECT_EQ(child(difference, 1).material, a);
    EXPECT_EQ(scene.objects.at(2).material, c);
    EXPECT_EQ(scene.material_of_leaf(3).diffuse, 0.3);
}

TEST(SceneLoader, LeavesAreNumberedInDocumentOrderWithTheirPaths) {
    const Scene scene = parse(nested_csg_scene);
    EXPECT_EQ(scene.leaf_paths, (std::vector<std::string>{
                                    "objects[0]",
                                    "objects[1].children[0]",
                                    "objects[1].children[1].children[0]",
                                    "objects[1].children[1].children[1].children[0]",
                                    "objects[1].children[1].children[1].children[1]",
                                    "objects[2]",
                                }));
    const Object& intersection = child(scene.objects.at(1), 1);
    const Object& difference = child(intersection, 1);
    EXPECT_EQ(scene.objects.at(0).leaf, 0);
    EXPECT_EQ(child(scene.objects.at(1), 0).leaf, 1);
    EXPECT_EQ(child(intersection, 0).leaf, 2);
    EXPECT_EQ(child(difference, 0).leaf, 3);
    EXPECT_EQ(child(difference, 1).leaf, 4);
    EXPECT_EQ(scene.objects.at(2).leaf, 5);
    EXPECT_EQ(std::get<Csg>(difference.shape).op, CsgOp::difference);
    EXPECT_EQ(std::get<Csg>(intersection.shape).op, CsgOp::intersection);
}

// A mesh is one leaf in document order among the objects; its vertices, triangles and normals as written
// (normals of unit length), degenerate triangles listed by index, smooth where it gives normals.
TEST(SceneLoader, AMeshKeepsItsDataAndTakesItsPlaceInDocumentOrder) {
    const Scene scene = parse_with_camera(R"("materials": { "red": {} }, "objects": [
        { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
        { "type": "mesh", "material": "red", "vertices": [[0, 0, 0], [2, 0, 0], [0, 2, 0], [4, 0, 0]],
          "triangles": [[0, 1, 2], [0, 1, 3], [2, 2, 1]], "normals": [[0, 0, 3], [0, 0, 1], [0, 0, 1], [0, 0, 1]] },
        { "type": "box", "min": [0, 0, 0], "max": [1, 1, 1] } ])");
    EXPECT_EQ(scene.leaf_paths, (std::vector<std::string>{"objects[0]", "objects[1]", "objects[2]"}));
    ASSERT_EQ(scene.meshes.size(), 1u);
    const Mesh& mesh = scene.meshes[0];
    EXPECT_EQ(mesh.leaf, 1);
    EXPECT_EQ(mesh.material, 1);
    EXPECT_EQ(scene.objects.at(1).leaf, 2);
    EXPECT_EQ(mesh.data->vertices.at(3), (Vec3{4, 0, 0}));
    EXPECT_EQ(mesh.data->triangles.at(1), (std::array<std::uint32_t, 3>{0, 1, 3}));
    EXPECT_EQ(mesh.data->normals.at(0), (Vec3{0, 0, 1}));
    EXPECT_TRUE(mesh.data->smooth);
    EXPECT_EQ(mesh.data->degenerate, (std::vector<std::uint32_t>{1, 2})) << "collinear, then a repeated index";
    EXPECT_EQ(scene.primitive_count(), 5u);
}

// A mesh file is read beside the scene file, its name kept; its triangles count as the inline ones do.
TEST(SceneLoader, AMeshFileIsReadBesideTheSceneFile) {
    const std::filesystem::path scene_file = source_dir / "tests" / "data" / "meshes" / "scene.json";
    const Scene scene =
        parse_scene("{ " + std::string(camera_block) + R"(, "objects": [ { "type": "mesh", "file": "cube.obj" } ] })",
                    scene_file.string());
    ASSERT_EQ(scene.meshes.size(), 1u);
    const MeshData& data = *scene.meshes[0].data;
    EXPECT_EQ(data.file, "cube.obj");
    EXPECT_EQ(data.triangles.size(), 12u) << "six quads, two triangles each";
    EXPECT_EQ(data.vertices.size(), 8u);
    EXPECT_EQ(scene.primitive_count(), 12u);
    EXPECT_TRUE(data.degenerate.empty());
}

// smooth without normals: each vertex's the normalised sum of its triangles' (b − a) × (c − a).
TEST(SceneLoader, ASmoothMeshWithoutNormalsGetsAreaWeightedVertexNormals) {
    const Scene scene = parse_with_camera(R"("objects": [
        { "type": "mesh", "smooth": true, "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
          "triangles": [[0, 1, 2], [0, 3, 1]] } ])");
    const MeshData& data = *scene.meshes.at(0).data;
    EXPECT_TRUE(data.smooth);
    // Vertex 0 and 1 sum (0, 0, 1) and (0, 1, 0); vertex 2 has only the first, vertex 3 only the second.
    const double half = std::sqrt(0.5);
    EXPECT_NEAR(data.normals.at(0).y, half, 1e-15);
    EXPECT_NEAR(data.normals.at(0).z, half, 1e-15);
    EXPECT_EQ(data.normals.at(2), (Vec3{0, 0, 1}));
    EXPECT_EQ(data.normals.at(3), (Vec3{0, 1, 0}));
}

TEST(SceneLoader, ContractExampleLoads) {
    const Scene scene = parse(R"({
      "format": "twinray-scene/1",
      "image":  { "width": 320, "height": 240 },
      "camera": { "eye": [0, 2, 8], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov_deg": 50 },
      "background": [0, 0, 0],
      "ambient_light": [1, 1, 1],
      "max_depth": 5,
      "materials": {
        "floor": { "color": [0.8, 0.8, 0.8], "diffuse": 0.8 },
        "glass": { "color": [1, 1, 1], "ambient": 0, "diffuse": 0.05, "phong": 0.9, "phong_size": 80,
                   "reflection": 0.1, "transmission": 0.85, "ior": 1.5 }
      },
      "lights": [ { "position": [5, 8, -6], "color": [1, 1, 1] } ],
      "objects": [
        { "type": "plane",    "normal": [0, 1, 0], "offset": 0, "material": "floor" },
        { "type": "sphere",   "center": [0, 1, 0], "radius": 1, "material": "glass" },
        { "type": "cylinder", "base": [2, 0, 0], "cap": [2, 2, 0], "radius": 0.5 },
        { "type": "box",      "min": [-3, 0, -1], "max": [-2, 1, 0] },
        { "type": "difference", "material": "floor", "children": [
            { "type": "box", "min": [-1, 0, 2], "max": [1, 2, 4] },
            { "type": "sphere", "center": [0, 1, 2], "radius": 1.2 } ] }
      ]
    })");
    EXPECT_EQ(scene.material_names, (std::vector<std::string>{"(default)", "floor", "glass"}));
    EXPECT_EQ(scene.leaf_materials, (std::vector<int>{1, 2, 0, 0, 1, 1}));
    EXPECT_EQ(scene.leaf_paths.back(), "objects[4].children[1]");
    EXPECT_TRUE(scene.has_csg());
    EXPECT_TRUE(scene.has_transparency());
    EXPECT_TRUE(scene.has_reflection());
}

TEST(SceneLoader, OnlyMaterialsInUseMakeASceneTransparentOrReflective) {
    const std::string materials = R"("materials": { "glass": { "transmission": 0.9 }, "mirror": { "reflection": 1 } })";
    const Scene unused = parse_with_camera(materials + R"(, "objects": [
        { "type": "sphere", "center": [0, 0, 0], "radius": 1 } ])");
    EXPECT_FALSE(unused.has_transparency());
    EXPECT_FALSE(unused.has_reflection());
    EXPECT_FALSE(unused.has_csg());
    // Both reach a leaf only through a CSG ancestor.
    const Scene inherited = parse_with_camera(materials + R"(, "objects": [
        { "type": "union", "material": "glass", "children": [
            { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
            { "type": "union", "material": "mirror", "children": [
                { "type": "sphere", "center": [1, 0, 0], "radius": 1 },
                { "type": "sphere", "center": [2, 0, 0], "radius": 1 } ] } ] } ])");
    EXPECT_TRUE(inherited.has_transparency());
    EXPECT_TRUE(inherited.has_reflection());
    EXPECT_TRUE(inherited.has_csg());
}

TEST(SceneLoader, CsgNestedSixtyFourLevelsDeepLoads) {
    const std::string sphere = R"({ "type": "sphere", "center": [0, 0, 0], "radius": 1 })";
    std::string object = sphere;
    for (int level = 1; level < 64; ++level) {
        object = R"({ "type": "union", "children": [ )" + object + ", " + sphere + " ] }";
    }
    const Scene scene = parse_with_camera(R"("objects": [ )" + object + " ]");
    EXPECT_EQ(scene.leaf_paths.front(), "objects[0]" + repeated(".children[0]", 63));
    EXPECT_EQ(scene.leaf_paths.size(), 64u);
}

TEST(SceneLoader, TheSameKeyInDifferentObjectsIsNoDuplicate) {
    const Scene scene = parse_with_camera(R"("objects": [
        { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
        { "type": "sphere", "center": [1, 0, 0], "radius": 2 } ])");
    EXPECT_EQ(scene.objects.size(), 2u);
}

TEST(SceneLoader, SyntaxErrorIsLocatedByLineAndColumnFromOne) {
    try {
        parse("{\n  \"objects\": [],\n  \"camera\": x\n}");
        ADD_FAILURE() << "accepted";
    } catch (const SceneError& error) {
        EXPECT_EQ(error.location(), "line 3, column 13") << error.what();
        EXPECT_EQ(error.problem().find("json.exception"), std::string::npos) << error.what();
        EXPECT_EQ(std::string(error.what()), "<test>: " + error.location() + ": " + error.problem());
    }
}

TEST(SceneLoader, MissingFileIsASceneErrorNamingTheFile) {
    const std::filesystem::path file = malformed_dir / "no_such_scene.json";
    try {
        load_scene(file);
        ADD_FAILURE() << "loaded a file that does not exist";
    } catch (const SceneError& error) {
        EXPECT_EQ(error.file(), file.string());
        EXPECT_EQ(error.location(), "");
        EXPECT_NE(error.problem().find("cannot open file"), std::string::npos) << error.what();
        EXPECT_TRUE(std::string_view(error.what()).starts_with(file.string() + ": ")) << error.what();
    }
}

TEST(SceneLoader, DirectoryIsASceneErrorNotAnEmptyScene) {
    try {
        load_scene(malformed_dir);
        ADD_FAILURE() << "loaded a directory";
    } catch (const SceneError& error) {
        EXPECT_NE(error.problem().find("cannot read file"), std::string::npos) << error.what();
    }
}

// ---------------------------------------------------------------------------------------------------
// The primitive limit (docs/scene-format.md, "Limits"), checked with a small limit so that the scenes stay
// small: the check is the same for the default.

// Four primitives: a sphere, a union of two, a box. `materials_first`: streamed, as every scene is written;
// else the elements of objects are kept in the tree until the materials are known.
std::string four_primitives(bool materials_first) {
    const std::string materials = R"("materials": { "red": { "color": [1, 0, 0] } })";
    const std::string objects = R"("objects": [
        { "type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "red" },
        { "type": "union", "children": [
            { "type": "sphere", "center": [1, 0, 0], "radius": 1 },
            { "type": "sphere", "center": [2, 0, 0], "radius": 1 } ] },
        { "type": "box", "min": [0, 0, 0], "max": [1, 1, 1] } ])";
    return "{ " + std::string(camera_block) + ", " +
           (materials_first ? materials + ", " + objects : objects + ", " + materials) + " }";
}

SceneError refusal_with_limit(const std::string& text, std::size_t max_primitives) {
    try {
        parse_scene(text, "limit.json", max_primitives);
    } catch (const SceneError& error) {
        return error;
    }
    ADD_FAILURE() << "accepted with a limit of " << max_primitives << " primitives";
    return SceneError("", "", "");
}

TEST(SceneLimits, TheDefaultAllowsWhatTheGeneratorWritesWithHeadroom) {
    EXPECT_GE(max_scene_primitives, 4u * 1'000'000u);
    EXPECT_EQ(parse(four_primitives(true)).leaf_paths.size(), 4u);
}

TEST(SceneLimits, ASceneOfExactlyTheLimitLoads) {
    for (bool materials_first : {true, false}) {
        EXPECT_EQ(parse_scene(four_primitives(materials_first), "limit.json", 4).leaf_paths.size(), 4u);
    }
}

TEST(SceneLimits, ThePrimitivePastTheLimitIsRefusedWithItsPathCountAndLimit) {
    const SceneError error = refusal_with_limit(four_primitives(true), 2);
    EXPECT_EQ(error.file(), "limit.json");
    EXPECT_EQ(error.location(), "objects[1].children[1]") << error.what();
    EXPECT_EQ(error.problem(), "primitive number 3 of the scene: more than the limit of 2 primitives (about " +
                                   std::to_string(bytes_per_primitive) +
                                   " bytes of memory each when rendered; no scene may hold more than " +
                                   std::to_string(max_scene_primitives) + ")")
        << error.what();
    EXPECT_EQ(refusal_with_limit(four_primitives(true), 3).location(), "objects[2]");
}

// A mesh's triangles count towards the limit, each as a primitive: the mesh that would pass it is refused
// with its triangles array's path.
TEST(SceneLimits, EachTriangleOfAMeshCountsAsAPrimitive) {
    const std::string text = "{ " + std::string(camera_block) + R"(, "objects": [
        { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
        { "type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]],
          "triangles": [[0, 1, 2], [1, 3, 2]] } ] })";
    EXPECT_EQ(parse_scene(text, "limit.json", 3).primitive_count(), 3u);
    const SceneError error = refusal_with_limit(text, 2);
    EXPECT_EQ(error.location(), "objects[1].triangles") << error.what();
    EXPECT_TRUE(error.problem().starts_with("its 2 triangles: more than the limit of 1 primitives")) << error.what();
}

// A mesh's rows are counted as the text is read: the triangles past the limit, the vertices and normals past three
// per triangle of it, are refused at that row, before the rest of the array is held.
TEST(SceneLimits, AMeshsRowsPastTheLimitAreRefusedAtTheRowAsTheyAreRead) {
    const auto rows_of = [](std::string_view row, int count) {
        std::string rows = repeated(std::string(row) + ", ", count);
        return "[" + rows.substr(0, rows.size() - 2) + "]";
    };
    const auto mesh = [&](int vertices, int normals, int triangles) {
        return "{ " + std::string(camera_block) +
               R"(, "objects": [{ "type": "sphere", "center": [0, 0, 0], "radius": 1 },
            { "type": "mesh", "vertices": )" +
               rows_of("[0, 0, 1]", vertices) +
               (normals > 0 ? R"(, "normals": )" + rows_of("[0, 0, 1]", normals) : "") + R"(, "triangles": )" +
               rows_of("[0, 1, 2]", triangles) + " } ] }";
    };
    const SceneError triangles = refusal_with_limit(mesh(3, 0, 3), 2);
    EXPECT_EQ(triangles.location(), "objects[1].triangles[2]") << triangles.what();
    EXPECT_TRUE(triangles.problem().starts_with("triangle number 3 of a mesh: more than the limit of 2 primitives"))
        << triangles.what();
    const SceneError vertices = refusal_with_limit(mesh(7, 0, 1), 2);
    EXPECT_EQ(vertices.location(), "objects[1].vertices[6]") << vertices.what();
    EXPECT_EQ(vertices.problem(),
              "vertex number 7 of a mesh: more than three per triangle of the limit of 2 primitives");
    const SceneError normals = refusal_with_limit(mesh(6, 7, 1), 2);
    EXPECT_EQ(normals.location(), "objects[1].normals[6]") << normals.what();
    // Within the rows' bound, the reader's own counts as before: the sphere leaves 2 triangles of 3.
    const SceneError reader = refusal_with_limit(mesh(3, 0, 3), 3);
    EXPECT_EQ(reader.location(), "objects[1].triangles") << reader.what();
    EXPECT_TRUE(reader.problem().starts_with("its 3 triangles: more than the limit of 2 primitives")) << reader.what();
    EXPECT_EQ(parse_scene(mesh(6, 6, 1), "rows.json", 2).primitive_count(), 2u);
}

// Elements kept in the tree (objects before materials) are counted as the text is read: the tree stops
// growing at the limit, before any primitive is read.
TEST(SceneLimits, AKeptObjectsArrayIsRefusedAtTheElementPastTheLimit) {
    const SceneError error = refusal_with_limit(four_primitives(false), 2);
    EXPECT_EQ(error.location(), "objects[2]") << error.what();
    EXPECT_TRUE(error.problem().starts_with(
        "element number 3 of objects, each holding a primitive at least: more than the limit of 2 primitives"))
        << error.what();
    // Within the elements' limit, the primitives of a CSG object are counted as they are read.
    EXPECT_EQ(refusal_with_limit(four_primitives(false), 3).location(), "objects[2]") << "the box, 4th primitive";
}

// The refusal of a streamed element waits for the end of the file, as every streamed refusal does, so a
// fault earlier in reading order is the one reported.
TEST(SceneLimits, ARefusalEarlierInReadingOrderIsReportedFirst) {
    std::string text = four_primitives(true);
    const std::string look_at = "\"look_at\": [0, 1, 0]";
    text.replace(text.find(look_at), look_at.size(), "\"look_at\": [0, 1, 5]");  // the eye
    EXPECT_EQ(refusal_with_limit(text, 2).location(), "camera.look_at");
}

// ---------------------------------------------------------------------------------------------------
// The command-line image size.

Scene scene_of_size(int width, int height) {
    Scene scene;
    scene.width = width;
    scene.height = height;
    return scene;
}

void expect_size(const ImageSize& size, int width, int height) {
    EXPECT_EQ(size.width, width);
    EXPECT_EQ(size.height, height);
}

TEST(ResolveImageSize, NeitherSideGivenKeepsTheScenesSize) {
    expect_size(resolve_image_size(scene_of_size(320, 240), 0, 0), 320, 240);
}

TEST(ResolveImageSize, BothSidesGivenReplaceTheScenesSize) {
    expect_size(resolve_image_size(scene_of_size(320, 240), 100, 300), 100, 300);
}

TEST(ResolveImageSize, OneSideGivenScalesTheOtherToTheScenesAspectRatio) {
    const Scene scene = scene_of_size(320, 240);
    expect_size(resolve_image_size(scene, 640, 0), 640, 480);
    expect_size(resolve_image_size(scene, 0, 480), 640, 480);
    expect_size(resolve_image_size(scene, 100, 0), 100, 75);
}

TEST(ResolveImageSize, ScaledSideRoundsToTheNearestInteger) {
    const Scene scene = scene_of_size(320, 240);
    expect_size(resolve_image_size(scene, 10, 0), 10, 8);   // 7.5 rounds up
    expect_size(resolve_image_size(scene, 11, 0), 11, 8);   // 8.25
    expect_size(resolve_image_size(scene, 0, 10), 13, 10);  // 13.33
    expect_size(resolve_image_size(scene, 0, 11), 15, 11);  // 14.67
}

TEST(ResolveImageSize, ScaledSideIsAtLeastOne) {
    expect_size(resolve_image_size(scene_of_size(16384, 1), 100, 0), 100, 1);
    expect_size(resolve_image_size(scene_of_size(320, 240), 1, 0), 1, 1);
}

TEST(ResolveImageSize, SideOutsideOneTo16384IsRefused) {
    const Scene scene = scene_of_size(320, 240);
    EXPECT_THROW(resolve_image_size(scene, 16385, 0), std::invalid_argument);
    EXPECT_THROW(resolve_image_size(scene, -1, 0), std::invalid_argument);
    EXPECT_THROW(resolve_image_size(scene, 0, -5), std::invalid_argument);
    EXPECT_THROW(resolve_image_size(scene, 100, 16385), std::invalid_argument);
    EXPECT_NO_THROW(resolve_image_size(scene, 16384, 16384));
}

TEST(ResolveImageSize, ScaledSideBeyond16384IsRefused) {
    EXPECT_THROW(resolve_image_size(scene_of_size(1, 16384), 2, 0), std::invalid_argument);
}

// Top-level elements' paths are held as their index alone; every other path, and every spelling of an index the
// loader never writes, as text: each comes back as it went in.
TEST(LeafPaths, EveryPathComesBackAsItWasGivenWhetherHeldAsAnIndexOrAsText) {
    const std::vector<std::string> paths{"objects[0]",
                                         "objects[7]",
                                         "objects[2147483647]",
                                         "objects[2147483648]",
                                         "objects[01]",
                                         "objects[-1]",
                                         "objects[]",
                                         "objects[12",
                                         "objects[3].children[1]",
                                         "objects[4] (shapes.tree)",
                                         std::string("shapes.a\0b", 10),
                                         ""};
    LeafPaths held;
    for (const std::string& path : paths) {
        held.push_back(path);
    }
    ASSERT_EQ(held.size(), paths.size());
    for (std::size_t leaf = 0; leaf < paths.size(); ++leaf) {
        EXPECT_EQ(held[leaf], paths[leaf]) << "leaf " << leaf;
    }
    EXPECT_TRUE(held == paths);
    EXPECT_EQ(held.back(), "");
    EXPECT_THROW(static_cast<void>(held.at(paths.size())), std::out_of_range);
}

// The bench's generated scenes (twinray bench --scaling): as many spheres as asked, numbered as the
// loader numbers leaves, inside the cube, the same again for the same seed and another for another.
TEST(SphereField, HasTheAskedSpheresNumberedAsLoadedAndIsTheSameForTheSameSeed) {
    Scene field = sphere_field(100);
    ASSERT_EQ(field.objects.size(), 100u);
    ASSERT_EQ(field.leaf_paths.size(), 100u);
    ASSERT_EQ(field.leaf_materials.size(), 100u);
    for (std::size_t i = 0; i < field.objects.size(); ++i) {
        const auto& sphere = std::get<Sphere>(field.objects[i].shape);
        EXPECT_EQ(field.objects[i].leaf, static_cast<int>(i));
        EXPECT_EQ(field.leaf_paths[i], "objects[" + std::to_string(i) + "]");
        EXPECT_GT(sphere.radius, 0.0);
        for (int axis = 0; axis < 3; ++axis) {
            EXPECT_LE(std::fabs(sphere.center[axis]), 10.0);
        }
        EXPECT_GE(field.objects[i].material, 1);
        EXPECT_LT(field.objects[i].material, static_cast<int>(field.materials.size()));
    }
    Scene again = sphere_field(100);
    Scene other = sphere_field(100, 8);
    EXPECT_EQ(std::get<Sphere>(again.objects[57].shape).center, std::get<Sphere>(field.objects[57].shape).center);
    EXPECT_NE(std::get<Sphere>(other.objects[57].shape).center, std::get<Sphere>(field.objects[57].shape).center);
}

// ---------------------------------------------------------------------------------------------------
// The streaming reader keeps a top-level mesh's rows of three numbers packed (scene_stream.cpp): 9 bytes a
// number instead of an entry a number and one a row, so an inline mesh of a million triangles is never a tree.

namespace stream {

// Keeps every element of "objects" in the tree.
class KeepObjects final : public ObjectsReader {
public:
    bool stream_elements(const JsonTree&) override { return false; }
    void element(JsonValue, JsonValue, std::size_t) override {}
    std::size_t most_elements() const override { return 1'000'000; }
};

JsonTree tree_of(std::string_view text) {
    JsonTree tree;
    KeepObjects keep;
    read_json(text, tree, keep);
    return tree;
}

// Everything the tree holds of each entry but its key, as text.
std::vector<std::string> entries_of(const JsonTree& tree) {
    std::vector<std::string> entries;
    for (std::size_t i = 0; i < tree.entry_count(); ++i) {
        const JsonTree::Entry& e = tree.entry(i);
        entries.push_back(std::to_string(static_cast<int>(e.kind)) + " end " + std::to_string(e.end) + " count " +
                          std::to_string(e.count) + " rows " + std::to_string(e.rows) + " integer " +
                          std::to_string(e.integer) + " value " + JsonValue(tree, i).dump());
    }
    return entries;
}

std::string mesh_scene(std::string_view key, std::string_view rows) {
    return R"({"objects": [{"type": "mesh", ")" + std::string(key) + R"(": )" + std::string(rows) + "}]}";
}

}  // namespace stream

TEST(SceneStream, AMeshsRowsOfThreeNumbersArePackedNotAnEntryEach) {
    std::string rows = "[[1.0, 7, -0], [1e300, -9007199254740992, 9007199254740992]";
    for (int i = 0; i < 10000; ++i) {
        rows += ", [" + std::to_string(i) + ", 0.5, 2]";
    }
    rows += "]";
    const JsonTree tree = stream::tree_of(stream::mesh_scene("vertices", rows));
    // The root, "objects", the mesh, its "type" and its "vertices": no entry for a row or a number.
    ASSERT_EQ(tree.entry_count(), 5u);
    const JsonValue vertices = *tree.root().find("objects")->first_child().find("vertices");
    ASSERT_TRUE(vertices.is_packed_rows());
    ASSERT_EQ(vertices.size(), 10002u);
    EXPECT_EQ(tree.packed_size(), 3 * 10002u);
    const std::array<std::string, 6> written = {"1.0", "7", "0", "1e+300", "-9007199254740992", "9007199254740992"};
    const std::array<double, 6> values = {1.0, 7.0, 0.0, 1e300, -9007199254740992.0, 9007199254740992.0};
    for (std::size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(vertices.row_dump(i / 3, i % 3), written[i]) << i;
        EXPECT_EQ(vertices.row_number(i / 3, i % 3), values[i]) << i;
    }
    EXPECT_FALSE(std::signbit(vertices.row_number(0, 2))) << "-0 written as an integer is +0, as nlohmann reads it";
    EXPECT_EQ(vertices.row_number(10001, 0), 9999.0);
    EXPECT_EQ(vertices.row_dump(10001, 1), "0.5");
}

// Each case breaks the rows somewhere: the tree must be what it is for the same text under a key of the same
// length that is never packed ("vertexes"), entry for entry.
TEST(SceneStream, RowsThatAreNotAllThreeNumbersAreEntriesAsIfNeverPacked) {
    const std::vector<std::string> cases = {
        "[[0, 0, 0], [1, 2]]",
        "[[1e300, -0.0, 7], [-5, 18446744073709551615, 9007199254740992], [1, 2]]",
        "[[-1e-300, 1.5, -9007199254740992], [0.5, -0, 3], \"x\"]",
        "[[0, 0, 0], [1, 2, 3, 4]]",
        "[[0, 0, 0], [1, 2], [3, 4, 5]]",
        "[[0, 0, 0], \"x\", [1, 2, 3]]",
        "[[0, 0, 0], 5]",
        "[[0, 0, 0], [1, [2], 3]]",
        "[[0, 0, 0], [1, {\"a\": 2}, 3]]",
        "[[0, 0, 0], [1, 2, 9007199254740993]]",
        "[[0, 0, 0], [1, 2, -9007199254740993]]",
        "[[0, 0, 0], [true, null, 1.5]]",
        "[[]]",
        "[]",
        "[[0, 0, 0], []]",
        "{\"a\": [[0, 0, 0]]}",
    };
    for (const std::string& rows : cases) {
        const JsonTree packed = stream::tree_of(stream::mesh_scene("vertices", rows));
        const JsonTree plain = stream::tree_of(stream::mesh_scene("vertexes", rows));
        const JsonValue value = *packed.root().find("objects")->first_child().find("vertices");
        const bool all_rows = rows == "[]";
        EXPECT_EQ(value.is_packed_rows(), all_rows) << rows;
        if (!all_rows) {
            EXPECT_EQ(stream::entries_of(packed), stream::entries_of(plain)) << rows;
            EXPECT_EQ(packed.packed_size(), 0u) << rows;
        }
    }
}

TEST(SceneStream, OnlyATopLevelObjectsVerticesTrianglesAndNormalsArePacked) {
    const std::string rows = "[[0, 1, 2]]";
    for (const std::string key : {"vertices", "triangles", "normals"}) {
        const JsonTree tree = stream::tree_of(stream::mesh_scene(key, rows));
        EXPECT_TRUE(tree.root().find("objects")->first_child().find(key)->is_packed_rows()) << key;
    }
    const JsonTree nested = stream::tree_of(R"({"objects": [{"type": "union", "children": [{"vertices": [[0, 1, 2]]}]}],
                                                "vertices": [[0, 1, 2]]})");
    EXPECT_EQ(nested.packed_size(), 0u);
    EXPECT_EQ(nested.entry_count(), 16u) << "each row and number an entry of its own";
}

TEST(SceneStream, AStreamedMeshsPackedRowsAreDroppedWithIt) {
    struct CountRows final : ObjectsReader {
        bool stream_elements(const JsonTree&) override { return true; }
        void element(JsonValue, JsonValue value, std::size_t) override {
            rows.push_back(value.find("triangles")->size());
            packed.push_back(tree->packed_size());
        }
        std::size_t most_elements() const override { return 1000; }
        const JsonTree* tree = nullptr;
        std::vector<std::size_t> rows, packed;
    };
    JsonTree tree;
    CountRows count;
    count.tree = &tree;
    read_json(R"({"objects": [{"type": "mesh", "triangles": [[0, 1, 2], [2, 1, 0]]},
                              {"type": "mesh", "triangles": [[0, 1, 2]]}]})",
              tree, count);
    EXPECT_EQ(count.rows, (std::vector<std::size_t>{2, 1}));
    EXPECT_EQ(count.packed, (std::vector<std::size_t>{6, 3})) << "the first mesh's numbers were not dropped";
    EXPECT_EQ(tree.packed_size(), 0u);
}

}  // namespace
}  // namespace twinray::scene
