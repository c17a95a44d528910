// Scenes built in code for the tests, numbered as the loader numbers them: leaves 0..n-1 in document
// order, leaf_paths as "objects[i].children[j]", leaf_materials with CSG inheritance applied (a
// primitive's own material, else that of its nearest CSG ancestor that names one, else 0, the default).
#pragma once

#include "scene/geometry.h"
#include "scene/placement.h"
#include "scene/scene.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

namespace twinray::test {

// Material index 0 is the built-in default, so 0 also means "none named" here, as in the loader.
inline scene::Object plane(scene::Vec3 normal, double offset, int material = 0) {
    double norm = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    scene::Plane shape{{normal[0] / norm, normal[1] / norm, normal[2] / norm}, offset};
    return {shape, material, -1};
}

inline scene::Object sphere(scene::Vec3 center, double radius, int material = 0) {
    return {scene::Sphere{center, radius}, material, -1};
}

inline scene::Object cylinder(scene::Vec3 base, scene::Vec3 cap, double radius, int material = 0) {
    return {scene::Cylinder{base, cap, radius}, material, -1};
}

inline scene::Object box(scene::Vec3 min, scene::Vec3 max, int material = 0) {
    return {scene::Box{min, max}, material, -1};
}

// The primitive placed by `to_world`, as the loader places one with a "transform" (scene/placement.h).
inline scene::Object placed(scene::Object primitive, const scene::Transform& to_world) {
    primitive.shape = scene::placed(primitive.shape, to_world);
    return primitive;
}

// `material` is the node's own named material, inherited by children that name none.
inline scene::Object csg(scene::CsgOp op, std::vector<scene::Object> children, int material = 0) {
    return {scene::Csg{op, std::move(children)}, material, -1};
}

// A mesh of the given vertices and triangles, flat unless normals are given.
inline scene::Mesh mesh(std::vector<scene::Vec3> vertices, std::vector<std::array<std::uint32_t, 3>> triangles,
                        int material = 0, std::vector<scene::Vec3> normals = {}) {
    auto data = std::make_shared<scene::MeshData>();
    data->vertices = std::move(vertices);
    data->triangles = std::move(triangles);
    data->smooth = !normals.empty();
    data->normals = std::move(normals);
    data->degenerate = scene::degenerate_triangles(*data);
    return {std::move(data), material, -1, std::nullopt};
}

class SceneBuilder {
public:
    SceneBuilder() {
        scene_.camera.eye = {0, 0, 5};
        scene_.camera.look_at = {0, 0, 0};
    }

    // Appends a named material; returns its index for the shapes above.
    int material(const scene::Material& material) {
        scene_.materials.push_back(material);
        scene_.material_names.push_back("m" + std::to_string(scene_.materials.size() - 1));
        return static_cast<int>(scene_.materials.size()) - 1;
    }

    SceneBuilder& light(scene::Vec3 position, scene::Vec3 color = {1, 1, 1}) {
        scene_.lights.push_back({position, color});
        return *this;
    }

    SceneBuilder& object(scene::Object object) {
        scene_.objects.push_back(std::move(object));
        return *this;
    }

    // A mesh in document order after the objects added so far.
    SceneBuilder& add(scene::Mesh mesh) {
        mesh_positions_.push_back(scene_.objects.size());
        scene_.meshes.push_back(std::move(mesh));
        return *this;
    }

    // Everything else (camera, background, ambient_light, max_depth, size) is set directly.
    scene::Scene& scene() { return scene_; }

    scene::Scene build() const {
        scene::Scene result = scene_;
        result.leaf_paths.clear();
        result.leaf_materials.clear();
        std::size_t next_mesh = 0, element = 0;
        auto number_meshes_before = [&](std::size_t object) {
            for (; next_mesh < mesh_positions_.size() && mesh_positions_[next_mesh] == object; ++next_mesh) {
                scene::Mesh& mesh = result.meshes[next_mesh];
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

private:
    static void number(scene::Object& object, const std::string& path, int inherited, scene::Scene& result) {
        int material = object.material != 0 ? object.material : inherited;
        if (auto* node = std::get_if<scene::Csg>(&object.shape)) {
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

    scene::Scene scene_;
    std::vector<std::size_t> mesh_positions_;  // for each mesh, how many objects come before it
};

}  // namespace twinray::test

// Component-wise EXPECT_NEAR on anything with x, y, z (reference::Vec3): each failure prints the
// measured and the expected component.
#define TWINRAY_EXPECT_VEC_NEAR(actual, expected, tolerance)                   \
    do {                                                                       \
        const auto twinray_a_ = (actual);                                      \
        const auto twinray_e_ = (expected);                                    \
        EXPECT_NEAR(twinray_a_.x, twinray_e_.x, tolerance) << "x of " #actual; \
        EXPECT_NEAR(twinray_a_.y, twinray_e_.y, tolerance) << "y of " #actual; \
        EXPECT_NEAR(twinray_a_.z, twinray_e_.z, tolerance) << "z of " #actual; \
    } while (false)
