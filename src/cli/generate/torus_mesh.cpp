// torus-mesh: a ring of radius 1 and tube radius 1/3, tilted (its axis at the angle of cosine 4/5 to the
// vertical, exact numbers) to rest on the floor: 3n segments around the ring and n around the tube (so
// the quads on its outside are about square), both wrapped onto shared vertices; smooth, its normals the
// exact directions from the tube's centre line.
#include "cli/generate/families.h"
#include "cli/generate/mesh_parts.h"
#include "cli/generate/scene_parts.h"

#include <numbers>
#include <string>

namespace twinray::cli::generate {
namespace {

constexpr double ring_radius = 1;
constexpr double tube_radius = 1.0 / 3;
constexpr double tilt_cosine = 0.8;
constexpr double tilt_sine = 0.6;

std::int64_t torus_triangles(int tube_segments) {
    return 6 * std::int64_t{tube_segments} * tube_segments;
}

Vec3 tilted(Vec3 v) {
    return {v.x, tilt_cosine * v.y - tilt_sine * v.z, tilt_sine * v.y + tilt_cosine * v.z};
}

struct Torus {
    int tube_segments;
    int ring_segments = 3 * tube_segments;

    // Rows go around the ring, columns around the tube: that order makes grid_triangles' front the outside.
    int vertex(int row, int column) const { return row % ring_segments * tube_segments + column % tube_segments; }

    // Each vertex's point on the tube's centre line and its direction from it, untilted.
    template <typename Emit>
    void each_vertex(Emit emit) const {
        for (int row = 0; row < ring_segments; ++row) {
            SineCosine around = sine_cosine(2 * std::numbers::pi * row / ring_segments);
            for (int column = 0; column < tube_segments; ++column) {
                SineCosine tube = sine_cosine(2 * std::numbers::pi * column / tube_segments);
                emit(ring_radius * Vec3{around.cosine, 0, around.sine},
                     Vec3{tube.cosine * around.cosine, tube.sine, tube.cosine * around.sine});
            }
        }
    }
};

}  // namespace

GeneratedScene write_torus_mesh(int size, std::uint64_t seed, const SceneSink& sink) {
    SplitMix64 random(seed);
    const Torus torus{nearest_parameter(3, size, torus_triangles)};
    // The tilted ring's lowest point is tilt_sine below its centre, the tube's surface tube_radius lower.
    const Vec3 center{0, tilt_sine * ring_radius + tube_radius, 0};
    scene::Scene header = framed_scene(center, ring_radius + tube_radius, {0.3, 0.75, 0.9});
    const int material = add_material(header, "torus", metal(random_color(random), 0.35));
    // The shortest edges, along the inside of the ring, are 2·(1 − 1/3)·sin(π/ring_segments)
    // ≥ 8/3 / ring_segments long.
    SceneTextWriter out(sink, decimals_resolving(8.0 / 3 / torus.ring_segments));
    out.begin(header);
    write_floor(out);
    out.mesh({[&](const PointEmitter& emit) {
                  torus.each_vertex(
                      [&](Vec3 on_ring, Vec3 outward) { emit(center + tilted(on_ring + tube_radius * outward)); });
              },
              [&](const TriangleEmitter& emit) {
                  grid_triangles(
                      torus.ring_segments, torus.tube_segments,
                      [&](int row, int column) { return torus.vertex(row, column); }, emit);
              },
              [&](const PointEmitter& emit) { torus.each_vertex([&](Vec3, Vec3 outward) { emit(tilted(outward)); }); }},
             material);
    out.end();
    return {out.primitives(), out.triangles(),
            std::to_string(out.triangles()) + " triangles: " + std::to_string(torus.ring_segments) + " x " +
                std::to_string(torus.tube_segments) + " segments"};
}

}  // namespace twinray::cli::generate
