// triangle-soup: `size` triangles of random place, shape and orientation in a cube above the floor, each
// its own three vertices: a mesh with no structure for a BVH to find. Their sizes shrink as the cube's
// side over the cube root of the count, so the cloud keeps its look at any count, as scene::sphere_field's.
#include "cli/generate/families.h"
#include "cli/generate/scene_parts.h"

#include <string>

namespace twinray::cli::generate {
namespace {

constexpr double cube_half_side = 1;
const Vec3 cube_center{0, 1.6, 0};

// The side of the smallest cubic grid with at least `count` cells: the cube root, rounded up, without
// std::cbrt (whose last bit differs between maths libraries).
int cube_side(int count) {
    int side = 0;
    while (static_cast<std::int64_t>(side) * side * side < count) {
        ++side;
    }
    return side;
}

}  // namespace

GeneratedScene write_triangle_soup(int size, std::uint64_t seed, const SceneSink& sink) {
    SplitMix64 random(seed);
    scene::Scene header = framed_scene(cube_center, 1.9, {0.5, 0.4, 0.85});
    const int material = add_material(header, "triangles", plastic(random_color(random)));
    // Corners at most `reach` (at most 0.5) along each axis from a centre within the cube: all 0.1 or more above
    // the floor.
    const double reach = 0.5 / cube_side(size);
    SceneTextWriter out(sink, decimals_resolving(reach));
    out.begin(header);
    write_floor(out);
    const SplitMix64 corners_start = random;
    out.mesh({[&](const PointEmitter& emit) {
                  SplitMix64 corners = corners_start;  // the same corners each time the list is asked for
                  for (int i = 0; i < size; ++i) {
                      const Vec3 center = cube_center + Vec3{corners.uniform(-cube_half_side, cube_half_side),
                                                             corners.uniform(-cube_half_side, cube_half_side),
                                                             corners.uniform(-cube_half_side, cube_half_side)};
                      for (int corner = 0; corner < 3; ++corner) {
                          emit(center + Vec3{corners.uniform(-reach, reach), corners.uniform(-reach, reach),
                                             corners.uniform(-reach, reach)});
                      }
                  }
              },
              [&](const TriangleEmitter& emit) {
                  for (int i = 0; i < size; ++i) {
                      emit(3 * i, 3 * i + 1, 3 * i + 2);
                  }
              },
              {}},
             material);
    out.end();
    return {out.primitives(), out.triangles(), std::to_string(out.triangles()) + " triangles"};
}

}  // namespace twinray::cli::generate
