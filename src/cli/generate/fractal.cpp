// fractal: Eric Haines's sphereflake (SPD "balls"): a sphere and, on every sphere of one level, nine
// children of a third of its radius, touching it; reflective, on a floor.
#include "cli/generate/families.h"
#include "cli/generate/scene_parts.h"

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace twinray::cli::generate {
namespace {

// Floor + (9^(depth+1) − 1) / 8 spheres.
std::int64_t fractal_primitives(int depth) {
    std::int64_t spheres = 0;
    std::int64_t level = 1;
    for (int d = 0; d <= depth; ++d) {
        spheres += level;
        level *= 9;
    }
    return 1 + spheres;
}

// A child's direction in its parent's frame: u and v across the parent's axis, w along it (away from
// the grandparent). Six around the equator 60° apart and three at 60° of latitude between them, so
// that no two children touch: cosines and sines of multiples of 30° only, all from √3/2, so no library
// trigonometry (whose last bit varies) is needed.
struct ChildDirection {
    double u, v, w;
};

std::array<ChildDirection, 9> child_directions() {
    const double s = std::sqrt(3.0) / 2;  // sqrt is correctly rounded everywhere
    return {{{1, 0, 0},
             {0.5, s, 0},
             {-0.5, s, 0},
             {-1, 0, 0},
             {-0.5, -s, 0},
             {0.5, -s, 0},
             {0.5 * s, 0.25, s},
             {-0.5 * s, 0.25, s},
             {0, -0.5, s}}};
}

struct Sphereflake {
    SceneTextWriter& out;
    int depth;
    std::vector<int> level_materials;
    std::array<ChildDirection, 9> directions = child_directions();

    void grow(Vec3 center, double radius, Vec3 axis, int level) {
        out.sphere(center, radius, level_materials[static_cast<std::size_t>(level)]);
        if (level == depth) {
            return;
        }
        Vec3 helper = std::fabs(axis.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
        Vec3 u = math::normalize(math::cross(helper, axis));
        Vec3 v = math::cross(axis, u);
        double child_radius = radius / 3;
        for (const ChildDirection& direction : directions) {
            Vec3 child_axis = direction.u * u + direction.v * v + direction.w * axis;
            grow(center + (radius + child_radius) * child_axis, child_radius, child_axis, level + 1);
        }
    }
};

}  // namespace

GeneratedScene write_fractal(int size, std::uint64_t seed, const SceneSink& sink) {
    SplitMix64 random(seed);
    const int depth = nearest_parameter(0, size, fractal_primitives);
    // The root, of radius 1, rests on the floor; every level reaches at most 2/3 of its parent's
    // radius beyond it, so the whole flake lies within 2 of the root's centre and above the floor.
    const Vec3 root{0, 1, 0};
    scene::Scene header = framed_scene(root, 2, {0.6, 0.35, 0.75});
    std::vector<int> level_materials;
    for (int level = 0; level <= depth; ++level) {
        level_materials.push_back(
            add_material(header, "level" + std::to_string(level), metal(random_color(random), 0.45)));
    }
    // The smallest sphere's radius is 3^-depth.
    std::int64_t thirds = 1;
    for (int d = 0; d < depth; ++d) {
        thirds *= 3;
    }
    SceneTextWriter out(sink, decimals_resolving(1.0 / static_cast<double>(thirds)));
    out.begin(header);
    write_floor(out);
    Sphereflake flake{out, depth, level_materials};
    flake.grow(root, 1, {0, 1, 0}, 0);
    out.end();
    return {out.primitives(), 0, "depth " + std::to_string(depth)};
}

}  // namespace twinray::cli::generate
