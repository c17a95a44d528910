// sombrero: the height field y = base + amplitude·sin(u)/u, u = ripple·r (r the distance from the axis), over
// a square above the floor, as SPD's sombrero: an open surface of n × n quads, each cut along the same
// diagonal, its front facing up; smooth, its normals from the field's exact gradient.
#include "cli/generate/families.h"
#include "cli/generate/mesh_parts.h"
#include "cli/generate/scene_parts.h"

#include <cmath>
#include <string>

namespace twinray::cli::generate {
namespace {

constexpr double half_width = 3;
constexpr double ripple = 3;  // crests 2π/3 apart, three from the axis to the square's edge
constexpr double amplitude = 1.2;
// sin(u)/u is at least −0.22, so the surface stays above 0.23.
constexpr double base_height = 0.5;

std::int64_t sombrero_triangles(int quads_per_side) {
    return 2 * std::int64_t{quads_per_side} * quads_per_side;
}

struct HeightField {
    SquareGrid grid;

    template <typename Emit>
    void each_vertex(Emit emit) const {
        for (int row = 0; row <= grid.quads_per_side; ++row) {
            for (int column = 0; column <= grid.quads_per_side; ++column) {
                const double x = grid.coordinate(row), z = grid.coordinate(column);
                const double u = ripple * std::sqrt(x * x + z * z);
                const SineCosine wave = sine_cosine(u);
                const double height = u == 0 ? 1 : wave.sine / u;
                // d(sin u / u)/du / r = ripple² · (u·cos u − sin u)/u³, which tends to −ripple²/3 on the axis.
                const double slope_per_r =
                    u == 0 ? -ripple * ripple / 3 : ripple * ripple * (u * wave.cosine - wave.sine) / (u * u * u);
                const double slope_x = amplitude * slope_per_r * x, slope_z = amplitude * slope_per_r * z;
                emit(Vec3{x, base_height + amplitude * height, z}, math::normalize(Vec3{-slope_x, 1, -slope_z}));
            }
        }
    }
};

}  // namespace

GeneratedScene write_sombrero(int size, std::uint64_t seed, const SceneSink& sink) {
    SplitMix64 random(seed);
    const HeightField field{{nearest_parameter(1, size, sombrero_triangles), half_width}};
    scene::Scene header = framed_scene({0, base_height + 0.4, 0}, half_width + 0.3, {0.45, 0.8, 0.85});
    const int material = add_material(header, "sombrero", plastic(random_color(random)));
    SceneTextWriter out(sink, decimals_resolving(2 * half_width / field.grid.quads_per_side));
    out.begin(header);
    write_floor(out);
    out.mesh({[&](const PointEmitter& emit) { field.each_vertex([&](Vec3 point, Vec3) { emit(point); }); },
              [&](const TriangleEmitter& emit) { field.grid.triangles(emit); },
              [&](const PointEmitter& emit) { field.each_vertex([&](Vec3, Vec3 normal) { emit(normal); }); }},
             material);
    out.end();
    return {out.primitives(), out.triangles(),
            std::to_string(out.triangles()) + " triangles: " + std::to_string(field.grid.quads_per_side) + " x " +
                std::to_string(field.grid.quads_per_side) + " quads"};
}

}  // namespace twinray::cli::generate
