#include "plugin/abi_scene.h"

#include "scene/geometry.h"
#include "scene/placement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <string>

namespace twinray::plugin {
namespace {

[[noreturn]] void refuse(const std::string& where, const std::string& what) {
    throw InvalidAbiScene("the tracer ABI's scene, " + where + ": " + what);
}

std::string element(const char* array, std::size_t index) {
    return std::string(array) + "[" + std::to_string(index) + "]";
}

scene::Vec3 vec(const double (&v)[3], const std::string& where) {
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
        refuse(where, "a coordinate is not finite");
    }
    return {v[0], v[1], v[2]};
}

template <typename T>
std::span<const T> array(const T* items, std::uint32_t count, const char* name) {
    if (count != 0 && items == nullptr) {
        refuse(name, "the count is " + std::to_string(count) + " but the array is NULL");
    }
    return {items, count};
}

// A primitive or mesh of the ABI's arrays, placed among the leaves by its object.
struct Leaf {
    std::uint32_t object;
    enum class Kind { plane, sphere, cylinder, box, mesh, instance } kind;
    std::size_t index;
};

class Rebuild {
public:
    explicit Rebuild(const twinray_scene& abi)
        : abi_(abi),
          planes_(array(abi.planes, abi.plane_count, "planes")),
          spheres_(array(abi.spheres, abi.sphere_count, "spheres")),
          cylinders_(array(abi.cylinders, abi.cylinder_count, "cylinders")),
          boxes_(array(abi.boxes, abi.box_count, "boxes")),
          meshes_(array(abi.meshes, abi.mesh_count, "meshes")),
          shapes_(array(abi.shapes, abi.shape_count, "shapes")),
          instances_(array(abi.instances, abi.instance_count, "instances")),
          transforms_(array(abi.transforms, abi.transform_count, "transforms")) {}

    AbiScene run() {
        for (std::size_t i = 0; i < transforms_.size(); ++i) {
            placements_.push_back(transform(transforms_[i], element("transforms", i)));
        }
        for (std::size_t i = 0; i < shapes_.size(); ++i) {
            out_.scene.mesh_shapes.push_back(
                {"shapes[" + std::to_string(i) + "]", mesh_data(shapes_[i], element("shapes", i)), -1});
        }
        collect(planes_, Leaf::Kind::plane, "planes");
        collect(spheres_, Leaf::Kind::sphere, "spheres");
        collect(cylinders_, Leaf::Kind::cylinder, "cylinders");
        collect(boxes_, Leaf::Kind::box, "boxes");
        collect(meshes_, Leaf::Kind::mesh, "meshes");
        collect(instances_, Leaf::Kind::instance, "instances");
        std::sort(leaves_.begin(), leaves_.end(), [](const Leaf& a, const Leaf& b) { return a.object < b.object; });
        for (std::size_t i = 1; i < leaves_.size(); ++i) {
            if (leaves_[i].object == leaves_[i - 1].object) {
                refuse("object " + std::to_string(leaves_[i].object), "named by two primitives");
            }
        }
        scene::Scene& scene = out_.scene;
        scene.camera.eye = vec(abi_.eye, "eye");
        scene.camera.look_at = scene.camera.eye + scene::Vec3{0, 0, -1};
        for (const Leaf& leaf : leaves_) {
            add(leaf, static_cast<int>(scene.leaf_materials.size()));
        }
        return std::move(out_);
    }

private:
    template <typename T>
    void collect(std::span<const T> items, Leaf::Kind kind, const char* name) {
        for (std::size_t i = 0; i < items.size(); ++i) {
            if (items[i].object >= abi_.object_count) {
                refuse(element(name, i), "its object " + std::to_string(items[i].object) +
                                             " is not below object_count " + std::to_string(abi_.object_count));
            }
            leaves_.push_back({items[i].object, kind, i});
        }
    }

    scene::Transform transform(const twinray_transform& placed, const std::string& where) const {
        scene::Matrix3 linear;
        for (int row = 0; row < 3; ++row) {
            linear.row[row] = vec(placed.linear[row], where + ".linear");
        }
        const scene::Transform to_world = scene::affine(linear, vec(placed.translation, where + ".translation"));
        if (!(scene::condition_number(to_world) <= scene::max_transform_condition)) {
            refuse(where, "singular or too badly conditioned (the limit of the condition number is 1e5)");
        }
        return to_world;
    }

    std::shared_ptr<const scene::MeshData> mesh_data(const twinray_mesh& mesh, const std::string& where) const {
        auto data = std::make_shared<scene::MeshData>();
        const std::span<const double> vertices = array(mesh.vertices, 3 * mesh.vertex_count, "vertices");
        const std::span<const std::uint32_t> triangles = array(mesh.triangles, 3 * mesh.triangle_count, "triangles");
        for (std::size_t v = 0; v < mesh.vertex_count; ++v) {
            const double xyz[3] = {vertices[3 * v], vertices[3 * v + 1], vertices[3 * v + 2]};
            data->vertices.push_back(vec(xyz, where + ".vertices[" + std::to_string(v) + "]"));
        }
        for (std::size_t t = 0; t < mesh.triangle_count; ++t) {
            std::array<std::uint32_t, 3> corners{triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]};
            for (std::uint32_t corner : corners) {
                if (corner >= mesh.vertex_count) {
                    refuse(where + ".triangles[" + std::to_string(t) + "]",
                           "vertex " + std::to_string(corner) + " of " + std::to_string(mesh.vertex_count));
                }
            }
            data->triangles.push_back(corners);
        }
        data->degenerate = scene::degenerate_triangles(*data);
        return data;
    }

    // A sphere, cylinder or box as itself, or placed by transforms[index].
    template <typename S>
    scene::Shape placed(const S& shape, std::uint32_t index, const std::string& where) const {
        if (index == TWINRAY_NONE) {
            return shape;
        }
        if (index >= placements_.size()) {
            refuse(where, "its transform " + std::to_string(index) + " is not below transform_count " +
                              std::to_string(placements_.size()));
        }
        return scene::Transformed<S>(shape, placements_[index]);
    }

    scene::Shape primitive(const Leaf& leaf) const {
        switch (leaf.kind) {
            case Leaf::Kind::plane: {
                const twinray_plane& p = planes_[leaf.index];
                const std::string where = element("planes", leaf.index);
                if (!std::isfinite(p.offset)) {
                    refuse(where, "its offset is not finite");
                }
                const scene::Vec3 normal = vec(p.normal, where + ".normal");
                if (!(std::fabs(math::length(normal) - 1) <= 1e-9)) {
                    refuse(where, "its normal is not of unit length");
                }
                return scene::Plane{normal, p.offset};
            }
            case Leaf::Kind::sphere: {
                const twinray_sphere& s = spheres_[leaf.index];
                const std::string where = element("spheres", leaf.index);
                if (!(s.radius > 0) || !std::isfinite(s.radius)) {
                    refuse(where, "its radius is not a positive finite number");
                }
                return placed(scene::Sphere{vec(s.center, where + ".center"), s.radius}, s.transform, where);
            }
            case Leaf::Kind::cylinder: {
                const twinray_cylinder& c = cylinders_[leaf.index];
                const std::string where = element("cylinders", leaf.index);
                if (!(c.radius > 0) || !std::isfinite(c.radius)) {
                    refuse(where, "its radius is not a positive finite number");
                }
                return placed(scene::Cylinder{vec(c.base, where + ".base"), vec(c.cap, where + ".cap"), c.radius},
                              c.transform, where);
            }
            case Leaf::Kind::box: {
                const twinray_box& b = boxes_[leaf.index];
                const std::string where = element("boxes", leaf.index);
                const scene::Box box{vec(b.min, where + ".min"), vec(b.max, where + ".max")};
                if (!(box.min.x < box.max.x && box.min.y < box.max.y && box.min.z < box.max.z)) {
                    refuse(where, "min is not below max on every axis");
                }
                return placed(box, b.transform, where);
            }
            default: break;
        }
        refuse("leaf", "not a primitive");
    }

    void add(const Leaf& leaf, int number) {
        scene::Scene& scene = out_.scene;
        std::uint32_t instance = TWINRAY_NONE;
        if (leaf.kind == Leaf::Kind::mesh) {
            scene.meshes.push_back(
                {mesh_data(meshes_[leaf.index], element("meshes", leaf.index)), 0, number, std::nullopt});
        } else if (leaf.kind == Leaf::Kind::instance) {
            const twinray_instance& placed = instances_[leaf.index];
            const std::string where = element("instances", leaf.index);
            if (placed.shape >= scene.mesh_shapes.size()) {
                refuse(where, "its shape " + std::to_string(placed.shape) + " is not below shape_count " +
                                  std::to_string(scene.mesh_shapes.size()));
            }
            const scene::Transform to_world = transform(placed.to_world, where + ".to_world");
            scene.meshes.push_back({scene.mesh_shapes[placed.shape].data, 0, number,
                                    scene::placement_of(to_world, static_cast<int>(placed.shape))});
            instance = static_cast<std::uint32_t>(leaf.index);
        } else {
            scene::Object object;
            object.shape = primitive(leaf);
            object.leaf = number;
            scene.objects.push_back(std::move(object));
        }
        scene.leaf_paths.push_back("objects[" + std::to_string(number) + "]");
        scene.leaf_materials.push_back(0);
        out_.object_of_leaf.push_back(leaf.object);
        out_.instance_of_leaf.push_back(instance);
    }

    const twinray_scene& abi_;
    std::span<const twinray_plane> planes_;
    std::span<const twinray_sphere> spheres_;
    std::span<const twinray_cylinder> cylinders_;
    std::span<const twinray_box> boxes_;
    std::span<const twinray_mesh> meshes_;
    std::span<const twinray_mesh> shapes_;
    std::span<const twinray_instance> instances_;
    std::span<const twinray_transform> transforms_;
    std::vector<scene::Transform> placements_;
    std::vector<Leaf> leaves_;
    AbiScene out_;
};

}  // namespace

AbiScene scene_from_abi(const twinray_scene& abi) {
    return Rebuild(abi).run();
}

}  // namespace twinray::plugin
