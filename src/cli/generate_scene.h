// The scene families of `twinray generate`: large scenes as users have them, for the work on scaling
// (docs/performance.md "Generated scenes"). Each is written as streamed text, never held whole, and is
// the same file, byte for byte, for the same family, size and seed on any machine. Each family is a file
// of generate/ (generate/families.h); what they share is in generate/scene_parts.h and mesh_parts.h.
#pragma once

#include "cli/generate/scene_text_writer.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace twinray::cli {

// Of primitives, or of triangles for a mesh family.
constexpr int max_generated_primitives = 1'000'000;
// Every scene the generator writes can be read (the loader's limit, docs/scene-format.md, which counts a
// mesh's triangles: a mesh family writes at most this many and a floor).
static_assert(static_cast<std::size_t>(max_generated_primitives) <= scene::max_scene_primitives);
constexpr int default_generated_primitives = 1000;

// fractal, field, lattice, csg, sphere-mesh, torus-mesh, tetra, sombrero, triangle-soup, mount, gears, forest: the
// order in which help and messages list them.
const std::vector<std::string>& generated_family_names();
// The names as a sentence lists them: "fractal, field, ... gears or forest".
std::string generated_family_list();

// What `generate --help` says of each family, grouped as the families are (of primitives, of one mesh, instanced), in
// the order of generated_family_names().
std::string generated_families_help();

// Whether the family writes a mesh (sphere-mesh, torus-mesh, tetra, sombrero, triangle-soup, mount, gears, forest).
bool is_mesh_family(std::string_view family);

struct GeneratedScene {
    std::int64_t primitives = 0;  // leaves written, the floor plane included; a mesh is one
    std::int64_t triangles = 0;   // of the meshes
    std::string structure;        // how the family met the size, e.g. "depth 3" or "8 x 7 x 7 nodes"
};

// Writes `family`'s scene with as close to `size` primitives as its structure allows, and never more
// than max_generated_primitives, to `sink` (a mesh inline in the text, or to a file where sink.mesh_file is set):
// - fractal: the sphereflake whose count (floor + (9^(depth+1) − 1) / 8 spheres) is nearest `size`;
// - field: exactly `size` (the floor and size − 1 spheres, boxes and cylinders);
// - lattice: the a × b × c nodes, sides differing by at most one, whose count (floor + abc spheres +
//   3abc − ab − bc − ca cylinders) is nearest `size`;
// - csg: exactly `size` (the floor and CSG objects of 2 to 5 primitives), except 3 for a size of 2.
// The mesh families write the floor and one mesh (`{"type": "mesh", "vertices", "triangles"}`, and
// `"normals"` and `"smooth": true` for a curved one), mount four glass spheres after it, `size` counting the
// mesh's triangles:
// - sphere-mesh: a UV sphere of b bands from pole to pole and 2b slices, the poles fans, shared vertices:
//   the 4b(b − 1) triangles (b >= 2) nearest `size`;
// - torus-mesh: 3n segments around the ring, n around the tube, shared vertices: the 6n² (n >= 3) nearest;
// - tetra: the Sierpinski tetrahedron of depth d, 4^d tetrahedra each its own closed shell: the largest
//   4·4^d triangles not above `size`, or 4 (d = 0) below that;
// - sombrero: the height field sin(r)/r over n × n quads, an open surface: the 2n² nearest;
// - triangle-soup: exactly `size` random triangles, three vertices each;
// - mount: SPD's fractal mountain, a square of two triangles subdivided d times by midpoint displacement, an
//   open surface, shared vertices: the 2·4^d (d >= 0) nearest `size`;
// - gears: SPD's gears, a g × g grid of 24-tooth gears, each a closed prism of two concave faces (94
//   triangles each) and 96 side quads: the 380g² (g >= 1) nearest.
// - forest: one tree declared as a mesh shape (1 008 triangles, counted once) and exactly `size` instances of it
//   on a jittered square grid, each turned, scaled and coloured at random (`size` counting the instances).
// The closed meshes are counter-clockwise seen from outside. Ties go to the smaller scene. Throws
// std::invalid_argument for an unknown family or a size outside 1..max_generated_primitives.
GeneratedScene generate_scene(std::string_view family, int size, std::uint64_t seed, const SceneSink& sink);

}  // namespace twinray::cli
