// libFuzzer target for the scene loader: arbitrary bytes into twinray::scene::parse_scene.
//
// What it holds the loader to, beyond what ASan and UBSan catch by themselves (reads out of bounds,
// use after free, signed overflow, bad float-to-int conversions, stack exhaustion):
// - the only way to refuse a document is a SceneError: any other exception escapes this function and
//   libFuzzer reports it as a crash (std::terminate);
// - a scene that is accepted keeps every promise the tracers rely on (docs/scene-format.md): numbers
//   finite, indices in range, unit plane normals, positive radii, non-degenerate boxes, bounded
//   nesting. A broken promise aborts, so libFuzzer saves the input that broke it.
// Built only with -DTWINRAY_FUZZ=ON (preset `fuzz`, clang); see docs/reliability.md.
#include "promise.h"
#include "scene/loader.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <variant>
#include <vector>

namespace {

using namespace twinray::scene;

void expect(bool holds, const char* what) {
    twinray::fuzz::expect(holds, "scene_loader_fuzz", what);
}

bool non_negative(const Vec3& v) {
    return v[0] >= 0 && v[1] >= 0 && v[2] >= 0;
}

// Returns the number of leaves below `object`; checks each leaf's numbering and material.
int check_object(const Scene& scene, const Object& object, int depth, int& next_leaf) {
    expect(depth <= 64, "objects nest at most 64 levels");
    if (const auto* csg = std::get_if<Csg>(&object.shape)) {
        expect(csg->children.size() >= 2, "a CSG node has at least 2 children");
        int leaves = 0;
        for (const Object& child : csg->children) {
            leaves += check_object(scene, child, depth + 1, next_leaf);
        }
        return leaves;
    }
    expect(object.leaf == next_leaf, "leaves are numbered in document order");
    ++next_leaf;
    expect(object.material >= 0 && static_cast<std::size_t>(object.material) < scene.materials.size(),
           "a leaf's material index is in range");
    if (const auto* plane = std::get_if<Plane>(&object.shape)) {
        expect(is_finite(plane->normal) && std::isfinite(plane->offset), "plane is finite");
        double length = std::sqrt(plane->normal[0] * plane->normal[0] + plane->normal[1] * plane->normal[1] +
                                  plane->normal[2] * plane->normal[2]);
        expect(std::abs(length - 1.0) < 1e-12, "plane normal has unit length");
    } else if (const auto* sphere = std::get_if<Sphere>(&object.shape)) {
        expect(is_finite(sphere->center) && std::isfinite(sphere->radius) && sphere->radius > 0, "sphere radius > 0");
    } else if (const auto* cylinder = std::get_if<Cylinder>(&object.shape)) {
        expect(is_finite(cylinder->base) && is_finite(cylinder->cap) && cylinder->base != cylinder->cap,
               "cylinder base differs from cap");
        expect(std::isfinite(cylinder->radius) && cylinder->radius > 0, "cylinder radius > 0");
    } else if (const auto* box = std::get_if<Box>(&object.shape)) {
        expect(is_finite(box->min) && is_finite(box->max), "box is finite");
        for (int axis = 0; axis < 3; ++axis) {
            expect(box->min[axis] < box->max[axis], "box min < max on every axis");
        }
    }
    return 1;
}

// A mesh the tracers can index blindly: every index in range, finite vertices, one unit normal per vertex
// where it shades smooth, degenerate triangles listed once, ascending, and truly degenerate.
void check_mesh(const Scene& scene, const Mesh& mesh) {
    expect(mesh.material >= 0 && static_cast<std::size_t>(mesh.material) < scene.materials.size(),
           "a mesh's material index is in range");
    const MeshData& data = *mesh.data;
    expect(!data.triangles.empty(), "a mesh has a triangle");
    for (const Vec3& vertex : data.vertices) {
        expect(is_finite(vertex), "mesh vertices are finite");
    }
    for (const auto& triangle : data.triangles) {
        for (std::uint32_t index : triangle) {
            expect(index < data.vertices.size(), "triangle indices are in range");
        }
    }
    expect(!data.smooth || data.normals.size() == data.vertices.size(), "a smooth mesh has a normal per vertex");
    for (const Vec3& normal : data.normals) {
        double length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
        expect(is_finite(normal) && (length == 0 || std::abs(length - 1.0) < 1e-12), "mesh normals are unit or zero");
    }
    for (std::size_t i = 0; i < data.degenerate.size(); ++i) {
        expect(data.degenerate[i] < data.triangles.size(), "degenerate triangles are in range");
        expect(i == 0 || data.degenerate[i - 1] < data.degenerate[i], "degenerate triangles are ascending");
    }
}

void check_accepted(const Scene& scene) {
    expect(scene.width >= 1 && scene.width <= max_image_side, "image width in range");
    expect(scene.height >= 1 && scene.height <= max_image_side, "image height in range");
    expect(scene.max_depth >= 1 && scene.max_depth <= max_trace_depth, "max_depth in range");
    expect(!scene.min_weight || (std::isfinite(*scene.min_weight) && *scene.min_weight >= 0), "min_weight >= 0");
    const Camera& camera = scene.camera;
    expect(is_finite(camera.eye) && is_finite(camera.look_at) && is_finite(camera.up), "camera is finite");
    expect(camera.eye != camera.look_at, "camera eye differs from look_at");
    expect(camera.fov_deg > 0 && camera.fov_deg < 180, "0 < fov_deg < 180");
    expect(is_finite(scene.background) && non_negative(scene.background), "background is a colour");
    expect(is_finite(scene.ambient_light) && non_negative(scene.ambient_light), "ambient_light is a colour");
    expect(!scene.materials.empty() && scene.materials.size() == scene.material_names.size(),
           "one name per material, the default first");
    for (const Material& m : scene.materials) {
        expect(is_finite(m.color) && non_negative(m.color), "material colour is a colour");
        for (double coefficient : {m.ambient, m.diffuse, m.phong, m.reflection, m.transmission}) {
            expect(std::isfinite(coefficient) && coefficient >= 0, "material coefficients are >= 0");
        }
        expect(std::isfinite(m.phong_size) && m.phong_size > 0, "phong_size > 0");
        expect(std::isfinite(m.ior) && m.ior > 0, "ior > 0");
    }
    for (const Light& light : scene.lights) {
        expect(is_finite(light.position) && is_finite(light.color) && non_negative(light.color), "light is finite");
    }
    // Meshes and instances of CSG shapes take leaf numbers among the objects': counted here by the numbers they take.
    std::vector<bool> mesh_leaf(scene.leaf_paths.size(), false);
    for (const Mesh& mesh : scene.meshes) {
        expect(mesh.leaf >= 0 && static_cast<std::size_t>(mesh.leaf) < scene.leaf_paths.size(), "mesh leaf in range");
        mesh_leaf[static_cast<std::size_t>(mesh.leaf)] = true;
        check_mesh(scene, mesh);
    }
    for (const SolidShape& shape : scene.solid_shapes) {
        expect(std::holds_alternative<Csg>(shape.tree.shape), "a solid shape is a CSG tree");
        expect(shape.part_paths.size() == shape.part_materials.size() &&
                   shape.part_paths.size() <= static_cast<std::size_t>(max_csg_leaves),
               "a solid shape's parts have a path and a material each, at most 64");
        for (int material : shape.part_materials) {
            expect(material >= -1 && material < static_cast<int>(scene.materials.size()),
                   "a part's material is in range, or -1 for the instance's");
        }
    }
    for (const SolidInstance& instance : scene.solid_instances) {
        expect(instance.leaf >= 0 && static_cast<std::size_t>(instance.leaf) < scene.leaf_paths.size(),
               "instance leaf in range");
        expect(instance.placement.shape >= 0 &&
                   static_cast<std::size_t>(instance.placement.shape) < scene.solid_shapes.size(),
               "an instance's shape is in range");
        expect(instance.material >= 0 && static_cast<std::size_t>(instance.material) < scene.materials.size(),
               "an instance's material is in range");
        mesh_leaf[static_cast<std::size_t>(instance.leaf)] = true;
    }
    int next_leaf = 0;
    auto skip_meshes = [&] {
        while (static_cast<std::size_t>(next_leaf) < mesh_leaf.size() &&
               mesh_leaf[static_cast<std::size_t>(next_leaf)]) {
            ++next_leaf;
        }
    };
    for (const Object& object : scene.objects) {
        skip_meshes();
        int leaves = check_object(scene, object, 1, next_leaf);
        if (std::holds_alternative<Csg>(object.shape)) {
            expect(leaves <= max_csg_leaves, "a top-level CSG object holds at most 64 primitives");
        }
    }
    skip_meshes();
    expect(static_cast<std::size_t>(next_leaf) == scene.leaf_paths.size(), "one path per leaf");
    expect(scene.primitive_count() <= max_scene_primitives, "at most the primitive limit");
    expect(scene.leaf_paths.size() == scene.leaf_materials.size(), "one material per leaf");
    for (int material : scene.leaf_materials) {
        expect(material >= 0 && static_cast<std::size_t>(material) < scene.materials.size(),
               "leaf_materials index in range");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        check_accepted(parse_scene(text, "<fuzz>"));
    } catch (const SceneError& refusal) {
        // A refusal must say where and what: an empty problem would leave the user guessing.
        expect(!refusal.problem().empty(), "a refusal says what is wrong");
    }
    return 0;
}

// Where a second target would plug in (issue 8 asks for one on `twinray compare`'s image loading,
// being written now): a file tests/fuzz/image_loader_fuzz.cpp whose LLVMFuzzerTestOneInput writes the
// bytes to a temporary .png/.exr and calls the compare library's image reader, expecting only its
// documented error type; registered in tests/fuzz/CMakeLists.txt with twinray_fuzz_target() next to
// this one, seeded from tests/data/ images.
