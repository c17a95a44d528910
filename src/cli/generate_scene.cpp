#include "cli/generate_scene.h"

#include "scene/portable_random.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <utility>

namespace twinray::cli {
namespace {

// Every family's picture: 4:3, 50° across. At that, the vertical half-angle's tangent is
// tan 25° · 3/4 = 0.350 and its sine 0.330, so a bounding sphere of radius R fills the height from
// 3.03 R away. A constant rather than std::tan, whose last bit differs between maths libraries.
constexpr int image_width = 320;
constexpr int image_height = 240;
constexpr double fov_deg = 50;
constexpr double distance_per_radius = 3.2;

// Boxes and cylinders that stand on the floor go this far into it: a face in the floor's own plane
// would leave each tracer to choose between two coincident surfaces.
constexpr double sink_depth = 0.05;

// Numbers with this many decimals. The smallest sizes of field, lattice and csg are 0.07 to 0.15 (the
// lattice's rods, written exactly, a field cylinder, the jack's rods): rounding moves none of them by
// more than 0.4%. The fractal's spheres shrink with its depth (fractal_decimals).
constexpr int default_decimals = 3;

// A scene without objects, its camera looking at the sphere (center, radius) around everything from
// the direction `view_from`, two lights above it and the floor's material (index 1).
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

constexpr int floor_material = 1;

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

// Materials 2 .. 1 + count, each plastic or (one in three) metal of a seeded colour.
void add_palette(scene::Scene& scene, int count, SplitMix64& random) {
    for (int i = 0; i < count; ++i) {
        Vec3 color = random_color(random);
        add_material(scene, "color" + std::to_string(i), i % 3 == 2 ? metal(color, 0.4) : plastic(color));
    }
}

int palette_material(SplitMix64& random, int palette_size) {
    return floor_material + 1 + static_cast<int>(random.next() % static_cast<std::uint64_t>(palette_size));
}

// Whether `candidate` primitives are nearer `size` than `best` (ties to the smaller, listed first).
bool nearer(std::int64_t candidate, std::int64_t best, int size) {
    return std::abs(candidate - size) < std::abs(best - size);
}

// The side of the smallest square grid with at least `count` cells.
int square_side(int count) {
    int side = 0;
    while (static_cast<std::int64_t>(side) * side < count) {
        ++side;
    }
    return side;
}

void write_floor(SceneTextWriter& out) {
    out.plane({0, 1, 0}, 0, floor_material);
}

// --- fractal: Eric Haines's sphereflake (SPD "balls"): a sphere and, on every sphere of one level,
// nine children of a third of its radius, touching it; reflective, on a floor.

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

// The smallest sphere's radius is 3^-depth: decimals enough for a thousand steps across it.
int fractal_decimals(int depth) {
    std::int64_t thirds = 1;
    for (int d = 0; d < depth; ++d) {
        thirds *= 3;
    }
    int decimals = default_decimals;
    for (std::int64_t tens = 1; tens < thirds; tens *= 10) {
        ++decimals;
    }
    return decimals;
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

GeneratedScene write_fractal(int size, std::uint64_t seed, const TextSink& sink) {
    SplitMix64 random(seed);
    int depth = 0;
    for (int d = 1; fractal_primitives(d) <= max_generated_primitives; ++d) {
        if (nearer(fractal_primitives(d), fractal_primitives(depth), size)) {
            depth = d;
        }
    }
    // The root, of radius 1, rests on the floor; every level reaches at most 2/3 of its parent's
    // radius beyond it, so the whole flake lies within 2 of the root's centre and above the floor.
    const Vec3 root{0, 1, 0};
    scene::Scene header = framed_scene(root, 2, {0.6, 0.35, 0.75});
    std::vector<int> level_materials;
    for (int level = 0; level <= depth; ++level) {
        level_materials.push_back(
            add_material(header, "level" + std::to_string(level), metal(random_color(random), 0.45)));
    }
    SceneTextWriter out(sink, fractal_decimals(depth));
    out.begin(header);
    write_floor(out);
    Sphereflake flake{out, depth, level_materials};
    flake.grow(root, 1, {0, 1, 0}, 0);
    out.end();
    return {out.primitives(), "depth " + std::to_string(depth)};
}

// --- field: spheres (some floating), boxes and cylinders (standing or lying) of varied sizes and
// materials, one in each cell of a square grid of 2 × 2 cells on the floor, placed at random within it
// so that no two overlap.

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

GeneratedScene write_field(int size, std::uint64_t seed, const TextSink& sink) {
    SplitMix64 random(seed);
    const int objects = size - 1;
    const int side = square_side(objects);
    const double half_side = side * field_cell / 2;
    scene::Scene header = framed_scene({0, 0.5, 0}, std::fmax(2, half_side), {0.5, 0.85, 0.9});
    add_palette(header, field_palette, random);
    add_material(header, "mirror", metal({0.9, 0.92, 0.95}, 0.8));
    scene::Material glass;
    glass.ambient = 0;
    glass.diffuse = 0.05;
    glass.phong = 0.8;
    glass.phong_size = 120;
    glass.reflection = 0.1;
    glass.transmission = 0.85;
    glass.ior = 1.5;
    add_material(header, "glass", glass);
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
    return {out.primitives(),
            std::to_string(objects) + " objects in " + std::to_string(side) + " x " + std::to_string(side) + " cells"};
}

// --- lattice: a × b × c nodes one unit apart, a sphere at each, a cylinder to each neighbour along
// x, y and z; c along x, a (the smallest) up, b along z.

struct LatticeSides {
    int a, b, c;
};

// Floor + abc spheres + (c − 1)ab + (a − 1)bc + (b − 1)ca cylinders.
std::int64_t lattice_primitives(LatticeSides sides) {
    std::int64_t a = sides.a, b = sides.b, c = sides.c;
    return 1 + 4 * a * b * c - a * b - b * c - c * a;
}

GeneratedScene write_lattice(int size, std::uint64_t seed, const TextSink& sink) {
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
    return {out.primitives(),
            std::to_string(sides.c) + " x " + std::to_string(sides.a) + " x " + std::to_string(sides.b) + " nodes"};
}

// --- csg: CSG objects of six kinds, one in each 3 × 3 cell of a square grid on the floor, each of
// half-width h (seeded) around `center`, its lowest point sink_depth below the floor.

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

GeneratedScene write_csg(int size, std::uint64_t seed, const TextSink& sink) {
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
    return {out.primitives(), std::to_string(objects) + " CSG objects in " + std::to_string(side) + " x " +
                                  std::to_string(side) + " cells"};
}

struct Family {
    const char* name;
    GeneratedScene (*write)(int size, std::uint64_t seed, const TextSink& sink);
};

const std::array<Family, 4> families = {{
    {"fractal", write_fractal},
    {"field", write_field},
    {"lattice", write_lattice},
    {"csg", write_csg},
}};

}  // namespace

const std::vector<std::string>& generated_family_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> list;
        for (const Family& family : families) {
            list.emplace_back(family.name);
        }
        return list;
    }();
    return names;
}

GeneratedScene generate_scene(std::string_view family, int size, std::uint64_t seed, const TextSink& sink) {
    if (size < 1 || size > max_generated_primitives) {
        throw std::invalid_argument("size must be 1.." + std::to_string(max_generated_primitives) + ", got " +
                                    std::to_string(size));
    }
    for (const Family& candidate : families) {
        if (family == candidate.name) {
            return candidate.write(size, seed, sink);
        }
    }
    std::string allowed;
    for (const Family& candidate : families) {
        allowed += std::string(allowed.empty() ? "" : ", ") + candidate.name;
    }
    throw std::invalid_argument("unknown family \"" + std::string(family) + "\"; allowed: " + allowed);
}

}  // namespace twinray::cli
