// tetra: Eric Haines's SPD "tetra", the Sierpinski tetrahedron: a regular tetrahedron replaced, `depth`
// times over, by the four of half its size at its corners, 4^depth tetrahedra of four triangles. Each is
// its own closed shell of four vertices: neighbours touch at a corner, and sharing that vertex would
// join two shells at one point (a mesh that is not a surface there) for no saving worth it.
#include "cli/generate/families.h"
#include "cli/generate/scene_parts.h"

#include <array>
#include <cmath>
#include <string>

namespace twinray::cli::generate {
namespace {

using Tetrahedron = std::array<Vec3, 4>;

// The base floats this far above the floor: a face in the floor's own plane would leave each tracer to
// choose between two coincident surfaces.
constexpr double floor_clearance = 0.05;

// The apex, then the base's corners counter-clockwise seen from above, at a distance 1 from the axis: the
// edges are √3 long and the apex √2 above the base. sqrt is correctly rounded everywhere.
Tetrahedron root_tetrahedron() {
    const double half_root3 = std::sqrt(3.0) / 2;
    return {{{0, floor_clearance + std::sqrt(2.0), 0},
             {0, floor_clearance, 1},
             {-half_root3, floor_clearance, -0.5},
             {half_root3, floor_clearance, -0.5}}};
}

// With the corners in root_tetrahedron's order, the face opposite each corner counter-clockwise seen from
// outside; every smaller tetrahedron is a copy at half the scale, so the same order holds for it.
constexpr std::array<std::array<int, 3>, 4> outward_faces = {{{1, 2, 3}, {0, 2, 1}, {0, 3, 2}, {0, 1, 3}}};

void each_tetrahedron(const Tetrahedron& tetrahedron, int levels, const std::function<void(const Tetrahedron&)>& emit) {
    if (levels == 0) {
        emit(tetrahedron);
        return;
    }
    for (const Vec3& corner : tetrahedron) {
        Tetrahedron part;
        for (std::size_t i = 0; i < part.size(); ++i) {
            part[i] = 0.5 * (corner + tetrahedron[i]);
        }
        each_tetrahedron(part, levels - 1, emit);
    }
}

}  // namespace

GeneratedScene write_tetra(int size, std::uint64_t seed, const SceneSink& sink) {
    SplitMix64 random(seed);
    auto tetrahedra_at = [](int depth) { return std::int64_t{1} << (2 * depth); };
    int depth = 0;
    while (4 * tetrahedra_at(depth + 1) <= size) {
        ++depth;
    }
    const std::int64_t tetrahedra = tetrahedra_at(depth);
    // The centroid is a quarter of the height above the base, and the corners 3/4·√2 from it.
    const Vec3 center{0, floor_clearance + std::sqrt(2.0) / 4, 0};
    scene::Scene header = framed_scene(center, 1.1, {0.55, 0.5, 0.85});
    const int material = add_material(header, "tetra", plastic(random_color(random)));
    // The edges of the smallest tetrahedra are √3/2^depth long.
    SceneTextWriter out(sink, decimals_resolving(std::sqrt(3.0) / static_cast<double>(std::int64_t{1} << depth)));
    out.begin(header);
    write_floor(out);
    out.mesh({[&](const PointEmitter& emit) {
                  each_tetrahedron(root_tetrahedron(), depth, [&](const Tetrahedron& tetrahedron) {
                      for (const Vec3& corner : tetrahedron) {
                          emit(corner);
                      }
                  });
              },
              [&](const TriangleEmitter& emit) {
                  for (std::int64_t t = 0; t < tetrahedra; ++t) {
                      const int first = static_cast<int>(4 * t);
                      for (const auto& [a, b, c] : outward_faces) {
                          emit(first + a, first + b, first + c);
                      }
                  }
              },
              {}},
             material);
    out.end();
    return {out.primitives(), out.triangles(),
            std::to_string(out.triangles()) + " triangles: depth " + std::to_string(depth) + ", " +
                std::to_string(tetrahedra) + " tetrahedra"};
}

}  // namespace twinray::cli::generate
