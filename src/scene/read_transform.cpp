// An object's "transform": a list of steps applied in order (docs/scene-format.md, "Transforms").
#include "scene/read_scene.h"

#include "scene/placement.h"

#include <cmath>
#include <optional>
#include <string>

namespace twinray::scene {
namespace {

constexpr std::string_view steps_expected =
    "a list of transform steps, each {\"translate\": [x, y, z]}, {\"scale\": s or [sx, sy, sz]}, "
    "{\"rotate\": [ax, ay, az] or {\"axis\": [x, y, z], \"deg\": a}} or {\"matrix\": [[…], […], […]]} (3 rows of 4)";

const Schema step_schema{"a transform step", {}, {"translate", "scale", "rotate", "matrix"}};
const Schema axis_rotation_schema{"a rotation about an axis", {"axis", "deg"}, {}};

double require_scale_factor(const Node& node) {
    double factor = require_number(node);
    if (factor == 0) {
        refuse(node.path(), "a scale factor must be non-zero (a negative one mirrors), got 0");
    }
    return factor;
}

Transform read_scale(const Node& node) {
    if (node.json().is_number()) {
        double s = require_scale_factor(node);
        return scaling({s, s, s});
    }
    const std::vector<Node> factors = require_array(node, "a number or an array of 3 non-zero numbers");
    if (factors.size() != 3) {
        refuse(node.path(), "expected a number or 3 factors [sx, sy, sz], got " + std::to_string(factors.size()));
    }
    return scaling(
        {require_scale_factor(factors[0]), require_scale_factor(factors[1]), require_scale_factor(factors[2])});
}

Transform read_rotation(const Node& node) {
    if (!node.json().is_object()) {
        return rotation_xyz(require_vec3(node));
    }
    require_keys_of(node, axis_rotation_schema);
    const Node axis = at(node, "axis");
    const Vec3 direction = require_vec3(axis);
    if (is_zero(direction)) {
        refuse(axis.path(), "a rotation's axis must be non-zero, got [0, 0, 0]");
    }
    return rotation(normalized(direction), require_number(at(node, "deg")));
}

Transform read_matrix(const Node& node) {
    const std::vector<Node> rows = require_array(node, "3 rows of 4 numbers [a, b, c, t]");
    if (rows.size() != 3) {
        refuse(node.path(), "expected 3 rows of 4 numbers (the 3 × 4 matrix [L | t], row-major), got " +
                                std::to_string(rows.size()) + " rows");
    }
    Matrix3 linear;
    Vec3 offset;
    for (std::size_t i = 0; i < 3; ++i) {
        const std::vector<Node> entries = require_array(rows[i], "a row of 4 numbers");
        if (entries.size() != 4) {
            refuse(rows[i].path(), "expected 4 numbers, got " + std::to_string(entries.size()));
        }
        for (std::size_t j = 0; j < 3; ++j) {
            linear.row[i][static_cast<int>(j)] = require_number(entries[j]);
        }
        offset[static_cast<int>(i)] = require_number(entries[3]);
    }
    if (!(math::determinant(linear) != 0)) {
        refuse(node.path(), "the matrix is singular (its 3 × 3 part has determinant 0): it flattens the object");
    }
    return affine(linear, offset);
}

Transform read_step(const Node& step) {
    require_object(step);
    require_keys_of(step, step_schema);
    std::vector<std::string_view> present;
    for (std::string_view key : step_schema.allowed) {
        if (find_key(step, key)) {
            present.push_back(key);
        }
    }
    if (present.size() != 1) {
        refuse(step.path(), present.empty() ? "a transform step holds one of translate, scale, rotate or matrix, got "
                                              "an empty object"
                                            : "a transform step holds one of translate, scale, rotate or matrix, "
                                              "this one holds " +
                                                  join(present) + "; write them as steps, in the order they apply");
    }
    const Node value = at(step, present.front());
    if (present.front() == "translate") {
        return translation(require_vec3(value));
    }
    if (present.front() == "scale") {
        return read_scale(value);
    }
    if (present.front() == "rotate") {
        return read_rotation(value);
    }
    return read_matrix(value);
}

bool is_finite(const Transform& m) {
    for (const Vec3& row : m.linear.row) {
        if (!math::is_finite(row)) {
            return false;
        }
    }
    for (const Vec3& row : m.inverse.row) {
        if (!math::is_finite(row)) {
            return false;
        }
    }
    return math::is_finite(m.translation);
}

}  // namespace

Transform read_transform(const Node& list) {
    Transform out = identity_transform();
    for (const Node& step : require_array(list, steps_expected)) {
        out = math::composed(read_step(step), out);
    }
    return out;
}

std::optional<std::string> why_unusable(const Transform& to_world) {
    if (!is_finite(to_world)) {
        return "the transform's entries (or its inverse's) overflow double: not all finite";
    }
    const double condition = condition_number(to_world);
    if (!(condition <= max_transform_condition)) {
        return std::isinf(condition)
                   ? std::string("the transform is singular (determinant 0): it flattens the object")
                   : "the transform is too badly conditioned: its condition number ‖L‖·‖L⁻¹‖ (Frobenius) is " +
                         format_number(condition) + ", the limit is " + format_number(max_transform_condition) +
                         " (a float ray carried into the object's space would lose a share κ·2⁻²⁴ of its size; "
                         "an eccentricity of 1e4 passes)";
    }
    return std::nullopt;
}

void require_usable(const Node& where, const Transform& to_world) {
    if (const std::optional<std::string> problem = why_unusable(to_world)) {
        refuse(where.path(), *problem);
    }
}

}  // namespace twinray::scene
