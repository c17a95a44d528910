// lattice: a × b × c nodes one unit apart, a sphere at each, a cylinder to each neighbour along
// x, y and z; c along x, a (the smallest) up, b along z.
#include "cli/generate/families.h"
#include "cli/generate/scene_parts.h"

#include <array>
#include <string>

namespace twinray::cli::generate {
namespace {

struct LatticeSides {
    int a, b, c;
};

// Floor + abc spheres + (c − 1)ab + (a − 1)bc + (b − 1)ca cylinders.
std::int64_t lattice_primitives(LatticeSides sides) {
    std::int64_t a = sides.a, b = sides.b, c = sides.c;
    return 1 + 4 * a * b * c - a * b - b * c - c * a;
}

}  // namespace

GeneratedScene write_lattice(int size, std::uint64_t seed, const SceneSink& sink) {
    SplitMix64 random(seed);
    // In increasing count: n³, n²(n + 1), n(n + 1)², (n + 1)³, ...
    LatticeSides sides{1, 1, 1};
    for (int n = 1;; ++n) {
        bool any_within_maximum = false;
        for (LatticeSides candidate :
             {LatticeSides{n, n, n}, LatticeSides{n, n, n + 1}, LatticeSides{n, n + 1, n + 1}}) {
            if (lattice_primitives(candidate) > max_generated_primitives) {
                continue;
            }
            any_within_maximum = true;
            if (nearer(lattice_primitives(candidate), lattice_primitives(sides), size)) {
                sides = candidate;
            }
        }
        if (!any_within_maximum || lattice_primitives({n, n, n}) > size) {
            break;
        }
    }
    constexpr double node_radius = 0.2;
    constexpr double rod_radius = 0.07;
    constexpr double lowest = 0.5;
    const Vec3 first{-(sides.c - 1) / 2.0, lowest, -(sides.b - 1) / 2.0};
    const Vec3 half_extent{(sides.c - 1) / 2.0 + node_radius, (sides.a - 1) / 2.0 + node_radius,
                           (sides.b - 1) / 2.0 + node_radius};
    scene::Scene header =
        framed_scene({0, lowest + (sides.a - 1) / 2.0, 0}, math::length(half_extent), {0.55, 0.45, 0.7});
    const int node = add_material(header, "node", metal(random_color(random), 0.5));
    const std::array<int, 3> rods = {add_material(header, "rod_x", plastic(random_color(random))),
                                     add_material(header, "rod_y", plastic(random_color(random))),
                                     add_material(header, "rod_z", plastic(random_color(random)))};
    SceneTextWriter out(sink, default_decimals);
    out.begin(header);
    write_floor(out);
    for (int j = 0; j < sides.a; ++j) {
        for (int k = 0; k < sides.b; ++k) {
            for (int i = 0; i < sides.c; ++i) {
                Vec3 here = first + Vec3{static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)};
                out.sphere(here, node_radius, node);
                if (i + 1 < sides.c) {
                    out.cylinder(here, here + Vec3{1, 0, 0}, rod_radius, rods[0]);
                }
                if (j + 1 < sides.a) {
                    out.cylinder(here, here + Vec3{0, 1, 0}, rod_radius, rods[1]);
                }
                if (k + 1 < sides.b) {
                    out.cylinder(here, here + Vec3{0, 0, 1}, rod_radius, rods[2]);
                }
            }
        }
    }
    out.end();
    return {out.primitives(), 0,
            std::to_string(sides.c) + " x " + std::to_string(sides.a) + " x " + std::to_string(sides.b) + " nodes"};
}

}  // namespace twinray::cli::generate
