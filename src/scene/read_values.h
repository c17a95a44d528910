// Reading a value of a scene file against the contract: a Node is a JSON value with its place in the
// document, so that every check can name the JSON path where it failed; the path is only spelled out
// for a refusal (and for the primitives' ids), never for a value that passes.
#pragma once

#include "scene/json_tree.h"
#include "scene/refusal.h"
#include "scene/scene.h"

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace twinray::scene {

// A value and where it is: a member (by key) or an element (by index) of its parent, which must
// outlive it.
class Node {
public:
    static Node root(JsonValue json) { return Node(json, nullptr, {}, 0); }
    Node member(JsonValue value, std::string_view key) const { return Node(value, this, key, 0); }
    Node element(JsonValue value, std::size_t index) const { return Node(value, this, {}, index, false); }

    const JsonValue& json() const { return json_; }
    std::string path() const;

private:
    Node(JsonValue json, const Node* parent, std::string_view key, std::size_t index, bool is_member = true)
        : json_(json), parent_(parent), key_(key), index_(index), is_member_(is_member) {}

    JsonValue json_;
    const Node* parent_;
    std::string_view key_;
    std::size_t index_;
    bool is_member_;
};

// The keys one kind of JSON object may hold; messages list required keys first, then optional ones.
struct Schema {
    Schema(std::string_view noun, std::vector<std::string_view> required, std::vector<std::string_view> optional);

    std::string_view noun;  // "a sphere", "the camera"
    std::vector<std::string_view> required;
    std::vector<std::string_view> allowed;  // required, then optional
};

std::string format_vec3(const Vec3& v);
std::string join(const std::vector<std::string_view>& words);
// Scalars as written; containers only by their shape, since printing them could be huge.
std::string describe(const JsonValue& value);

void require_object(const Node& node);
// Unknown keys are refused because they are usually typos; missing required keys are refused here so
// that readers can take every required key as present.
void require_keys_of(const Node& object, const Schema& schema);
std::optional<Node> find_key(const Node& object, std::string_view key);
// For keys that require_keys_of has already proven present.
Node at(const Node& object, std::string_view key);

template <class T, class Read>
T read_or(const Node& object, std::string_view key, T fallback, Read read) {
    const std::optional<Node> field = find_key(object, key);
    return field ? read(*field) : fallback;
}

std::vector<Node> require_array(const Node& node, std::string_view expected);
std::string_view require_string(const Node& node);
double require_number(const Node& node);
bool require_boolean(const Node& node);

// The contract's real-valued limits: an open or closed lower bound, an optional open upper bound.
struct Range {
    double low;
    bool low_inclusive;
    double high = std::numeric_limits<double>::infinity();

    bool contains(double value) const { return (low_inclusive ? value >= low : value > low) && value < high; }
    std::string describe() const;
};

constexpr Range non_negative{0, true};
constexpr Range positive{0, false};
constexpr Range field_of_view{0, false, 180};

double require_number_in(const Node& node, const Range& range);
int require_integer_in(const Node& node, int low, int high);

inline auto number_in(Range range) {
    return [range](const Node& node) { return require_number_in(node, range); };
}

// Written 5 or 5.0 alike; 2.5 is refused with the same message as an out-of-range value.
inline auto integer_in(int low, int high) {
    return [low, high](const Node& node) { return require_integer_in(node, low, high); };
}

Vec3 require_vec3(const Node& node);
Vec3 require_color(const Node& node);

void require_distinct(const Node& second, const Vec3& second_point, std::string_view first_name,
                      const Vec3& first_point);

// Vector arithmetic needed by the geometric rules.
Vec3 minus(const Vec3& a, const Vec3& b);
bool is_zero(const Vec3& v);
// For a finite non-zero v.
Vec3 normalized(const Vec3& v);
double sine_of_angle(const Vec3& a, const Vec3& b);

}  // namespace twinray::scene
