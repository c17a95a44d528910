#include "cli/generate_scene.h"

#include "cli/generate/families.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace twinray::cli {
namespace {

// Which paragraph of the help lists a family; every family but those of primitives writes a mesh.
enum class FamilyGroup { primitives, mesh, instances };

struct Family {
    const char* name;
    GeneratedScene (*write)(int size, std::uint64_t seed, const SceneSink& sink);
    FamilyGroup group;
    const char* help;  // what `generate --help` says of it, lines after the first indented by the help itself
};

const std::array<Family, 12> families = {{
    {"fractal", generate::write_fractal, FamilyGroup::primitives,
     "a sphereflake (9 reflective spheres around each sphere, recursively) on a floor; the depth\n"
     "whose count, 1 + (9^(depth+1) - 1)/8, is nearest --size"},
    {"field", generate::write_field, FamilyGroup::primitives,
     "spheres, boxes and cylinders of random sizes and materials on a floor; exactly --size"},
    {"lattice", generate::write_lattice, FamilyGroup::primitives,
     "a 3-D lattice of cylinders joined by spheres, a x b x c nodes with sides differing by at\n"
     "most one; the count nearest --size"},
    {"csg", generate::write_csg, FamilyGroup::primitives,
     "an array of CSG objects (differences, intersections, unions) on a floor; exactly --size\n"
     "(3 for a size of 2)"},
    {"sphere-mesh", generate::write_sphere_mesh, FamilyGroup::mesh,
     "a UV sphere, b bands and 2b slices, closed, smooth; the 4b(b - 1) nearest --size"},
    {"torus-mesh", generate::write_torus_mesh, FamilyGroup::mesh,
     "a tilted torus, 3n x n segments, closed, smooth; the 6n^2 nearest --size"},
    {"tetra", generate::write_tetra, FamilyGroup::mesh,
     "the Sierpinski tetrahedron of depth d (SPD \"tetra\"), 4^d closed tetrahedra; the\n"
     "largest 4 x 4^d not above --size (4 below that)"},
    {"sombrero", generate::write_sombrero, FamilyGroup::mesh,
     "the height field sin(r)/r over n x n quads, open, smooth; the 2n^2 nearest --size"},
    {"triangle-soup", generate::write_triangle_soup, FamilyGroup::mesh, "random triangles in a cube; exactly --size"},
    {"mount", generate::write_mount, FamilyGroup::mesh,
     "a fractal mountain (SPD \"mount\"): a square of two triangles subdivided d times by\n"
     "midpoint displacement, open, flat, and four glass spheres; the 2 x 4^d nearest --size"},
    {"gears", generate::write_gears, FamilyGroup::mesh,
     "a g x g grid of meshing 24-tooth gears (SPD \"gears\"), closed prisms whose concave\n"
     "faces are ear-clipped, flat; the 380g^2 nearest --size"},
    {"forest", generate::write_forest, FamilyGroup::instances,
     "one tree (a trunk and three cones, 1 008 triangles) declared once as a mesh shape, and\n"
     "instances of it on a jittered square grid, each turned, scaled and coloured at random;\n"
     "exactly --size instances, the tree's triangles counted once"},
}};

// Each group's paragraph begins with its heading (none for the first).
struct GroupHelp {
    FamilyGroup group;
    const char* heading;
};

constexpr GroupHelp group_help[] = {
    {FamilyGroup::primitives, ""},
    {FamilyGroup::mesh,
     "Counts include the floor plane; ties go to the smaller scene. Mesh families write one triangle mesh\n"
     "on a floor, --size counting its triangles:\n"},
    {FamilyGroup::instances, "Instanced families place one mesh shape many times on a floor:\n"},
};

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

std::string generated_family_list() {
    const std::vector<std::string>& names = generated_family_names();
    std::string list;
    for (std::size_t i = 0; i < names.size(); ++i) {
        list += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    }
    return list;
}

std::string generated_families_help() {
    std::string help;
    for (const GroupHelp& group : group_help) {
        std::size_t name_width = 0;  // the group's descriptions start in one column
        for (const Family& family : families) {
            if (family.group == group.group) {
                name_width = std::max(name_width, std::string_view(family.name).size());
            }
        }
        const std::string indent(2 + name_width + 2, ' ');
        help += group.heading;
        for (const Family& family : families) {
            if (family.group != group.group) {
                continue;
            }
            std::string name = family.name;
            name.resize(name_width, ' ');
            help += "  " + name + "  ";
            for (const char* c = family.help; *c != '\0'; ++c) {
                help += *c;
                if (*c == '\n') {
                    help += indent;
                }
            }
            help += '\n';
        }
    }
    help.pop_back();
    return help;
}

bool is_mesh_family(std::string_view family) {
    for (const Family& candidate : families) {
        if (family == candidate.name) {
            return candidate.group != FamilyGroup::primitives;
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
    throw std::invalid_argument("unknown family \"" + std::string(family) + "\"; allowed: " + generated_family_list());
}

}  // namespace twinray::cli
