#include "sse/compiled_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

namespace twinray::sse {
namespace {

struct BoundingSphere {
    scene::Vec3 center;
    double radius;
};

BoundingSphere bounding_sphere(const scene::Plane&) {
    return {{0, 0, 0}, std::numeric_limits<double>::infinity()};
}
BoundingSphere bounding_sphere(const scene::Sphere& sphere) {
    return {sphere.center, sphere.radius};
}
BoundingSphere bounding_sphere(const scene::Cylinder& cylinder) {
    BoundingSphere out{};
    double half_length_squared = 0;
    for (int i = 0; i < 3; ++i) {
        out.center[i] = 0.5 * (cylinder.base[i] + cylinder.cap[i]);
        half_length_squared += 0.25 * (cylinder.cap[i] - cylinder.base[i]) * (cylinder.cap[i] - cylinder.base[i]);
    }
    out.radius = std::sqrt(half_length_squared + cylinder.radius * cylinder.radius);
    return out;
}
BoundingSphere bounding_sphere(const scene::Box& box) {
    BoundingSphere out{};
    double half_diagonal_squared = 0;
    for (int i = 0; i < 3; ++i) {
        out.center[i] = 0.5 * (box.min[i] + box.max[i]);
        half_diagonal_squared += 0.25 * (box.max[i] - box.min[i]) * (box.max[i] - box.min[i]);
    }
    out.radius = std::sqrt(half_diagonal_squared);
    return out;
}

vfloat4 lanes_of(double value) {
    return vfloat4(static_cast<float>(value));
}

PlaneF convert(const scene::Plane& plane) {
    return {{lanes_of(plane.normal[0]), lanes_of(plane.normal[1]), lanes_of(plane.normal[2])}, lanes_of(plane.offset)};
}
SphereF convert(const scene::Sphere& sphere) {
    float radius = static_cast<float>(sphere.radius);
    return {{lanes_of(sphere.center[0]), lanes_of(sphere.center[1]), lanes_of(sphere.center[2])},
            vfloat4(radius * radius)};
}
// Axis and height are derived in float from the float end points, as the reference<float> does.
CylinderF convert(const scene::Cylinder& cylinder) {
    Vec3 base(cylinder.base);
    Vec3 along = Vec3(cylinder.cap) - base;
    Vec3 axis = normalize(along);
    float radius = static_cast<float>(cylinder.radius);
    // The bounding sphere widened by 1e-4 relative: far beyond any float rounding, so that culling
    // never loses a hit.
    BoundingSphere bound = bounding_sphere(cylinder);
    const scene::Vec3& middle = bound.center;
    double widened =
        bound.radius +
        1e-4 * (bound.radius + std::max({std::fabs(middle[0]), std::fabs(middle[1]), std::fabs(middle[2])}));
    return {{vfloat4(base.x), vfloat4(base.y), vfloat4(base.z)},
            {vfloat4(axis.x), vfloat4(axis.y), vfloat4(axis.z)},
            vfloat4(length(along)),
            vfloat4(radius * radius),
            {lanes_of(middle[0]), lanes_of(middle[1]), lanes_of(middle[2])},
            lanes_of(widened * widened)};
}
BoxF convert(const scene::Box& box) {
    return {{lanes_of(box.min[0]), lanes_of(box.min[1]), lanes_of(box.min[2])},
            {lanes_of(box.max[0]), lanes_of(box.max[1]), lanes_of(box.max[2])}};
}

template <typename Primitive, typename Shape>
void append(PrimitiveList<Primitive>& list, const Shape& shape, std::int32_t id, float transmission) {
    list.items.push_back(convert(shape));
    list.ids.push_back(id);
    list.transmission.push_back(transmission);
    BoundingSphere bound = bounding_sphere(shape);
    list.bound_centers.push_back(bound.center);
    list.bound_radii.push_back(bound.radius);
}

struct Bounds {
    scene::Vec3 low, high;
};

constexpr double unbounded = std::numeric_limits<double>::infinity();

Bounds merge(const Bounds& a, const Bounds& b, bool intersect) {
    Bounds out;
    for (int axis = 0; axis < 3; ++axis) {
        out.low[axis] = intersect ? std::max(a.low[axis], b.low[axis]) : std::min(a.low[axis], b.low[axis]);
        out.high[axis] = intersect ? std::min(a.high[axis], b.high[axis]) : std::max(a.high[axis], b.high[axis]);
    }
    return out;
}

// A conservative axis-aligned bound: a cylinder is bounded by its end points ± radius on every axis, a
// plane not at all; an intersection by the overlap of its children's bounds, a difference by its first
// child's.
Bounds bounds_of(const scene::Object& object) {
    return std::visit(
        [&](const auto& shape) -> Bounds {
            using S = std::decay_t<decltype(shape)>;
            auto around = [](const scene::Vec3& a, const scene::Vec3& b, double pad) {
                Bounds out;
                for (int axis = 0; axis < 3; ++axis) {
                    out.low[axis] = std::min(a[axis], b[axis]) - pad;
                    out.high[axis] = std::max(a[axis], b[axis]) + pad;
                }
                return out;
            };
            if constexpr (std::is_same_v<S, scene::Plane>) {
                return {{-unbounded, -unbounded, -unbounded}, {unbounded, unbounded, unbounded}};
            } else if constexpr (std::is_same_v<S, scene::Sphere>) {
                return around(shape.center, shape.center, shape.radius);
            } else if constexpr (std::is_same_v<S, scene::Cylinder>) {
                return around(shape.base, shape.cap, shape.radius);
            } else if constexpr (std::is_same_v<S, scene::Box>) {
                return around(shape.min, shape.max, 0.0);
            } else {
                Bounds out = bounds_of(shape.children.front());
                if (shape.op == scene::CsgOp::difference) {
                    return out;
                }
                for (std::size_t i = 1; i < shape.children.size(); ++i) {
                    out = merge(out, bounds_of(shape.children[i]), shape.op == scene::CsgOp::intersection);
                }
                return out;
            }
        },
        object.shape);
}

// Widened by a relative margin far beyond float rounding, so that culling never loses a hit.
scene::Box as_float_safe_box(const Bounds& bounds) {
    scene::Box box;
    for (int axis = 0; axis < 3; ++axis) {
        double margin = 1e-4 * (std::fabs(bounds.low[axis]) + std::fabs(bounds.high[axis])) + 1e-30;
        box.min[axis] = bounds.low[axis] - margin;
        box.max[axis] = bounds.high[axis] + margin;
    }
    return box;
}

LeafInfo leaf_info(const scene::Object& object) {
    LeafInfo info{};
    info.material = object.material;
    std::visit(
        [&](const auto& shape) {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (std::is_same_v<S, scene::Plane>) {
                info.kind = LeafKind::plane;
                info.direction = Vec3(shape.normal);
                info.offset = static_cast<float>(shape.offset);
            } else if constexpr (std::is_same_v<S, scene::Sphere>) {
                info.kind = LeafKind::sphere;
                info.position = Vec3(shape.center);
                info.radius = static_cast<float>(shape.radius);
            } else if constexpr (std::is_same_v<S, scene::Cylinder>) {
                info.kind = LeafKind::cylinder;
                info.position = Vec3(shape.base);
                Vec3 along = Vec3(shape.cap) - info.position;
                info.direction = normalize(along);
                info.radius = static_cast<float>(shape.radius);
                info.height = length(along);
            } else if constexpr (std::is_same_v<S, scene::Box>) {
                info.kind = LeafKind::box;
                info.position = Vec3(shape.min);
                info.far_corner = Vec3(shape.max);
            }
        },
        object.shape);
    return info;
}

// Appends a primitive to the list of its type: at top level, or inside one CSG object.
void append_primitive(PrimitiveLists& lists, const scene::Object& object, std::int32_t id, float transmission) {
    std::visit(
        [&](const auto& shape) {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (std::is_same_v<S, scene::Plane>)
                append(lists.planes, shape, id, transmission);
            else if constexpr (std::is_same_v<S, scene::Sphere>)
                append(lists.spheres, shape, id, transmission);
            else if constexpr (std::is_same_v<S, scene::Cylinder>)
                append(lists.cylinders, shape, id, transmission);
            else if constexpr (std::is_same_v<S, scene::Box>)
                append(lists.boxes, shape, id, transmission);
        },
        object.shape);
}

class Compiler {
public:
    explicit Compiler(const scene::Scene& scene) : scene_(scene) {}

    CompiledScene run() {
        CompiledScene out;
        for (const scene::Material& m : scene_.materials) {
            out.materials.push_back({Color(m.color), static_cast<float>(m.ambient), static_cast<float>(m.diffuse),
                                     static_cast<float>(m.phong), static_cast<float>(m.phong_size),
                                     static_cast<float>(m.reflection), static_cast<float>(m.transmission),
                                     static_cast<float>(m.ior)});
        }
        out.leaves.resize(scene_.leaf_paths.size());
        for (const scene::Object& object : scene_.objects) {
            if (const auto* csg = std::get_if<scene::Csg>(&object.shape)) {
                CsgObject compiled;
                add_csg_node(compiled, *csg, out);
                compiled.bound = convert(as_float_safe_box(bounds_of(object)));
                out.csg_objects.push_back(std::move(compiled));
            } else {
                out.leaves[object.leaf] = leaf_info(object);
                append_primitive(out.primitives, object, object.leaf, transmission_of(object));
            }
        }
        for (const scene::Light& light : scene_.lights) {
            out.lights.push_back({Vec3(light.position), Color(light.color)});
        }
        out.background = Color(scene_.background);
        out.ambient_light = Color(scene_.ambient_light);
        out.max_depth = scene_.max_depth;
        out.any_transparency = scene_.has_transparency();
        out.any_box_test = !out.primitives.boxes.items.empty() || !out.csg_objects.empty();

        out.eye = Vec3(scene_.camera.eye);
        out.forward = normalize(Vec3(scene_.camera.look_at) - out.eye);
        out.right = normalize(cross(out.forward, Vec3(scene_.camera.up)));
        out.up = cross(out.right, out.forward);
        out.half_width = static_cast<float>(std::tan(scene_.camera.fov_deg * std::numbers::pi / 360.0));
        return out;
    }

private:
    float transmission_of(const scene::Object& object) const {
        return static_cast<float>(scene_.materials[object.material].transmission);
    }

    // Nodes are laid out so that a node's children are contiguous in children_of.
    int add_csg_node(CsgObject& compiled, const scene::Csg& csg, CompiledScene& out) {
        int index = static_cast<int>(compiled.nodes.size());
        compiled.nodes.push_back({csg.op, 0, static_cast<int>(csg.children.size()), -1});
        std::vector<int> children;
        for (const scene::Object& child : csg.children) {
            if (const auto* inner = std::get_if<scene::Csg>(&child.shape)) {
                children.push_back(add_csg_node(compiled, *inner, out));
            } else {
                int slot = static_cast<int>(compiled.slot_leaf.size());
                compiled.slot_leaf.push_back(child.leaf);
                out.leaves[child.leaf] = leaf_info(child);
                append_primitive(compiled.leaves, child, slot, transmission_of(child));
                children.push_back(static_cast<int>(compiled.nodes.size()));
                compiled.nodes.push_back({scene::CsgOp::union_, 0, 0, slot});
            }
        }
        compiled.nodes[index].first_child = static_cast<int>(compiled.children_of.size());
        compiled.children_of.insert(compiled.children_of.end(), children.begin(), children.end());
        return index;
    }

    const scene::Scene& scene_;
};

}  // namespace

CompiledScene compile(const scene::Scene& scene) {
    return Compiler(scene).run();
}

}  // namespace twinray::sse
