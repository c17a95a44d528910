#include "scene/scene_builder.h"

#include "scene/geometry.h"
#include "scene/placement.h"

#include <cmath>
#include <memory>
#include <utility>
#include <variant>

namespace twinray::scene::builder {
namespace {

// Numbers the leaves under `object` after those already in `result`.
void number(Object& object, const std::string& path, int inherited, Scene& result) {
    const int material = object.material != 0 ? object.material : inherited;
    if (auto* node = std::get_if<Csg>(&object.shape)) {
        for (std::size_t i = 0; i < node->children.size(); ++i) {
            number(node->children[i], path + ".children[" + std::to_string(i) + "]", material, result);
        }
        return;
    }
    object.material = material;
    object.leaf = static_cast<int>(result.leaf_paths.size());
    result.leaf_paths.push_back(path);
    result.leaf_materials.push_back(material);
}

}  // namespace

Object plane(Vec3 normal, double offset, int material) {
    return {Plane{math::normalize(normal), offset}, material, -1};
}

Object sphere(Vec3 center, double radius, int material) {
    return {Sphere{center, radius}, material, -1};
}

Object cylinder(Vec3 base, Vec3 cap, double radius, int material) {
    return {Cylinder{base, cap, radius}, material, -1};
}

Object box(Vec3 min, Vec3 max, int material) {
    return {Box{min, max}, material, -1};
}

Object placed(Object primitive, const Transform& to_world) {
    primitive.shape = scene::placed(primitive.shape, to_world);
    return primitive;
}

Object csg(CsgOp op, std::vector<Object> children, int material) {
    return {Csg{op, std::move(children)}, material, -1};
}

Mesh mesh(std::vector<Vec3> vertices, std::vector<std::array<std::uint32_t, 3>> triangles, int material,
          std::vector<Vec3> normals) {
    auto data = std::make_shared<MeshData>();
    data->vertices = std::move(vertices);
    data->triangles = std::move(triangles);
    data->smooth = !normals.empty();
    data->normals = std::move(normals);
    data->degenerate = degenerate_triangles(*data);
    return {std::move(data), material, -1, std::nullopt};
}

SceneBuilder::SceneBuilder() {
    scene_.camera.eye = {0, 0, 5};
    scene_.camera.look_at = {0, 0, 0};
}

int SceneBuilder::material(const Material& material) {
    scene_.materials.push_back(material);
    scene_.material_names.push_back("m" + std::to_string(scene_.materials.size() - 1));
    return static_cast<int>(scene_.materials.size()) - 1;
}

SceneBuilder& SceneBuilder::light(Vec3 position, Vec3 color) {
    scene_.lights.push_back({position, color});
    return *this;
}

SceneBuilder& SceneBuilder::object(Object object) {
    scene_.objects.push_back(std::move(object));
    return *this;
}

SceneBuilder& SceneBuilder::add(Mesh mesh) {
    mesh_positions_.push_back(scene_.objects.size());
    scene_.meshes.push_back(std::move(mesh));
    return *this;
}

Scene SceneBuilder::build() const {
    Scene result = scene_;
    result.leaf_paths.clear();
    result.leaf_materials.clear();
    std::size_t next_mesh = 0, element = 0;
    auto number_meshes_before = [&](std::size_t object) {
        for (; next_mesh < mesh_positions_.size() && mesh_positions_[next_mesh] == object; ++next_mesh) {
            Mesh& mesh = result.meshes[next_mesh];
            mesh.leaf = static_cast<int>(result.leaf_paths.size());
            result.leaf_paths.push_back("objects[" + std::to_string(element++) + "]");
            result.leaf_materials.push_back(mesh.material);
        }
    };
    for (std::size_t i = 0; i < result.objects.size(); ++i) {
        number_meshes_before(i);
        number(result.objects[i], "objects[" + std::to_string(element++) + "]", 0, result);
    }
    number_meshes_before(result.objects.size());
    return result;
}

}  // namespace twinray::scene::builder
