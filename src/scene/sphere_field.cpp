#include "scene/sphere_field.h"

#include "scene/portable_random.h"

#include <cmath>
#include <string>

namespace twinray::scene {

Scene sphere_field(int count, std::uint64_t seed) {
    constexpr double half_side = 10;
    SplitMix64 random(seed);
    Scene scene;
    scene.width = 320;
    scene.height = 240;
    scene.camera = {{0, 0, 3.2 * half_side}, {0, 0, 0}, {0, 1, 0}, 50};
    scene.background = {0.1, 0.1, 0.15};
    scene.ambient_light = {1, 1, 1};
    scene.max_depth = 1;
    scene.lights.push_back({{2 * half_side, 3 * half_side, 3 * half_side}, {1, 1, 1}});
    constexpr int palette = 4;
    for (int i = 0; i < palette; ++i) {
        Material material;
        material.color = {random.uniform(0.2, 1), random.uniform(0.2, 1), random.uniform(0.2, 1)};
        material.phong = 0.4;
        scene.materials.push_back(material);
        scene.material_names.push_back("palette" + std::to_string(i));
    }
    // Radii shrink as the cube root of the count, so the spheres fill the same share of the cube's
    // volume at any count (about 5%): the picture stays a cloud of spheres, never empty nor a wall.
    double radius = 0.6 * half_side / std::cbrt(static_cast<double>(count));
    for (int i = 0; i < count; ++i) {
        Object object;
        Vec3 center = {random.uniform(-half_side, half_side), random.uniform(-half_side, half_side),
                       random.uniform(-half_side, half_side)};
        object.shape = Sphere{center, radius * random.uniform(0.5, 1)};
        object.material = 1 + static_cast<int>(random.next() % palette);
        object.leaf = i;
        scene.objects.push_back(object);
        scene.leaf_paths.push_back("objects[" + std::to_string(i) + "]");
        scene.leaf_materials.push_back(object.material);
    }
    return scene;
}

}  // namespace twinray::scene
