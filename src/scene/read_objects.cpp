// The scene's objects: primitives, and CSG trees of them.
#include "scene/read_scene.h"

#include <algorithm>
#include <variant>

namespace twinray::scene {
namespace {

using Shape = decltype(Object::shape);

// A top-level object is level 1; each CSG child is one level deeper than its parent.
constexpr int max_object_nesting = 64;

Shape read_plane(const Node& node) {
    const Node normal = at(node, "normal");
    const Vec3 n = require_vec3(normal);
    if (is_zero(n)) {
        refuse(normal.path(), "must be non-zero (it gives the plane's orientation), got [0, 0, 0]");
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
            refuse(max.path(), "must be greater than min on every axis, but on " + std::string(1, "xyz"[axis]) +
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
        refuse(key_path(object.path(), "type"), "missing required key \"type\"; allowed types: " + object_types());
    }
    const std::string_view name = require_string(*type);
    for (const ObjectKind& kind : object_kinds) {
        if (kind.type == name) {
            return kind;
        }
    }
    refuse(type->path(), "unknown object type " + in_quotes(name) + "; allowed types: " + object_types());
}

// Reads the objects of one top-level element; `names` are the material names objects may use.
class ObjectReader {
public:
    ObjectReader(const std::vector<std::string>& names, std::size_t max_primitives, Scene& scene)
        : names_(names), max_primitives_(max_primitives), scene_(scene) {}

    // `level` bounds the recursion (max_object_nesting); `inherited_material` is that of the nearest
    // ancestor naming one, else the default.
    Object read(const Node& node, int level, int inherited_material) {
        if (level > max_object_nesting) {
            refuse(node.path(), "objects nested deeper than " + std::to_string(max_object_nesting) +
                                    " levels; a top-level object is level 1 and each CSG child one level deeper");
        }
        const ObjectKind& kind = require_object_kind(node);
        require_keys_of(node, kind.schema);
        const int material = read_or(node, "material", inherited_material,
                                     [this](const Node& name) { return require_material_name(name); });
        if (const CsgOp* op = std::get_if<CsgOp>(&kind.shape)) {
            return Object{read_csg(node, *op, level, material), material, -1};
        }
        if (scene_.leaf_paths.size() == max_primitives_) {
            refuse(node.path(),
                   over_primitive_limit("primitive number " + std::to_string(max_primitives_ + 1) + " of the scene",
                                        max_primitives_));
        }
        Shape shape = std::get<Shape (*)(const Node&)>(kind.shape)(node);
        const int leaf = static_cast<int>(scene_.leaf_paths.size());
        scene_.leaf_paths.push_back(node.path());
        scene_.leaf_materials.push_back(material);
        return Object{std::move(shape), material, leaf};
    }

private:
    // Index 0, the built-in default, has no name a scene can use.
    int require_material_name(const Node& node) const {
        const std::string_view name = require_string(node);
        const auto found = std::find(names_.begin() + 1, names_.end(), name);
        if (found == names_.end()) {
            const std::vector<std::string_view> defined(names_.begin() + 1, names_.end());
            refuse(node.path(),
                   "unknown material " + in_quotes(name) + "; " +
                       (defined.empty() ? "the scene defines no materials" : "materials defined: " + join(defined)));
        }
        return static_cast<int>(found - names_.begin());
    }

    Csg read_csg(const Node& node, CsgOp op, int level, int material) {
        const Node children = at(node, "children");
        const std::vector<Node> elements = require_array(children, "an array of objects");
        if (elements.size() < 2) {
            refuse(children.path(), "expected at least 2 objects, got " + std::to_string(elements.size()));
        }
        Csg csg{op, {}};
        for (const Node& child : elements) {
            csg.children.push_back(read(child, level + 1, material));
        }
        return csg;
    }

    const std::vector<std::string>& names_;
    const std::size_t max_primitives_;
    Scene& scene_;
};

}  // namespace

void read_top_level_object(const Node& element, const std::vector<std::string>& material_names,
                           std::size_t max_primitives, Scene& scene) {
    const std::size_t leaves_before = scene.leaf_paths.size();
    scene.objects.push_back(ObjectReader(material_names, max_primitives, scene).read(element, 1, 0));
    const std::size_t leaves = scene.leaf_paths.size() - leaves_before;
    if (leaves > static_cast<std::size_t>(max_csg_leaves)) {
        refuse(element.path(),
               "a CSG object may hold at most " + std::to_string(max_csg_leaves) +
                   " primitives (the SSE tracer keeps its span lists in fixed-size arrays), this one holds " +
                   std::to_string(leaves) + "; split it into several objects");
    }
}

}  // namespace twinray::scene
