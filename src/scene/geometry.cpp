#include "scene/geometry.h"

#include "math/exact_predicates.h"

#include <memory>
#include <variant>

namespace twinray::scene {
namespace {

Bounds merged(const Bounds& a, const Bounds& b, bool intersect) {
    Bounds out;
    for (int axis = 0; axis < 3; ++axis) {
        out.low[axis] = intersect ? std::max(a.low[axis], b.low[axis]) : std::min(a.low[axis], b.low[axis]);
        out.high[axis] = intersect ? std::min(a.high[axis], b.high[axis]) : std::max(a.high[axis], b.high[axis]);
    }
    return out;
}

}  // namespace

[[gnu::noinline]] double rounded_to_float(double value) {
    return static_cast<float>(value);
}

Bounds bounds(const Object& object) {
    return std::visit(
        [](const auto& shape) {
            if constexpr (is_primitive<std::decay_t<decltype(shape)>>) {
                return bounds(shape);
            } else {
                Bounds out = bounds(shape.children.front());
                if (shape.op == CsgOp::difference) {
                    return out;
                }
                for (std::size_t i = 1; i < shape.children.size(); ++i) {
                    out = merged(out, bounds(shape.children[i]), shape.op == CsgOp::intersection);
                }
                return out;
            }
        },
        object.shape);
}

// Csg has no overloads of its own: each operation recurses into the children.
void move(Object& object, double scale, const Vec3& shift) {
    std::visit(
        [&](auto& shape) {
            if constexpr (is_primitive<std::decay_t<decltype(shape)>>) {
                shape = moved(shape, scale, shift);
            } else {
                for (Object& child : shape.children) {
                    move(child, scale, shift);
                }
            }
        },
        object.shape);
}

Scene moved(const Scene& scene, double scale, const Vec3& shift) {
    Scene result = scene;
    result.camera.eye = moved(scene.camera.eye, scale, shift);
    result.camera.look_at = moved(scene.camera.look_at, scale, shift);
    for (Light& light : result.lights) {
        light.position = moved(light.position, scale, shift);
    }
    for (Object& object : result.objects) {
        move(object, scale, shift);
    }
    for (Mesh& mesh : result.meshes) {
        mesh = moved(mesh, scale, shift);
    }
    for (SolidInstance& instance : result.solid_instances) {
        instance.placement = moved(instance.placement, scale, shift);
    }
    return result;
}

std::vector<std::uint32_t> degenerate_triangles(const MeshData& mesh) {
    auto exactly = [&](std::uint32_t vertex) {
        const Vec3& p = mesh.vertices[vertex];
        return math::Coordinates{p.x, p.y, p.z};
    };
    std::vector<std::uint32_t> degenerate;
    for (std::uint32_t i = 0; i < mesh.triangles.size(); ++i) {
        const std::array<std::uint32_t, 3>& t = mesh.triangles[i];
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0] ||
            math::exactly_collinear(exactly(t[0]), exactly(t[1]), exactly(t[2]))) {
            degenerate.push_back(i);
        }
    }
    return degenerate;
}

std::array<double, 3> barycentrics(const MeshData& mesh, std::uint32_t triangle, const Vec3& point) {
    const std::array<std::uint32_t, 3>& corners = mesh.triangles[triangle];
    const Vec3& a = mesh.vertices[corners[0]];
    const Vec3& b = mesh.vertices[corners[1]];
    const Vec3& c = mesh.vertices[corners[2]];
    Vec3 normal = cross(b - a, c - a);
    double whole = dot(normal, normal);
    return {dot(normal, cross(b - point, c - point)) / whole, dot(normal, cross(c - point, a - point)) / whole,
            dot(normal, cross(a - point, b - point)) / whole};
}

Bounds vertex_bounds(const MeshData& mesh) {
    Bounds out = around(mesh.vertices.front(), mesh.vertices.front(), 0.0);
    for (const Vec3& vertex : mesh.vertices) {
        for (int axis = 0; axis < 3; ++axis) {
            out.low[axis] = std::min(out.low[axis], vertex[axis]);
            out.high[axis] = std::max(out.high[axis], vertex[axis]);
        }
    }
    return out;
}

Placement moved(const Placement& placement, double scale, const Vec3& shift) {
    // As a transformed primitive's: (s·L)·x + (s·t + shift), the shape itself kept.
    Placement out = placement;
    for (Vec3& row : out.linear.row) {
        row = scale * row;
    }
    out.translation = moved(out.translation, scale, shift);
    return out;
}

Mesh moved(const Mesh& mesh, double scale, const Vec3& shift) {
    Mesh out = mesh;
    if (out.placement) {
        out.placement = moved(*out.placement, scale, shift);
        return out;
    }
    auto data = std::make_shared<MeshData>(*mesh.data);
    for (Vec3& vertex : data->vertices) {
        vertex = moved(vertex, scale, shift);
    }
    out.data = std::move(data);
    return out;
}

double largest_coordinate(const Mesh& mesh) {
    double largest = 0;
    for (const Vec3& vertex : mesh.data->vertices) {
        largest = std::max(largest, largest_coordinate(vertex));
    }
    if (mesh.placement) {
        return largest_coordinate(mesh.placement->translation) + math::row_sum_norm(mesh.placement->linear) * largest;
    }
    return largest;
}

void round_to_float(Object& object) {
    std::visit(
        [&](auto& shape) {
            if constexpr (is_primitive<std::decay_t<decltype(shape)>>) {
                shape = rounded_to_float(shape);
            } else {
                for (Object& child : shape.children) {
                    round_to_float(child);
                }
            }
        },
        object.shape);
}

double largest_coordinate(const Object& object) {
    return std::visit(
        [&](const auto& shape) {
            if constexpr (is_primitive<std::decay_t<decltype(shape)>>) {
                return largest_coordinate(shape);
            } else {
                double largest = 0;
                for (const Object& child : shape.children) {
                    largest = std::max(largest, largest_coordinate(child));
                }
                return largest;
            }
        },
        object.shape);
}

}  // namespace twinray::scene
