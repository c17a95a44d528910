// The families of `twinray generate`, one file each (fractal.cpp, ...): each writes its scene for the size
// and seed as cli/generate_scene.h states its rule, checked there to be within 1..max_generated_primitives.
#pragma once

#include "cli/generate_scene.h"

#include <cstdint>

namespace twinray::cli::generate {

GeneratedScene write_fractal(int size, std::uint64_t seed, const SceneSink& sink);
GeneratedScene write_field(int size, std::uint64_t seed, const SceneSink& sink);
GeneratedScene write_lattice(int size, std::uint64_t seed, const SceneSink& sink);
GeneratedScene write_csg(int size, std::uint64_t seed, const SceneSink& sink);
GeneratedScene write_sphere_mesh(int size, std::uint64_t seed, const SceneSink& sink);
GeneratedScene write_torus_mesh(int size, std::uint64_t seed, const SceneSink& sink);
GeneratedScene write_tetra(int size, std::uint64_t seed, const SceneSink& sink);
GeneratedScene write_sombrero(int size, std::uint64_t seed, const SceneSink& sink);
GeneratedScene write_triangle_soup(int size, std::uint64_t seed, const SceneSink& sink);
GeneratedScene write_mount(int size, std::uint64_t seed, const SceneSink& sink);
GeneratedScene write_gears(int size, std::uint64_t seed, const SceneSink& sink);
GeneratedScene write_forest(int size, std::uint64_t seed, const SceneSink& sink);

}  // namespace twinray::cli::generate
