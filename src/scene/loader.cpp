// Reads twinray-scene/1 (docs/scene-format.md) in two passes over the text. A SAX scan first refuses
// what the document tree can no longer show: syntax errors (with their line and column), duplicate
// keys (the tree keeps only the last) and runaway nesting. The tree is then read against the contract,
// one helper per kind of value, and every refusal names the JSON path of the offending value.
#include "scene/loader.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <system_error>
#include <variant>
#include <vector>

namespace twinray::scene {

namespace {

// Ordered, so that named materials are numbered in file order.
using Json = nlohmann::ordered_json;
using Shape = decltype(Object::shape);

// Far beyond any real scene, and low enough that nothing recursing over the tree can exhaust the stack.
constexpr std::size_t max_json_depth = 200;
// A top-level object is level 1; each CSG child is one level deeper than its parent.
constexpr int max_object_nesting = 64;
constexpr double min_up_sine = 1e-6;

// A refusal found while reading; parse_scene adds the source name.
struct Refusal {
    std::string location;
    std::string problem;
};

std::string key_path(const std::string& parent, std::string_view key) {
    return parent.empty() ? std::string(key) : parent + "." + std::string(key);
}

std::string index_path(const std::string& parent, std::size_t index) {
    return parent + "[" + std::to_string(index) + "]";
}

[[noreturn]] void refuse(const std::string& path, std::string problem) {
    throw Refusal{path.empty() ? "(root)" : path, std::move(problem)};
}

std::string in_quotes(std::string_view text) {
    return Json(text).dump();
}

std::string format_number(double value) {
    char digits[32];  // the shortest round-trip form of any double fits in 24
    return std::string(digits, std::to_chars(std::begin(digits), std::end(digits), value).ptr);
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

std::string element_count(std::size_t count) {
    return std::to_string(count) + (count == 1 ? " element" : " elements");
}

// Scalars as written; containers only by their shape, since printing them could be huge.
std::string describe(const Json& value) {
    if (value.is_object()) {
        return "an object";
    }
    if (value.is_array()) {
        return "an array of " + element_count(value.size());
    }
    return value.dump();
}

// ---------------------------------------------------------------------------------------------------
// First pass: syntax, duplicate keys, nesting depth.

std::string line_and_column(std::string_view text, std::size_t bytes_read) {
    // The parser counts the character it stopped at as read; at the end of the input that is one past
    // the last byte. Columns count bytes, not characters.
    const std::size_t offset = std::min(bytes_read == 0 ? 0 : bytes_read - 1, text.size());
    const std::string_view before = text.substr(0, offset);
    const auto line = 1 + std::count(before.begin(), before.end(), '\n');
    const std::size_t last_newline = before.rfind('\n');
    const std::size_t line_start = last_newline == std::string_view::npos ? 0 : last_newline + 1;
    return "line " + std::to_string(line) + ", column " + std::to_string(offset - line_start + 1);
}

// The parser quotes the bytes it stopped at, which may not be UTF-8; a message must stay printable.
std::string ascii_only(std::string_view text) {
    static constexpr char hex[] = "0123456789ABCDEF";
    std::string result;
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        result += byte < 0x80 ? std::string(1, c) : std::string{'\\', 'x', hex[byte >> 4], hex[byte & 15]};
    }
    return result;
}

// What follows the first `marker` in `text`, or all of `text` if there is none.
std::string_view after(std::string_view text, std::string_view marker) {
    const std::size_t found = text.find(marker);
    return found == std::string_view::npos ? text : text.substr(found + marker.size());
}

// "[json.exception.parse_error.101] parse error at line 1, column 5: syntax error ..." keeps only
// "syntax error ...": the position is reported separately, computed from the byte offset.
std::string plain_parser_message(const Json::exception& error) {
    std::string_view message = after(error.what(), "] ");
    if (message.starts_with("parse error")) {
        message = after(message, ": ");
    }
    // The parser's one refusal that is not a syntax error (406): a number beyond the range of double.
    const std::string allowed =
        error.id == 406
            ? "; numbers must be finite, at most " + format_number(std::numeric_limits<double>::max()) + " in magnitude"
            : "";
    return ascii_only(message) + allowed;
}

class SyntaxScan final : public nlohmann::json_sax<Json> {
public:
    explicit SyntaxScan(std::string_view text) : text_(text) {}

    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t) override { return value(); }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t, const string_t&) override { return value(); }
    bool string(string_t&) override { return value(); }
    bool binary(binary_t&) override { return value(); }
    bool start_object(std::size_t) override { return open(true); }
    bool start_array(std::size_t) override { return open(false); }
    bool end_object() override { return close(); }
    bool end_array() override { return close(); }

    bool key(string_t& name) override {
        Level& object = levels_.back();
        object.key = name;
        if (!object.keys.insert(name).second) {
            refuse(path(), "duplicate key " + in_quotes(name) + "; a key may appear only once in an object");
        }
        return true;
    }

    bool parse_error(std::size_t bytes_read, const std::string&, const Json::exception& error) override {
        throw Refusal{line_and_column(text_, bytes_read), plain_parser_message(error)};
    }

private:
    struct Level {
        bool is_object;
        std::set<std::string> keys;
        std::string key;
        std::size_t elements = 0;
    };

    bool value() {
        if (!levels_.empty() && !levels_.back().is_object) {
            ++levels_.back().elements;
        }
        return true;
    }

    bool open(bool is_object) {
        value();
        if (levels_.size() == max_json_depth) {
            refuse(path(), "nested deeper than " + std::to_string(max_json_depth) +
                               " levels of arrays and objects, the most a scene may use");
        }
        levels_.push_back(Level{is_object, {}, {}, 0});
        return true;
    }

    bool close() {
        levels_.pop_back();
        return true;
    }

    // The path of the value being read (the last key or element of each open level).
    std::string path() const {
        std::string result;
        for (const Level& level : levels_) {
            result = level.is_object ? key_path(result, level.key) : index_path(result, level.elements - 1);
        }
        return result;
    }

    std::string_view text_;
    std::vector<Level> levels_;
};

Json parse_json(std::string_view text) {
    SyntaxScan scan(text);
    // Every stop of the scan throws a Refusal, so the result carries no news.
    static_cast<void>(Json::sax_parse(text.begin(), text.end(), &scan));
    return Json::parse(text.begin(), text.end());
}

// ---------------------------------------------------------------------------------------------------
// Second pass: the document against the contract.

// A value of the document with its path, so that every check can say where it failed.
struct Node {
    const Json& json;
    std::string path;
};

// The keys one kind of JSON object may hold; messages list required keys first, then optional ones.
struct Schema {
    std::string_view noun;  // "a sphere", "the camera"
    std::vector<std::string_view> required;
    std::vector<std::string_view> optional;

    std::vector<std::string_view> allowed() const {
        std::vector<std::string_view> keys = required;
        keys.insert(keys.end(), optional.begin(), optional.end());
        return keys;
    }
};

void require_object(const Node& node) {
    if (!node.json.is_object()) {
        refuse(node.path, "expected an object, got " + describe(node.json));
    }
}

// Unknown keys are refused because they are usually typos; missing required keys are refused here so
// that readers can take every required key as present.
void require_keys_of(const Node& object, const Schema& schema) {
    require_object(object);
    const std::vector<std::string_view> allowed = schema.allowed();
    for (const auto& [key, value] : object.json.items()) {
        if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
            refuse(key_path(object.path, key), "unknown key " + in_quotes(key) + "; allowed keys for " +
                                                   std::string(schema.noun) + ": " + join(allowed));
        }
    }
    for (const std::string_view key : schema.required) {
        if (!object.json.contains(key)) {
            refuse(key_path(object.path, key), "missing required key " + in_quotes(key) + "; required keys for " +
                                                   std::string(schema.noun) + ": " + join(schema.required));
        }
    }
}

std::optional<Node> find_key(const Node& object, std::string_view key) {
    const auto found = object.json.find(key);
    if (found == object.json.end()) {
        return std::nullopt;
    }
    return Node{*found, key_path(object.path, key)};
}

// For keys that require_keys_of has already proven present.
Node at(const Node& object, std::string_view key) {
    return Node{object.json.at(key), key_path(object.path, key)};
}

template <class T, class Read>
T read_or(const Node& object, std::string_view key, T fallback, Read read) {
    const std::optional<Node> field = find_key(object, key);
    return field ? read(*field) : fallback;
}

std::vector<Node> require_array(const Node& node, std::string_view expected) {
    if (!node.json.is_array()) {
        refuse(node.path, "expected " + std::string(expected) + ", got " + describe(node.json));
    }
    std::vector<Node> elements;
    for (std::size_t i = 0; i < node.json.size(); ++i) {
        elements.push_back(Node{node.json[i], index_path(node.path, i)});
    }
    return elements;
}

const std::string& require_string(const Node& node) {
    if (!node.json.is_string()) {
        refuse(node.path, "expected a string, got " + describe(node.json));
    }
    return node.json.get_ref<const std::string&>();
}

// Finite by construction: JSON cannot spell NaN or infinity, and the parser refuses overflow (1e999).
double require_number(const Node& node) {
    if (!node.json.is_number()) {
        refuse(node.path, "expected a number, got " + describe(node.json));
    }
    return node.json.get<double>();
}

// The contract's real-valued limits: an open or closed lower bound, an optional open upper bound.
struct Range {
    double low;
    bool low_inclusive;
    double high = std::numeric_limits<double>::infinity();

    bool contains(double value) const { return (low_inclusive ? value >= low : value > low) && value < high; }

    std::string describe() const {
        const std::string lower = (low_inclusive ? ">= " : "> ") + format_number(low);
        return std::isinf(high) ? lower : lower + " and < " + format_number(high);
    }
};

constexpr Range non_negative{0, true};
constexpr Range positive{0, false};
constexpr Range field_of_view{0, false, 180};

double require_number_in(const Node& node, const Range& range) {
    const double value = require_number(node);
    if (!range.contains(value)) {
        refuse(node.path, "must be " + range.describe() + ", got " + describe(node.json));
    }
    return value;
}

auto number_in(Range range) {
    return [range](const Node& node) { return require_number_in(node, range); };
}

// Written 5 or 5.0 alike; 2.5 is refused with the same message as an out-of-range value.
auto integer_in(int low, int high) {
    return [low, high](const Node& node) {
        const double value = require_number(node);
        if (!(std::floor(value) == value && value >= low && value <= high)) {
            refuse(node.path, "must be an integer from " + std::to_string(low) + " to " + std::to_string(high) +
                                  ", got " + describe(node.json));
        }
        return static_cast<int>(value);
    };
}

Vec3 require_triple(const Node& node, const std::function<double(const Node&)>& read_component) {
    const std::vector<Node> elements = require_array(node, "an array of 3 numbers");
    if (elements.size() != 3) {
        refuse(node.path, "expected an array of 3 numbers, got " + element_count(elements.size()));
    }
    return {read_component(elements[0]), read_component(elements[1]), read_component(elements[2])};
}

Vec3 require_vec3(const Node& node) {
    return require_triple(node, require_number);
}

Vec3 require_color(const Node& node) {
    return require_triple(node, number_in(non_negative));
}

// ---------------------------------------------------------------------------------------------------
// Vector arithmetic needed by the geometric rules.

Vec3 minus(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double length(const Vec3& v) {
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

bool is_zero(const Vec3& v) {
    return v == Vec3{0, 0, 0};
}

bool is_finite(const Vec3& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

// For a finite non-zero v. Dividing by the largest component first keeps the squared length from
// overflowing (1e200) or underflowing (1e-200).
Vec3 normalized(const Vec3& v) {
    const double largest = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
    const Vec3 scaled{v[0] / largest, v[1] / largest, v[2] / largest};
    const double scaled_length = length(scaled);
    return {scaled[0] / scaled_length, scaled[1] / scaled_length, scaled[2] / scaled_length};
}

double sine_of_angle(const Vec3& a, const Vec3& b) {
    return is_zero(a) || is_zero(b) ? 0 : length(cross(normalized(a), normalized(b)));
}

// ---------------------------------------------------------------------------------------------------
// The blocks of a scene.

const Schema scene_schema{"a scene",
                          {"camera", "objects"},
                          {"format", "image", "background", "ambient_light", "max_depth", "materials", "lights"}};
const Schema image_schema{"image", {}, {"width", "height"}};
const Schema camera_schema{"the camera", {"eye", "look_at"}, {"up", "fov_deg"}};
const Schema material_schema{
    "a material", {}, {"color", "ambient", "diffuse", "phong", "phong_size", "reflection", "transmission", "ior"}};
const Schema light_schema{"a light", {"position"}, {"color"}};

constexpr std::string_view format_name = "twinray-scene/1";

void require_format(const Node& node) {
    if (require_string(node) != format_name) {
        refuse(node.path, "must be " + in_quotes(format_name) + ", got " + describe(node.json));
    }
}

void require_distinct(const Node& second, const Vec3& second_point, std::string_view first_name,
                      const Vec3& first_point) {
    if (second_point == first_point) {
        refuse(second.path, "must differ from " + std::string(first_name) + ", both are " + format_vec3(first_point));
    }
}

void read_image(const Node& node, Scene& scene) {
    require_keys_of(node, image_schema);
    scene.width = read_or(node, "width", scene.width, integer_in(1, max_image_side));
    scene.height = read_or(node, "height", scene.height, integer_in(1, max_image_side));
}

// look_at - eye, which the up rule needs; coordinates so far apart that it overflows are refused.
Vec3 view_direction(const Node& look_at, const Camera& camera) {
    require_distinct(look_at, camera.look_at, "eye", camera.eye);
    const Vec3 forward = minus(camera.look_at, camera.eye);
    if (!is_finite(forward)) {
        refuse(look_at.path, "is too far from eye: look_at - eye overflows a double");
    }
    return forward;
}

void require_up_not_parallel(const Node& camera_node, const Vec3& up, const Vec3& forward) {
    const double sine = sine_of_angle(forward, up);
    if (!(sine >= min_up_sine)) {
        const std::string which_up = camera_node.json.contains("up") ? "up " : "the default up ";
        refuse(key_path(camera_node.path, "up"), which_up + format_vec3(up) + " is parallel to the view direction " +
                                                     format_vec3(forward) + "; the sine of their angle must be >= " +
                                                     format_number(min_up_sine) + ", got " + format_number(sine));
    }
}

Camera read_camera(const Node& node) {
    require_keys_of(node, camera_schema);
    Camera camera;
    camera.eye = require_vec3(at(node, "eye"));
    const Node look_at = at(node, "look_at");
    camera.look_at = require_vec3(look_at);
    const Vec3 forward = view_direction(look_at, camera);
    camera.up = read_or(node, "up", camera.up, require_vec3);
    require_up_not_parallel(node, camera.up, forward);
    camera.fov_deg = read_or(node, "fov_deg", camera.fov_deg, number_in(field_of_view));
    return camera;
}

Material read_material(const Node& node) {
    require_keys_of(node, material_schema);
    Material material;
    material.color = read_or(node, "color", material.color, require_color);
    material.ambient = read_or(node, "ambient", material.ambient, number_in(non_negative));
    material.diffuse = read_or(node, "diffuse", material.diffuse, number_in(non_negative));
    material.phong = read_or(node, "phong", material.phong, number_in(non_negative));
    material.phong_size = read_or(node, "phong_size", material.phong_size, number_in(positive));
    material.reflection = read_or(node, "reflection", material.reflection, number_in(non_negative));
    material.transmission = read_or(node, "transmission", material.transmission, number_in(non_negative));
    material.ior = read_or(node, "ior", material.ior, number_in(positive));
    return material;
}

void read_materials(const Node& node, Scene& scene) {
    require_object(node);
    for (const auto& [name, value] : node.json.items()) {
        scene.materials.push_back(read_material(Node{value, key_path(node.path, name)}));
        scene.material_names.push_back(name);
    }
}

Light read_light(const Node& node) {
    require_keys_of(node, light_schema);
    Light light;
    light.position = require_vec3(at(node, "position"));
    light.color = read_or(node, "color", light.color, require_color);
    return light;
}

std::vector<Light> read_lights(const Node& node) {
    std::vector<Light> lights;
    for (const Node& element : require_array(node, "an array of lights")) {
        lights.push_back(read_light(element));
    }
    return lights;
}

// ---------------------------------------------------------------------------------------------------
// Objects.

Shape read_plane(const Node& node) {
    const Node normal = at(node, "normal");
    const Vec3 n = require_vec3(normal);
    if (is_zero(n)) {
        refuse(normal.path, "must be non-zero (it gives the plane's orientation), got [0, 0, 0]");
    }
    return Plane{normalized(n), require_number(at(node, "offset"))};
}

Shape read_sphere(const Node& node) {
    return Sphere{require_vec3(at(node, "center")), require_number_in(at(node, "radius"), positive)};
}

Shape read_cylinder(const Node& node) {
    const Vec3 base = require_vec3(at(node, "base"));
    const Node cap = at(node, "cap");
    const Vec3 cap_point = require_vec3(cap);
    require_distinct(cap, cap_point, "base", base);
    return Cylinder{base, cap_point, require_number_in(at(node, "radius"), positive)};
}

Shape read_box(const Node& node) {
    const Vec3 min = require_vec3(at(node, "min"));
    const Node max = at(node, "max");
    const Vec3 max_corner = require_vec3(max);
    for (std::size_t axis = 0; axis < 3; ++axis) {
        if (!(min[axis] < max_corner[axis])) {
            refuse(max.path, "must be greater than min on every axis, but on " + std::string(1, "xyz"[axis]) +
                                 " min is " + format_number(min[axis]) + " and max is " +
                                 format_number(max_corner[axis]));
        }
    }
    return Box{min, max_corner};
}

struct ObjectKind {
    std::string_view type;
    Schema schema;
    std::variant<Shape (*)(const Node&), CsgOp> shape;  // how a primitive is read, or which CSG node
};

Schema object_schema(std::string_view noun, std::vector<std::string_view> own_keys) {
    own_keys.insert(own_keys.begin(), "type");
    return Schema{noun, std::move(own_keys), {"material"}};
}

const ObjectKind object_kinds[] = {
    {"plane", object_schema("a plane", {"normal", "offset"}), read_plane},
    {"sphere", object_schema("a sphere", {"center", "radius"}), read_sphere},
    {"cylinder", object_schema("a cylinder", {"base", "cap", "radius"}), read_cylinder},
    {"box", object_schema("a box", {"min", "max"}), read_box},
    {"union", object_schema("a union", {"children"}), CsgOp::union_},
    {"intersection", object_schema("an intersection", {"children"}), CsgOp::intersection},
    {"difference", object_schema("a difference", {"children"}), CsgOp::difference},
};

std::string object_types() {
    std::vector<std::string_view> types;
    for (const ObjectKind& kind : object_kinds) {
        types.push_back(kind.type);
    }
    return join(types);
}

const ObjectKind& require_object_kind(const Node& object) {
    require_object(object);
    const std::optional<Node> type = find_key(object, "type");
    if (!type) {
        refuse(key_path(object.path, "type"), "missing required key \"type\"; allowed types: " + object_types());
    }
    const std::string& name = require_string(*type);
    for (const ObjectKind& kind : object_kinds) {
        if (kind.type == name) {
            return kind;
        }
    }
    refuse(type->path, "unknown object type " + in_quotes(name) + "; allowed types: " + object_types());
}

// Index 0, the built-in default, has no name a scene can use.
int require_material_name(const Node& node, const Scene& scene) {
    const std::string& name = require_string(node);
    const auto found = std::find(scene.material_names.begin() + 1, scene.material_names.end(), name);
    if (found == scene.material_names.end()) {
        const std::vector<std::string_view> defined(scene.material_names.begin() + 1, scene.material_names.end());
        refuse(node.path,
               "unknown material " + in_quotes(name) + "; " +
                   (defined.empty() ? "the scene defines no materials" : "materials defined: " + join(defined)));
    }
    return static_cast<int>(found - scene.material_names.begin());
}

// `level` bounds the recursion (max_object_nesting); `inherited_material` is that of the nearest
// ancestor naming one, else the default.
Object read_object(const Node& node, Scene& scene, int level, int inherited_material);

Csg read_csg(const Node& node, CsgOp op, Scene& scene, int level, int material) {
    const Node children = at(node, "children");
    const std::vector<Node> elements = require_array(children, "an array of objects");
    if (elements.size() < 2) {
        refuse(children.path, "expected at least 2 objects, got " + std::to_string(elements.size()));
    }
    Csg csg{op, {}};
    for (const Node& child : elements) {
        csg.children.push_back(read_object(child, scene, level + 1, material));
    }
    return csg;
}

Object read_object(const Node& node, Scene& scene, int level, int inherited_material) {
    if (level > max_object_nesting) {
        refuse(node.path, "objects nested deeper than " + std::to_string(max_object_nesting) +
                              " levels; a top-level object is level 1 and each CSG child one level deeper");
    }
    const ObjectKind& kind = require_object_kind(node);
    require_keys_of(node, kind.schema);
    const int material = read_or(node, "material", inherited_material,
                                 [&scene](const Node& name) { return require_material_name(name, scene); });
    if (const CsgOp* op = std::get_if<CsgOp>(&kind.shape)) {
        return Object{read_csg(node, *op, scene, level, material), material, -1};
    }
    Shape shape = std::get<Shape (*)(const Node&)>(kind.shape)(node);
    const int leaf = static_cast<int>(scene.leaf_paths.size());
    scene.leaf_paths.push_back(node.path);
    scene.leaf_materials.push_back(material);
    return Object{std::move(shape), material, leaf};
}

void read_objects(const Node& node, Scene& scene) {
    for (const Node& element : require_array(node, "an array of objects")) {
        const std::size_t leaves_before = scene.leaf_paths.size();
        scene.objects.push_back(read_object(element, scene, 1, 0));
        const std::size_t leaves = scene.leaf_paths.size() - leaves_before;
        if (leaves > static_cast<std::size_t>(max_csg_leaves)) {
            refuse(element.path,
                   "a CSG object may hold at most " + std::to_string(max_csg_leaves) +
                       " primitives (the SSE tracer keeps its span lists in fixed-size arrays), this one holds " +
                       std::to_string(leaves) + "; split it into several objects");
        }
    }
}

Scene read_scene(const Node& root) {
    require_keys_of(root, scene_schema);
    Scene scene;
    if (const std::optional<Node> format = find_key(root, "format")) {
        require_format(*format);
    }
    if (const std::optional<Node> image = find_key(root, "image")) {
        read_image(*image, scene);
    }
    scene.camera = read_camera(at(root, "camera"));
    scene.background = read_or(root, "background", scene.background, require_color);
    scene.ambient_light = read_or(root, "ambient_light", scene.ambient_light, require_color);
    scene.max_depth = read_or(root, "max_depth", scene.max_depth, integer_in(1, max_trace_depth));
    if (const std::optional<Node> materials = find_key(root, "materials")) {
        read_materials(*materials, scene);
    }
    scene.lights = read_or(root, "lights", scene.lights, read_lights);
    read_objects(at(root, "objects"), scene);
    return scene;
}

std::string error_message(const std::string& file, const std::string& location, const std::string& problem) {
    return location.empty() ? file + ": " + problem : file + ": " + location + ": " + problem;
}

std::string system_error_text() {
    return std::error_code(errno, std::generic_category()).message();
}

struct CloseFile {
    void operator()(std::FILE* stream) const { std::fclose(stream); }
};

}  // namespace

SceneError::SceneError(std::string file, std::string location, std::string problem)
    : std::runtime_error(error_message(file, location, problem)),
      file_(std::move(file)),
      location_(std::move(location)),
      problem_(std::move(problem)) {}

Scene parse_scene(std::string_view json_text, const std::string& source_name) {
    try {
        const Json document = parse_json(json_text);
        return read_scene(Node{document, ""});
    } catch (const Refusal& refusal) {
        throw SceneError(source_name, refusal.location, refusal.problem);
    }
}

Scene load_scene(const std::filesystem::path& file) {
    const std::unique_ptr<std::FILE, CloseFile> stream(std::fopen(file.c_str(), "rb"));
    if (!stream) {
        throw SceneError(file.string(), "", "cannot open file: " + system_error_text());
    }
    std::string text;
    char chunk[65536];
    while (const std::size_t count = std::fread(chunk, 1, sizeof chunk, stream.get())) {
        text.append(chunk, count);
    }
    // A directory opens but cannot be read (EISDIR).
    if (std::ferror(stream.get())) {
        throw SceneError(file.string(), "", "cannot read file: " + system_error_text());
    }
    return parse_scene(text, file.string());
}

}  // namespace twinray::scene
