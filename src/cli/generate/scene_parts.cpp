#include "cli/generate/scene_parts.h"

#include "cli/generate_scene.h"

#include <cstdlib>
#include <stdexcept>
#include <utility>

namespace twinray::cli::generate {
namespace {

// Every family's picture: 4:3, 50° across. At that, the vertical half-angle's tangent is
// tan 25° · 3/4 = 0.350 and its sine 0.330, so a bounding sphere of radius R fills the height from
// 3.03 R away. A constant rather than std::tan, whose last bit differs between maths libraries.
constexpr int image_width = 320;
constexpr int image_height = 240;
constexpr double fov_deg = 50;
constexpr double distance_per_radius = 3.2;

// The finest grid SceneTextWriter writes.
constexpr int max_decimals = 9;

}  // namespace

int decimals_resolving(double smallest_feature) {
    int decimals = default_decimals;
    double steps = smallest_feature;
    for (int d = 0; d < decimals; ++d) {
        steps *= 10;
    }
    for (; steps < 1000; steps *= 10) {
        if (++decimals > max_decimals) {
            throw std::logic_error("generated feature too small for the grid: " + std::to_string(smallest_feature));
        }
    }
    return decimals;
}

scene::Scene framed_scene(Vec3 center, double radius, Vec3 view_from) {
    scene::Scene scene;
    scene.width = image_width;
    scene.height = image_height;
    scene.camera = {center + distance_per_radius * radius * math::normalize(view_from), center, {0, 1, 0}, fov_deg};
    scene.background = {0.32, 0.4, 0.55};
    scene.max_depth = 5;
    scene.lights.push_back({center + radius * Vec3{-1.5, 3, 2}, {0.75, 0.75, 0.75}});
    scene.lights.push_back({center + radius * Vec3{2.5, 2, 0.5}, {0.35, 0.35, 0.4}});
    scene::Material floor;
    floor.color = {0.72, 0.72, 0.68};
    floor.diffuse = 0.7;
    scene.materials.push_back(floor);
    scene.material_names.push_back("floor");
    return scene;
}

void write_floor(SceneTextWriter& out) {
    out.plane({0, 1, 0}, 0, floor_material);
}

int add_material(scene::Scene& scene, std::string name, const scene::Material& material) {
    scene.materials.push_back(material);
    scene.material_names.push_back(std::move(name));
    return static_cast<int>(scene.materials.size()) - 1;
}

Vec3 random_color(SplitMix64& random) {
    // A braced list evaluates its elements in order, so the three draws always land on r, g, b.
    return {random.uniform(0.15, 0.95), random.uniform(0.15, 0.95), random.uniform(0.15, 0.95)};
}

scene::Material plastic(Vec3 color) {
    scene::Material material;
    material.color = color;
    material.diffuse = 0.75;
    material.phong = 0.5;
    material.phong_size = 40;
    return material;
}

scene::Material metal(Vec3 color, double reflection) {
    scene::Material material;
    material.color = color;
    material.ambient = 0.05;
    material.diffuse = 0.45;
    material.phong = 0.7;
    material.phong_size = 60;
    material.reflection = reflection;
    return material;
}

scene::Material glass() {
    scene::Material material;
    material.ambient = 0;
    material.diffuse = 0.05;
    material.phong = 0.8;
    material.phong_size = 120;
    material.reflection = 0.1;
    material.transmission = 0.85;
    material.ior = 1.5;
    return material;
}

void add_palette(scene::Scene& scene, int count, SplitMix64& random) {
    for (int i = 0; i < count; ++i) {
        Vec3 color = random_color(random);
        add_material(scene, "color" + std::to_string(i), i % 3 == 2 ? metal(color, 0.4) : plastic(color));
    }
}

int palette_material(SplitMix64& random, int palette_size) {
    return floor_material + 1 + static_cast<int>(random.next() % static_cast<std::uint64_t>(palette_size));
}

bool nearer(std::int64_t candidate, std::int64_t best, int size) {
    return std::abs(candidate - size) < std::abs(best - size);
}

int nearest_parameter(int first, int size, const std::function<std::int64_t(int)>& count) {
    int best = first;
    // Past the first count above `size`, every later one is farther.
    for (int n = first + 1; count(n - 1) <= size && count(n) <= max_generated_primitives; ++n) {
        if (nearer(count(n), count(best), size)) {
            best = n;
        }
    }
    return best;
}

int square_side(int count) {
    int side = 0;
    while (static_cast<std::int64_t>(side) * side < count) {
        ++side;
    }
    return side;
}

}  // namespace twinray::cli::generate
