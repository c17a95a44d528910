#include "scene/read_values.h"

#include <nlohmann/json.hpp>

#include <algorithm>

namespace twinray::scene {
namespace {

std::string element_count(std::size_t count) {
    return std::to_string(count) + (count == 1 ? " element" : " elements");
}

Vec3 require_triple(const Node& node, double (*read_component)(const Node&)) {
    const JsonValue& array = node.json();
    if (!array.is_array()) {
        refuse(node.path(), "expected an array of 3 numbers, got " + describe(array));
    }
    if (array.size() != 3) {
        refuse(node.path(), "expected an array of 3 numbers, got " + element_count(array.size()));
    }
    const JsonValue first = array.first_child();
    const JsonValue second = first.next_sibling();
    return {read_component(node.element(first, 0)), read_component(node.element(second, 1)),
            read_component(node.element(second.next_sibling(), 2))};
}

double require_non_negative(const Node& node) {
    return require_number_in(node, non_negative);
}

Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double length(const Vec3& v) {
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

}  // namespace

std::string in_quotes(std::string_view text) {
    return nlohmann::json(text).dump();
}

std::string Node::path() const {
    if (parent_ == nullptr) {
        return "";
    }
    std::string path = parent_->path();
    if (!is_member_) {
        char digits[24];
        path += '[';
        path.append(digits, std::to_chars(std::begin(digits), std::end(digits), index_).ptr);
        path += ']';
    } else {
        path += path.empty() ? "" : ".";
        path += key_;
    }
    return path;
}

Schema::Schema(std::string_view noun_, std::vector<std::string_view> required_, std::vector<std::string_view> optional)
    : noun(noun_), required(std::move(required_)), allowed(required) {
    allowed.insert(allowed.end(), optional.begin(), optional.end());
}

std::string format_vec3(const Vec3& v) {
    return "[" + format_number(v[0]) + ", " + format_number(v[1]) + ", " + format_number(v[2]) + "]";
}

std::string join(const std::vector<std::string_view>& words) {
    std::string text;
    for (const std::string_view word : words) {
        text += (text.empty() ? "" : ", ") + std::string(word);
    }
    return text;
}

std::string describe(const JsonValue& value) {
    if (value.is_object()) {
        return "an object";
    }
    if (value.is_array()) {
        return "an array of " + element_count(value.size());
    }
    return value.dump();
}

void require_object(const Node& node) {
    if (!node.json().is_object()) {
        refuse(node.path(), "expected an object, got " + describe(node.json()));
    }
}

void require_keys_of(const Node& object, const Schema& schema) {
    require_object(object);
    const std::vector<std::string_view>& allowed = schema.allowed;
    JsonValue member = object.json().first_child();
    for (std::size_t i = 0; i < object.json().size(); ++i, member = member.next_sibling()) {
        if (std::find(allowed.begin(), allowed.end(), member.key()) == allowed.end()) {
            refuse(key_path(object.path(), member.key()), "unknown key " + in_quotes(member.key()) +
                                                              "; allowed keys for " + std::string(schema.noun) + ": " +
                                                              join(allowed));
        }
    }
    for (const std::string_view key : schema.required) {
        if (!object.json().find(key)) {
            refuse(key_path(object.path(), key), "missing required key " + in_quotes(key) + "; required keys for " +
                                                     std::string(schema.noun) + ": " + join(schema.required));
        }
    }
}

std::optional<Node> find_key(const Node& object, std::string_view key) {
    const std::optional<JsonValue> found = object.json().find(key);
    if (!found) {
        return std::nullopt;
    }
    return object.member(*found, key);
}

Node at(const Node& object, std::string_view key) {
    return object.member(*object.json().find(key), key);
}

std::vector<Node> require_array(const Node& node, std::string_view expected) {
    if (!node.json().is_array()) {
        refuse(node.path(), "expected " + std::string(expected) + ", got " + describe(node.json()));
    }
    std::vector<Node> elements;
    elements.reserve(node.json().size());
    JsonValue element = node.json().first_child();
    for (std::size_t i = 0; i < node.json().size(); ++i, element = element.next_sibling()) {
        elements.push_back(node.element(element, i));
    }
    return elements;
}

std::string_view require_string(const Node& node) {
    if (!node.json().is_string()) {
        refuse(node.path(), "expected a string, got " + describe(node.json()));
    }
    return node.json().string();
}

// Finite by construction: JSON cannot spell NaN or infinity, and the parser refuses overflow (1e999).
double require_number(const Node& node) {
    if (!node.json().is_number()) {
        refuse(node.path(), "expected a number, got " + describe(node.json()));
    }
    return node.json().number();
}

bool require_boolean(const Node& node) {
    if (!node.json().is_boolean()) {
        refuse(node.path(), "expected true or false, got " + describe(node.json()));
    }
    return node.json().boolean();
}

std::string Range::describe() const {
    const std::string lower = (low_inclusive ? ">= " : "> ") + format_number(low);
    return std::isinf(high) ? lower : lower + " and < " + format_number(high);
}

double require_number_in(const Node& node, const Range& range) {
    const double value = require_number(node);
    if (!range.contains(value)) {
        refuse(node.path(), "must be " + range.describe() + ", got " + describe(node.json()));
    }
    return value;
}

int require_integer_in(const Node& node, int low, int high) {
    const double value = require_number(node);
    if (!(std::floor(value) == value && value >= low && value <= high)) {
        refuse(node.path(), "must be an integer from " + std::to_string(low) + " to " + std::to_string(high) +
                                ", got " + describe(node.json()));
    }
    return static_cast<int>(value);
}

Vec3 require_vec3(const Node& node) {
    return require_triple(node, require_number);
}

Vec3 require_color(const Node& node) {
    return require_triple(node, require_non_negative);
}

void require_distinct(const Node& second, const Vec3& second_point, std::string_view first_name,
                      const Vec3& first_point) {
    if (second_point[0] == first_point[0] && second_point[1] == first_point[1] && second_point[2] == first_point[2]) {
        refuse(second.path(), "must differ from " + std::string(first_name) + ", both are " + format_vec3(first_point));
    }
}

Vec3 minus(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

bool is_zero(const Vec3& v) {
    return v[0] == 0 && v[1] == 0 && v[2] == 0;
}

// Dividing by the largest component first keeps the squared length from overflowing (1e200) or
// underflowing (1e-200).
Vec3 normalized(const Vec3& v) {
    const double largest = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
    const Vec3 scaled{v[0] / largest, v[1] / largest, v[2] / largest};
    const double scaled_length = length(scaled);
    return {scaled[0] / scaled_length, scaled[1] / scaled_length, scaled[2] / scaled_length};
}

double sine_of_angle(const Vec3& a, const Vec3& b) {
    return is_zero(a) || is_zero(b) ? 0 : length(cross(normalized(a), normalized(b)));
}

}  // namespace twinray::scene
