// Scenes built in code (the tests' scenes, the hand-solved cases of plugin/hand_solved.h), numbered as the loader
// numbers them: leaves 0..n-1 in document order, leaf_paths as "objects[i].children[j]", leaf_materials with CSG
// inheritance applied (a primitive's own material, else that of its nearest CSG ancestor that names one, else 0,
// the default).
#pragma once

#include "scene/scene.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace twinray::scene::builder {

// Material index 0 is the built-in default, so 0 also means "none named" here, as in the loader.
// `normal` of any length: the plane's is made unit.
Object plane(Vec3 normal, double offset, int material = 0);
Object sphere(Vec3 center, double radius, int material = 0);
Object cylinder(Vec3 base, Vec3 cap, double radius, int material = 0);
Object box(Vec3 min, Vec3 max, int material = 0);

// The primitive placed by `to_world`, as the loader places one with a "transform" (scene/placement.h).
Object placed(Object primitive, const Transform& to_world);

// `material` is the node's own named material, inherited by children that name none.
Object csg(CsgOp op, std::vector<Object> children, int material = 0);

// A mesh of the given vertices and triangles, flat unless normals are given; its degenerate triangles found as
// the loader finds them.
Mesh mesh(std::vector<Vec3> vertices, std::vector<std::array<std::uint32_t, 3>> triangles, int material = 0,
          std::vector<Vec3> normals = {});

class SceneBuilder {
public:
    // The camera at (0, 0, 5) looking at the origin.
    SceneBuilder();

    // Appends a named material; returns its index for the shapes above.
    int material(const Material& material);

    SceneBuilder& light(Vec3 position, Vec3 color = {1, 1, 1});
    SceneBuilder& object(Object object);
    // A mesh in document order after the objects added so far.
    SceneBuilder& add(Mesh mesh);

    // Everything else (camera, background, ambient_light, max_depth, size) is set directly.
    Scene& scene() { return scene_; }

    // The scene with its leaves numbered.
    Scene build() const;

private:
    Scene scene_;
    std::vector<std::size_t> mesh_positions_;  // for each mesh, how many objects come before it
};

}  // namespace twinray::scene::builder
