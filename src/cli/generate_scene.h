// The scene families of `twinray generate`: large scenes as users have them, for the work on scaling
// (docs/performance.md "Generated scenes"). Each is written as streamed text, never held whole, and is
// the same file, byte for byte, for the same family, size and seed on any machine.
#pragma once

#include "cli/scene_text_writer.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace twinray::cli {

constexpr int max_generated_primitives = 1'000'000;
// Every scene the generator writes can be read (the loader's limit, docs/scene-format.md).
static_assert(static_cast<std::size_t>(max_generated_primitives) <= scene::max_scene_primitives);
constexpr int default_generated_primitives = 1000;

// fractal, field, lattice, csg: the order in which help and messages list them.
const std::vector<std::string>& generated_family_names();

struct GeneratedScene {
    std::int64_t primitives = 0;  // leaves written, the floor plane included
    std::string structure;        // how the family met the size, e.g. "depth 3" or "8 x 7 x 7 nodes"
};

// Writes `family`'s scene with as close to `size` primitives as its structure allows, and never more
// than max_generated_primitives, to `sink`:
// - fractal: the sphereflake whose count (floor + (9^(depth+1) − 1) / 8 spheres) is nearest `size`;
// - field: exactly `size` (the floor and size − 1 spheres, boxes and cylinders);
// - lattice: the a × b × c nodes, sides differing by at most one, whose count (floor + abc spheres +
//   3abc − ab − bc − ca cylinders) is nearest `size`;
// - csg: exactly `size` (the floor and CSG objects of 2 to 5 primitives), except 3 for a size of 2.
// Ties go to the smaller scene. Throws std::invalid_argument for an unknown family or a size outside
// 1..max_generated_primitives.
GeneratedScene generate_scene(std::string_view family, int size, std::uint64_t seed, const TextSink& sink);

}  // namespace twinray::cli
