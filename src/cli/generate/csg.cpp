// csg: CSG objects of six kinds, one in each 3 × 3 cell of a square grid on the floor, each of
// half-width h (seeded) around `center`, its lowest point sink_depth below the floor.
#include "cli/generate/families.h"
#include "cli/generate/scene_parts.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace twinray::cli::generate {
namespace {

constexpr double csg_cell = 3;
constexpr int csg_palette = 6;

// Cylinders through `center` along x, y and z: the rods that pierce, cross or make up an object.
void write_three_rods(SceneTextWriter& out, Vec3 center, double half_length, double radius, int material) {
    for (Vec3 axis : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}) {
        out.cylinder(center - half_length * axis, center + half_length * axis, radius, material);
    }
}

void write_cube(SceneTextWriter& out, Vec3 center, double half_width) {
    out.box(center - Vec3{half_width, half_width, half_width}, center + Vec3{half_width, half_width, half_width});
}

struct CsgKind {
    int primitives;
    // `center` is the object's centre, h above the floor less the sink; `cutter` the material of
    // what a difference removes (its surfaces line the cut).
    void (*write)(SceneTextWriter& out, Vec3 center, double h, int material, int cutter);
};

const std::array<CsgKind, 6> csg_kinds = {{
    // A block with a bowl cut in its top.
    {2,
     [](SceneTextWriter& out, Vec3 center, double h, int material, int cutter) {
         out.begin_csg("difference", material);
         out.box(center - Vec3{h, h, h}, center + Vec3{h, 0.5 * h, h});
         out.sphere(center + Vec3{0, 0.5 * h, 0}, 0.8 * h, cutter);
         out.end_csg();
     }},
    // A cube with rounded edges.
    {2,
     [](SceneTextWriter& out, Vec3 center, double h, int material, int) {
         out.begin_csg("intersection", material);
         write_cube(out, center, h);
         out.sphere(center, 1.3 * h);
         out.end_csg();
     }},
    // The Steinmetz solid of three cylinders.
    {3,
     [](SceneTextWriter& out, Vec3 center, double h, int material, int) {
         out.begin_csg("intersection", material);
         write_three_rods(out, center, 1.2 * h, h, 0);
         out.end_csg();
     }},
    // A cube pierced through every face.
    {4,
     [](SceneTextWriter& out, Vec3 center, double h, int material, int cutter) {
         out.begin_csg("difference", material);
         write_cube(out, center, h);
         write_three_rods(out, center, 1.2 * h, 0.5 * h, cutter);
         out.end_csg();
     }},
    // A jack: a ball on three crossed rods.
    {4,
     [](SceneTextWriter& out, Vec3 center, double h, int material, int) {
         out.begin_csg("union", material);
         out.sphere(center, 0.6 * h);
         write_three_rods(out, center, h, 0.25 * h, 0);
         out.end_csg();
     }},
    // The textbook CSG tree: (cube ∩ ball) − three rods.
    {5,
     [](SceneTextWriter& out, Vec3 center, double h, int material, int cutter) {
         out.begin_csg("difference", material);
         out.begin_csg("intersection", 0);
         write_cube(out, center, h);
         out.sphere(center, 1.35 * h);
         out.end_csg();
         write_three_rods(out, center, 1.3 * h, 0.55 * h, cutter);
         out.end_csg();
     }},
}};

// The kind of the next object, given the primitives still to write: one that fits and does not leave
// exactly one over (no CSG object has a single primitive). With one left (a size of 2), a kind of two.
const CsgKind& next_csg_kind(SplitMix64& choices, std::int64_t remaining) {
    std::array<const CsgKind*, csg_kinds.size()> eligible{};
    std::size_t count = 0;
    for (const CsgKind& kind : csg_kinds) {
        if (kind.primitives <= std::max<std::int64_t>(remaining, 2) && remaining - kind.primitives != 1) {
            eligible[count++] = &kind;
        }
    }
    return *eligible[choices.next() % count];
}

}  // namespace

GeneratedScene write_csg(int size, std::uint64_t seed, const SceneSink& sink) {
    // The kinds come from a generator of their own, run once to count the objects (the grid's size)
    // and again, from the same seed, to write them; sizes, places and colours from another.
    int objects = 0;
    {
        SplitMix64 choices(seed);
        for (std::int64_t remaining = size - 1; remaining > 0; ++objects) {
            remaining -= next_csg_kind(choices, remaining).primitives;
        }
    }
    const int side = square_side(objects);
    const double half_side = side * csg_cell / 2;
    SplitMix64 random(~seed);
    scene::Scene header = framed_scene({0, 0.8, 0}, std::fmax(2.5, half_side), {0.45, 0.7, 0.9});
    add_palette(header, csg_palette, random);
    SceneTextWriter out(sink, default_decimals);
    out.begin(header);
    write_floor(out);
    SplitMix64 choices(seed);
    std::int64_t remaining = size - 1;
    for (int i = 0; remaining > 0; ++i) {
        const CsgKind& kind = next_csg_kind(choices, remaining);
        remaining -= kind.primitives;
        double h = random.uniform(0.55, 1);
        // Every kind reaches at most 1.3 h from its centre across the floor.
        double reach = 1.3 * h;
        double dx = random.uniform(-(csg_cell / 2 - reach), csg_cell / 2 - reach);
        double dz = random.uniform(-(csg_cell / 2 - reach), csg_cell / 2 - reach);
        int material = palette_material(random, csg_palette);
        int cutter = palette_material(random, csg_palette);
        Vec3 center{-half_side + csg_cell * (i % side + 0.5) + dx, h - sink_depth,
                    -half_side + csg_cell * (i / side + 0.5) + dz};
        kind.write(out, center, h, material, cutter);
    }
    out.end();
    return {
        out.primitives(), 0,
        std::to_string(objects) + " CSG objects in " + std::to_string(side) + " x " + std::to_string(side) + " cells"};
}

}  // namespace twinray::cli::generate
