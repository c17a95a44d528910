// sphere-mesh: a UV sphere of radius 1 resting on the floor: `bands` bands of latitude from pole to pole,
// twice as many slices around (so the quads at the equator are square), each pole one vertex and a fan
// of triangles; smooth, its normals the exact directions from the centre.
#include "cli/generate/families.h"
#include "cli/generate/mesh_parts.h"
#include "cli/generate/scene_parts.h"

#include <numbers>
#include <string>

namespace twinray::cli::generate {
namespace {

// Two fans of 2·bands and (bands − 2) rows of 2·bands quads.
std::int64_t sphere_triangles(int bands) {
    return 4 * std::int64_t{bands} * (bands - 1);
}

struct UvSphere {
    int bands;
    int slices = 2 * bands;

    // The north pole 0, the rings of latitude 1 .. bands − 1 of `slices` vertices each, the south pole.
    int vertex(int ring, int slice) const {
        if (ring == 0) {
            return 0;
        }
        if (ring == bands) {
            return 1 + (bands - 1) * slices;
        }
        return 1 + (ring - 1) * slices + slice % slices;
    }
    // Rows run south and columns east, which makes grid_triangles' front the outside.
    Vec3 direction(int ring, int slice) const {
        SineCosine latitude = sine_cosine(std::numbers::pi * ring / bands);
        SineCosine longitude = sine_cosine(2 * std::numbers::pi * slice / slices);
        return {latitude.sine * longitude.cosine, latitude.cosine, latitude.sine * longitude.sine};
    }
    void each_direction(const PointEmitter& emit) const {
        for (int ring = 0; ring <= bands; ++ring) {
            const int ring_vertices = ring == 0 || ring == bands ? 1 : slices;
            for (int slice = 0; slice < ring_vertices; ++slice) {
                emit(direction(ring, slice));
            }
        }
    }
};

}  // namespace

GeneratedScene write_sphere_mesh(int size, std::uint64_t seed, const SceneSink& sink) {
    SplitMix64 random(seed);
    const UvSphere sphere{nearest_parameter(2, size, sphere_triangles)};
    const Vec3 center{0, 1, 0};
    scene::Scene header = framed_scene(center, 1.2, {0.6, 0.45, 0.8});
    const int material = add_material(header, "sphere", plastic(random_color(random)));
    // The shortest edges, between the vertices of the rings next to a pole, are 2·sin(π/bands)·sin(π/slices)
    // ≥ 4/bands² long.
    SceneTextWriter out(sink, decimals_resolving(4 / (static_cast<double>(sphere.bands) * sphere.bands)));
    out.begin(header);
    write_floor(out);
    out.mesh({[&](const PointEmitter& emit) { sphere.each_direction([&](Vec3 d) { emit(center + d); }); },
              [&](const TriangleEmitter& emit) {
                  grid_triangles(
                      sphere.bands, sphere.slices, [&](int ring, int slice) { return sphere.vertex(ring, slice); },
                      emit);
              },
              [&](const PointEmitter& emit) { sphere.each_direction(emit); }},
             material);
    out.end();
    return {out.primitives(), out.triangles(),
            std::to_string(out.triangles()) + " triangles: " + std::to_string(sphere.bands) + " bands x " +
                std::to_string(sphere.slices) + " slices"};
}

}  // namespace twinray::cli::generate
