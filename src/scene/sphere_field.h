// A generated scene family for measuring how cost grows with scene size (twinray bench --scaling):
// `count` spheres scattered in a cube, one light, no reflection, the same picture density at any count.
// Built in memory, not written as text, so that what stands on the scene model alone (loader_test,
// precision_test, benchmarks/scene_load_benchmark) has it without the command line; the families of
// `twinray generate` live in src/cli/generate/.
#pragma once

#include "scene/scene.h"

#include <cstdint>

namespace twinray::scene {

// Positions, radii and colours come from splitmix64 seeded with `seed`, turned into doubles by hand
// (53 bits), so the scene is the same on every platform and standard library.
Scene sphere_field(int count, std::uint64_t seed = 7);

}  // namespace twinray::scene
