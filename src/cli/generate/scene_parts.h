// What the families of `twinray generate` share: every picture's framing and lights, the floor, the
// materials, and the rules by which a family meets the size it is asked for.
#pragma once

#include "cli/generate/scene_text_writer.h"
#include "scene/portable_random.h"
#include "scene/scene.h"

#include <cstdint>
#include <functional>
#include <string>

namespace twinray::cli::generate {

// Boxes and cylinders that stand on the floor go this far into it: a face in the floor's own plane
// would leave each tracer to choose between two coincident surfaces.
constexpr double sink_depth = 0.05;

// Numbers with this many decimals. The smallest sizes of field, lattice and csg are 0.07 to 0.15 (the
// lattice's rods, written exactly, a field cylinder, the jack's rods): rounding moves none of them by
// more than 0.4%. Families whose features shrink with the size choose theirs by decimals_resolving.
constexpr int default_decimals = 3;

// The decimals, default_decimals or more, that put a thousand grid steps or more across a feature of
// `smallest_feature` (> 0).
int decimals_resolving(double smallest_feature);

// A scene without objects, its camera looking at the sphere (center, radius) around everything from
// the direction `view_from`, two lights above it and the floor's material (index 1).
scene::Scene framed_scene(Vec3 center, double radius, Vec3 view_from);

constexpr int floor_material = 1;

void write_floor(SceneTextWriter& out);

int add_material(scene::Scene& scene, std::string name, const scene::Material& material);
Vec3 random_color(SplitMix64& random);
scene::Material plastic(Vec3 color);
scene::Material metal(Vec3 color, double reflection);
scene::Material glass();

// Materials 2 .. 1 + count, each plastic or (one in three) metal of a seeded colour.
void add_palette(scene::Scene& scene, int count, SplitMix64& random);
// One of those, at random.
int palette_material(SplitMix64& random, int palette_size);

// Whether `candidate` primitives are nearer `size` than `best` (ties to the smaller, listed first).
bool nearer(std::int64_t candidate, std::int64_t best, int size);

// The parameter n >= first whose count(n), increasing with n, is nearest `size` without passing
// max_generated_primitives; ties to the smaller. count(first) must be within that maximum.
int nearest_parameter(int first, int size, const std::function<std::int64_t(int)>& count);

// The side of the smallest square grid with at least `count` cells.
int square_side(int count);

}  // namespace twinray::cli::generate
