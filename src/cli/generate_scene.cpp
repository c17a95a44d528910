#include "cli/generate_scene.h"

#include "cli/generate/families.h"

#include <array>
#include <stdexcept>

namespace twinray::cli {
namespace {

struct Family {
    const char* name;
    GeneratedScene (*write)(int size, std::uint64_t seed, const SceneSink& sink);
    bool writes_mesh;
};

const std::array<Family, 12> families = {{
    {"fractal", generate::write_fractal, false},
    {"field", generate::write_field, false},
    {"lattice", generate::write_lattice, false},
    {"csg", generate::write_csg, false},
    {"sphere-mesh", generate::write_sphere_mesh, true},
    {"torus-mesh", generate::write_torus_mesh, true},
    {"tetra", generate::write_tetra, true},
    {"sombrero", generate::write_sombrero, true},
    {"triangle-soup", generate::write_triangle_soup, true},
    {"mount", generate::write_mount, true},
    {"gears", generate::write_gears, true},
    {"forest", generate::write_forest, true},
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

bool is_mesh_family(std::string_view family) {
    for (const Family& candidate : families) {
        if (family == candidate.name) {
            return candidate.writes_mesh;
        }
    }
    return false;
}

GeneratedScene generate_scene(std::string_view family, int size, std::uint64_t seed, const SceneSink& sink) {
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
