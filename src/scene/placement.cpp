#include "scene/placement.h"

#include "scene/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <variant>

namespace twinray::scene {
namespace {

// Each row and each column of L holds exactly one non-zero entry: an axis permutation with signed scales, which
// takes an axis-aligned box to an axis-aligned box. `source[i]` is the object axis world axis i comes from.
bool is_signed_permutation(const Matrix3& l, int source[3]) {
    bool column_used[3] = {false, false, false};
    for (int i = 0; i < 3; ++i) {
        int found = -1;
        for (int j = 0; j < 3; ++j) {
            if (l.row[i][j] != 0) {
                if (found >= 0) {
                    return false;
                }
                found = j;
            }
        }
        if (found < 0 || column_used[found]) {
            return false;
        }
        column_used[found] = true;
        source[i] = found;
    }
    return true;
}

// A signed permutation's common magnitude, or 0 where its scales differ.
double even_scale(const Matrix3& l, const int source[3]) {
    double s = std::fabs(l.row[0][source[0]]);
    bool even = std::fabs(l.row[1][source[1]]) == s && std::fabs(l.row[2][source[2]]) == s;
    return even ? s : 0;
}

// The factor s of a similarity, L = s·Q with Q orthogonal, if L is one: exactly for a signed permutation whose
// scales agree in magnitude, else where LᵀL = s²·I within 32 ulps (a rotation composed in double is orthogonal
// only to rounding, which is ~1e-16 of the size: far below what float can see). 0 if L is no similarity.
double similarity_factor(const Matrix3& l) {
    int source[3];
    if (is_signed_permutation(l, source)) {
        return even_scale(l, source);
    }
    double gram[3][3];
    double trace = 0;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            gram[i][j] = l.row[0][i] * l.row[0][j] + l.row[1][i] * l.row[1][j] + l.row[2][i] * l.row[2][j];
        }
        trace += gram[i][i];
    }
    double s2 = trace / 3;
    double tolerance = 32 * std::numeric_limits<double>::epsilon() * s2;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (std::fabs(gram[i][j] - (i == j ? s2 : 0)) > tolerance) {
                return 0;
            }
        }
    }
    return std::sqrt(s2);
}

bool is_identity(const Matrix3& l) {
    int source[3];
    return is_signed_permutation(l, source) && l.row[0].x == 1 && l.row[1].y == 1 && l.row[2].z == 1;
}

// cos and sin of `degrees`, exact at multiples of 90°.
void cos_sin(double degrees, double& c, double& s) {
    double turn = std::fmod(degrees, 360.0);  // exact
    if (turn < 0) {
        turn += 360;
    }
    if (std::fmod(turn, 90.0) == 0) {
        int quarter = static_cast<int>(turn / 90) % 4;
        c = quarter == 0 ? 1 : quarter == 2 ? -1 : 0;
        s = quarter == 1 ? 1 : quarter == 3 ? -1 : 0;
        return;
    }
    double radians = turn * (std::numbers::pi / 180);
    c = std::cos(radians);
    s = std::sin(radians);
}

Shape placed_plane(const Plane& plane, const Transform& m) {
    int source[3];
    double s = is_signed_permutation(m.linear, source) ? even_scale(m.linear, source) : 0;
    if (s > 0) {
        // L = s·P: the normal is P·n exactly, and n'·(L·(d·n) + t) = s·d + n'·t.
        Vec3 normal;
        for (int i = 0; i < 3; ++i) {
            normal[i] = std::copysign(1.0, m.linear.row[i][source[i]]) * plane.normal[source[i]];
        }
        return Plane{normal, s * plane.offset + math::dot(normal, m.translation)};
    }
    Vec3 normal = math::normalize(m.normal_to_world(plane.normal));
    return Plane{normal, math::dot(normal, m.point_to_world(plane.offset * plane.normal))};
}

Shape placed_sphere(const Sphere& sphere, const Transform& m) {
    double s = similarity_factor(m.linear);
    if (s > 0) {
        return Sphere{m.point_to_world(sphere.center), s * sphere.radius};
    }
    return Transformed<Sphere>(sphere, m);
}

Shape placed_cylinder(const Cylinder& cylinder, const Transform& m) {
    double s = similarity_factor(m.linear);
    if (s > 0) {
        return Cylinder{m.point_to_world(cylinder.base), m.point_to_world(cylinder.cap), s * cylinder.radius};
    }
    return Transformed<Cylinder>(cylinder, m);
}

Shape placed_box(const Box& box, const Transform& m) {
    int source[3];
    if (!is_signed_permutation(m.linear, source)) {
        return Transformed<Box>(box, m);
    }
    Box out;
    for (int i = 0; i < 3; ++i) {
        double v = m.linear.row[i][source[i]];
        double a = v * box.min[source[i]] + m.translation[i];
        double b = v * box.max[source[i]] + m.translation[i];
        out.min[i] = std::min(a, b);
        out.max[i] = std::max(a, b);
    }
    return out;
}

}  // namespace

Transform identity_transform() {
    return {math::identity_matrix<double>(), math::identity_matrix<double>(), {0, 0, 0}};
}

bool is_identity(const Transform& transform) {
    return is_identity(transform.linear) && transform.translation == Vec3{0, 0, 0};
}

Transform translation(const Vec3& offset) {
    return {math::identity_matrix<double>(), math::identity_matrix<double>(), offset};
}

Transform scaling(const Vec3& factors) {
    Matrix3 linear{{{factors.x, 0, 0}, {0, factors.y, 0}, {0, 0, factors.z}}};
    return affine(linear, {0, 0, 0});
}

// Rodrigues: L = c·I + s·[a]× + (1 − c)·a·aᵀ. About a coordinate axis at a multiple of 90°, c and s are 0 or ±1
// and a's components 0 or 1, so every entry is exact.
Transform rotation(const Vec3& axis, double degrees) {
    double c = 0, s = 0;
    cos_sin(degrees, c, s);
    const Vec3& a = axis;
    double k = 1 - c;
    Matrix3 linear{{{c + k * a.x * a.x, k * a.x * a.y - s * a.z, k * a.x * a.z + s * a.y},
                    {k * a.y * a.x + s * a.z, c + k * a.y * a.y, k * a.y * a.z - s * a.x},
                    {k * a.z * a.x - s * a.y, k * a.z * a.y + s * a.x, c + k * a.z * a.z}}};
    return affine(linear, {0, 0, 0});
}

Transform rotation_xyz(const Vec3& degrees) {
    Transform out = identity_transform();
    for (int axis = 0; axis < 3; ++axis) {
        Vec3 unit{axis == 0 ? 1.0 : 0.0, axis == 1 ? 1.0 : 0.0, axis == 2 ? 1.0 : 0.0};
        out = math::composed(rotation(unit, degrees[axis]), out);
    }
    return out;
}

Transform affine(const Matrix3& linear, const Vec3& offset) {
    return {linear, math::inverse_of(linear), offset};
}

double condition_number(const Transform& transform) {
    if (!(math::determinant(transform.linear) != 0)) {
        return std::numeric_limits<double>::infinity();
    }
    return math::frobenius_norm(transform.linear) * math::frobenius_norm(transform.inverse);
}

Shape placed(const Shape& primitive, const Transform& to_world) {
    if (is_identity(to_world)) {
        return primitive;
    }
    return std::visit(
        [&](const auto& shape) -> Shape {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (std::is_same_v<S, Plane>) {
                return placed_plane(shape, to_world);
            } else if constexpr (std::is_same_v<S, Sphere>) {
                return placed_sphere(shape, to_world);
            } else if constexpr (std::is_same_v<S, Cylinder>) {
                return placed_cylinder(shape, to_world);
            } else if constexpr (std::is_same_v<S, Box>) {
                return placed_box(shape, to_world);
            } else if constexpr (std::is_same_v<S, Csg>) {
                return shape;  // the loader places a CSG object's leaves, each with its own transform
            } else {
                return placed(Shape{shape.shape()}, math::composed(to_world, shape.to_world()));
            }
        },
        primitive);
}

void place(MeshData& mesh, const Transform& to_world) {
    if (is_identity(to_world)) {
        return;
    }
    for (Vec3& vertex : mesh.vertices) {
        vertex = to_world.point_to_world(vertex);
    }
    for (Vec3& normal : mesh.normals) {
        normal = math::normalize(to_world.normal_to_world(normal));
    }
}

Scene flattened(const Scene& scene) {
    Scene out = scene;
    for (Mesh& mesh : out.meshes) {
        if (!mesh.placement) {
            continue;
        }
        auto data = std::make_shared<MeshData>(*mesh.data);
        place(*data, mesh.placement->transform());
        data->degenerate = degenerate_triangles(*data);
        mesh = Mesh{std::move(data), mesh.material, mesh.leaf, std::nullopt};
    }
    out.mesh_shapes.clear();
    return out;
}

}  // namespace twinray::scene
