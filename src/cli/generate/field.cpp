// field: spheres (some floating), boxes and cylinders (standing or lying) of varied sizes and
// materials, one in each cell of a square grid of 2 × 2 cells on the floor, placed at random within it
// so that no two overlap.
#include "cli/generate/families.h"
#include "cli/generate/scene_parts.h"

#include <cmath>
#include <string>

namespace twinray::cli::generate {
namespace {

constexpr double field_cell = 2;
constexpr int field_palette = 6;

// One object within the cell of centre (x, 0, z), which it never leaves: a half-width h is jittered by
// at most 1 − h.
void write_field_object(SceneTextWriter& out, SplitMix64& random, double x, double z, int material) {
    const double half_cell = field_cell / 2;
    std::uint64_t kind = random.next() % 8;
    if (kind < 6) {
        double size = random.uniform(0, 1);
        double radius = 0.2 + 0.7 * size * size;  // mostly small, a few large
        double dx = random.uniform(-(half_cell - radius), half_cell - radius);
        double dz = random.uniform(-(half_cell - radius), half_cell - radius);
        double lift = random.next() % 8 == 0 ? random.uniform(0.3, 2) : 0;
        out.sphere({x + dx, radius + lift, z + dz}, radius, material);
    } else if (kind == 6) {
        double half_x = random.uniform(0.2, 0.7);
        double half_z = random.uniform(0.2, 0.7);
        double height = random.uniform(0.3, 1.6);
        double dx = random.uniform(-(half_cell - half_x), half_cell - half_x);
        double dz = random.uniform(-(half_cell - half_z), half_cell - half_z);
        out.box({x + dx - half_x, -sink_depth, z + dz - half_z}, {x + dx + half_x, height, z + dz + half_z}, material);
    } else {
        double radius = random.uniform(0.15, 0.5);
        if (random.next() % 2 == 0) {
            double height = random.uniform(0.4, 2);
            double dx = random.uniform(-(half_cell - radius), half_cell - radius);
            double dz = random.uniform(-(half_cell - radius), half_cell - radius);
            out.cylinder({x + dx, -sink_depth, z + dz}, {x + dx, height, z + dz}, radius, material);
        } else {
            // Lying in a random direction, its ends within the cell: half its length + radius <= half_cell.
            double along_x = 0, along_z = 0;
            do {
                along_x = random.uniform(-1, 1);
                along_z = random.uniform(-1, 1);
            } while (along_x * along_x + along_z * along_z < 0.01);
            Vec3 axis = math::normalize(Vec3{along_x, 0, along_z});
            double half_length = random.uniform(0.2, half_cell - radius);
            Vec3 center{x, radius, z};
            out.cylinder(center - half_length * axis, center + half_length * axis, radius, material);
        }
    }
}

}  // namespace

GeneratedScene write_field(int size, std::uint64_t seed, const SceneSink& sink) {
    SplitMix64 random(seed);
    const int objects = size - 1;
    const int side = square_side(objects);
    const double half_side = side * field_cell / 2;
    scene::Scene header = framed_scene({0, 0.5, 0}, std::fmax(2, half_side), {0.5, 0.85, 0.9});
    add_palette(header, field_palette, random);
    add_material(header, "mirror", metal({0.9, 0.92, 0.95}, 0.8));
    add_material(header, "glass", glass());
    SceneTextWriter out(sink, default_decimals);
    out.begin(header);
    write_floor(out);
    for (int i = 0; i < objects; ++i) {
        double x = -half_side + field_cell * (i % side + 0.5);
        double z = -half_side + field_cell * (i / side + 0.5);
        int material = palette_material(random, field_palette + 2);  // the palette, the mirror or the glass
        write_field_object(out, random, x, z, material);
    }
    out.end();
    return {out.primitives(), 0,
            std::to_string(objects) + " objects in " + std::to_string(side) + " x " + std::to_string(side) + " cells"};
}

}  // namespace twinray::cli::generate
