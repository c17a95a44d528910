// The scene's blocks other than its objects: format, image, camera, materials, lights.
#include "scene/read_scene.h"

namespace twinray::scene {
namespace {

constexpr double min_up_sine = 1e-6;
constexpr std::string_view format_name = "twinray-scene/1";

const Schema image_schema{"image", {}, {"width", "height"}};
const Schema camera_schema{"the camera", {"eye", "look_at"}, {"up", "fov_deg"}};
const Schema material_schema{
    "a material", {}, {"color", "ambient", "diffuse", "phong", "phong_size", "reflection", "transmission", "ior"}};
const Schema light_schema{"a light", {"position"}, {"color"}};

// look_at - eye, which the up rule needs; coordinates so far apart that it overflows are refused.
Vec3 view_direction(const Node& look_at, const Camera& camera) {
    require_distinct(look_at, camera.look_at, "eye", camera.eye);
    const Vec3 forward = minus(camera.look_at, camera.eye);
    if (!is_finite(forward)) {
        refuse(look_at.path(), "is too far from eye: look_at - eye overflows a double");
    }
    return forward;
}

void require_up_not_parallel(const Node& camera_node, const Vec3& up, const Vec3& forward) {
    const double sine = sine_of_angle(forward, up);
    if (!(sine >= min_up_sine)) {
        const std::string which_up = camera_node.json().find("up") ? "up " : "the default up ";
        refuse(key_path(camera_node.path(), "up"), which_up + format_vec3(up) + " is parallel to the view direction " +
                                                       format_vec3(forward) + "; the sine of their angle must be >= " +
                                                       format_number(min_up_sine) + ", got " + format_number(sine));
    }
}

Material read_material(const Node& node) {
    require_keys_of(node, material_schema);
    Material material;
    material.color = read_or(node, "color", material.color, require_color);
    material.ambient = read_or(node, "ambient", material.ambient, number_in(non_negative));
    material.diffuse = read_or(node, "diffuse", material.diffuse, number_in(non_negative));
    material.phong = read_or(node, "phong", material.phong, number_in(non_negative));
    material.phong_size = read_or(node, "phong_size", material.phong_size, number_in(positive));
    material.reflection = read_or(node, "reflection", material.reflection, number_in(non_negative));
    material.transmission = read_or(node, "transmission", material.transmission, number_in(non_negative));
    material.ior = read_or(node, "ior", material.ior, number_in(positive));
    return material;
}

Light read_light(const Node& node) {
    require_keys_of(node, light_schema);
    Light light;
    light.position = require_vec3(at(node, "position"));
    light.color = read_or(node, "color", light.color, require_color);
    return light;
}

}  // namespace

const Schema scene_schema{
    "a scene",
    {"camera", "objects"},
    {"format", "image", "background", "ambient_light", "max_depth", "min_weight", "materials", "lights", "shapes"}};

void require_format(const Node& node) {
    if (require_string(node) != format_name) {
        refuse(node.path(), "must be " + in_quotes(format_name) + ", got " + describe(node.json()));
    }
}

void read_image(const Node& node, Scene& scene) {
    require_keys_of(node, image_schema);
    scene.width = read_or(node, "width", scene.width, integer_in(1, max_image_side));
    scene.height = read_or(node, "height", scene.height, integer_in(1, max_image_side));
}

Camera read_camera(const Node& node) {
    require_keys_of(node, camera_schema);
    Camera camera;
    camera.eye = require_vec3(at(node, "eye"));
    const Node look_at = at(node, "look_at");
    camera.look_at = require_vec3(look_at);
    const Vec3 forward = view_direction(look_at, camera);
    camera.up = read_or(node, "up", camera.up, require_vec3);
    require_up_not_parallel(node, camera.up, forward);
    camera.fov_deg = read_or(node, "fov_deg", camera.fov_deg, number_in(field_of_view));
    return camera;
}

void read_materials(const Node& node, Scene& scene) {
    require_object(node);
    JsonValue member = node.json().first_child();
    for (std::size_t i = 0; i < node.json().size(); ++i, member = member.next_sibling()) {
        scene.materials.push_back(read_material(node.member(member, member.key())));
        scene.material_names.emplace_back(member.key());
    }
}

std::vector<Light> read_lights(const Node& node) {
    std::vector<Light> lights;
    for (const Node& element : require_array(node, "an array of lights")) {
        lights.push_back(read_light(element));
    }
    return lights;
}

std::vector<std::string> material_names_of(const JsonValue& materials) {
    std::vector<std::string> names{Scene{}.material_names.front()};
    if (materials.is_object()) {
        JsonValue member = materials.first_child();
        for (std::size_t i = 0; i < materials.size(); ++i, member = member.next_sibling()) {
            names.emplace_back(member.key());
        }
    }
    return names;
}

}  // namespace twinray::scene
