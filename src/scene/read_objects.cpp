// The scene's objects: primitives, and CSG trees of them.
#include "scene/read_scene.h"

#include "scene/geometry.h"
#include "scene/loader.h"
#include "scene/mesh_file.h"
#include "scene/placement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
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

// A mesh is read apart from the other objects: it is not a Shape (meshes are surfaces, never CSG children).
struct MeshKind {};
// An instance places a declared shape (docs/scene-format.md, "Shapes and instances").
struct InstanceKind {};

struct ObjectKind {
    std::string_view type;
    Schema schema;
    // How a primitive is read, which CSG node, a mesh or an instance.
    std::variant<Shape (*)(const Node&), CsgOp, MeshKind, InstanceKind> shape;
};

Schema object_schema(std::string_view noun, std::vector<std::string_view> own_keys) {
    own_keys.insert(own_keys.begin(), "type");
    return Schema{noun, std::move(own_keys), {"material", "transform"}};
}

const ObjectKind object_kinds[] = {
    {"plane", object_schema("a plane", {"normal", "offset"}), read_plane},
    {"sphere", object_schema("a sphere", {"center", "radius"}), read_sphere},
    {"cylinder", object_schema("a cylinder", {"base", "cap", "radius"}), read_cylinder},
    {"box", object_schema("a box", {"min", "max"}), read_box},
    {"union", object_schema("a union", {"children"}), CsgOp::union_},
    {"intersection", object_schema("an intersection", {"children"}), CsgOp::intersection},
    {"difference", object_schema("a difference", {"children"}), CsgOp::difference},
    {"mesh",
     Schema{"a mesh", {"type"}, {"vertices", "triangles", "normals", "file", "smooth", "material", "transform"}},
     MeshKind{}},
    {"instance", Schema{"an instance", {"type", "shape"}, {"material", "transform"}}, InstanceKind{}},
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

// Each vertex's normal as the sum of its triangles' (b − a) × (c − a), whose length is twice the area: large
// triangles weigh more, slivers nothing. Computed here once, in double, so that both tracers shade with the
// same normals. A vertex no triangle with area uses keeps a zero normal, which shading passes over.
std::vector<Vec3> area_weighted_normals(const MeshData& mesh) {
    std::vector<Vec3> sums(mesh.vertices.size(), Vec3{0, 0, 0});
    for (const std::array<std::uint32_t, 3>& triangle : mesh.triangles) {
        const Vec3& a = mesh.vertices[triangle[0]];
        const Vec3 twice_area = cross(mesh.vertices[triangle[1]] - a, mesh.vertices[triangle[2]] - a);
        for (std::uint32_t corner : triangle) {
            sums[corner] = sums[corner] + twice_area;
        }
    }
    for (Vec3& sum : sums) {
        if (!is_zero(sum)) {
            sum = normalized(sum);
        }
    }
    return sums;
}

// Rows of three numbers; a top-level mesh's come packed (scene_stream.cpp), unless one is not three numbers.
std::vector<Vec3> read_points(const Node& node, std::string_view expected) {
    const JsonValue& rows = node.json();
    if (rows.is_packed_rows()) {
        std::vector<Vec3> points(rows.size());
        for (std::size_t i = 0; i < points.size(); ++i) {
            points[i] = {rows.row_number(i, 0), rows.row_number(i, 1), rows.row_number(i, 2)};
        }
        return points;
    }
    std::vector<Vec3> points;
    const std::vector<Node> elements = require_array(node, expected);
    points.reserve(elements.size());
    for (const Node& element : elements) {
        points.push_back(require_vec3(element));
    }
    return points;
}

// One corner of a triangle: an index of `vertex_count` vertices, an integer written as a JSON number. `path` and
// `written` give the corner's JSON path and its number as written, for the refusal.
template <class Path, class Written>
std::uint32_t require_vertex_index(double index, std::size_t vertex_count, const Path& path, const Written& written) {
    if (!(std::floor(index) == index && index >= 0 && index < static_cast<double>(vertex_count))) {
        refuse(path(), "must be a vertex index, an integer from 0 to " +
                           std::to_string(static_cast<long long>(vertex_count) - 1) + " (the mesh has " +
                           std::to_string(vertex_count) + " vertices), got " + written());
    }
    return static_cast<std::uint32_t>(index);
}

std::array<std::uint32_t, 3> read_triangle(const Node& node, std::size_t vertex_count) {
    const std::vector<Node> corners = require_array(node, "an array of 3 vertex indices");
    if (corners.size() != 3) {
        refuse(node.path(), "expected 3 vertex indices, got " + std::to_string(corners.size()));
    }
    std::array<std::uint32_t, 3> triangle{};
    for (std::size_t i = 0; i < 3; ++i) {
        triangle[i] = require_vertex_index(
            require_number(corners[i]), vertex_count, [&] { return corners[i].path(); },
            [&] { return describe(corners[i].json()); });
    }
    return triangle;
}

// Row `row` of packed triangles (`triangles` is their array).
std::array<std::uint32_t, 3> read_packed_triangle(const Node& triangles, std::size_t row, std::size_t vertex_count) {
    const JsonValue& rows = triangles.json();
    std::array<std::uint32_t, 3> triangle{};
    for (std::size_t i = 0; i < 3; ++i) {
        triangle[i] = require_vertex_index(
            rows.row_number(row, i), vertex_count, [&] { return index_path(index_path(triangles.path(), row), i); },
            [&] { return rows.row_dump(row, i); });
    }
    return triangle;
}

// The key a mesh must have when it names no file.
Node required_mesh_key(const Node& node, std::string_view key) {
    const std::optional<Node> value = find_key(node, key);
    if (!value) {
        refuse(key_path(node.path(), key), "missing required key " + in_quotes(key) +
                                               "; a mesh gives \"vertices\" and \"triangles\", or a \"file\"");
    }
    return *value;
}

MeshData read_inline_mesh(const Node& node, std::size_t triangles_allowed) {
    MeshData mesh;
    mesh.vertices = read_points(required_mesh_key(node, "vertices"), "an array of vertices [x, y, z]");
    const Node triangles = required_mesh_key(node, "triangles");
    const bool packed = triangles.json().is_packed_rows();
    const std::vector<Node> elements =
        packed ? std::vector<Node>{} : require_array(triangles, "an array of triangles [i, j, k]");
    const std::size_t count = packed ? triangles.json().size() : elements.size();
    if (count == 0) {
        refuse(triangles.path(), "a mesh needs at least one triangle, got none");
    }
    if (count > triangles_allowed) {
        refuse(triangles.path(),
               over_primitive_limit("its " + std::to_string(count) + " triangles", triangles_allowed));
    }
    mesh.triangles.reserve(count);
    for (std::size_t t = 0; t < count; ++t) {
        mesh.triangles.push_back(packed ? read_packed_triangle(triangles, t, mesh.vertices.size())
                                        : read_triangle(elements[t], mesh.vertices.size()));
    }
    if (const std::optional<Node> normals = find_key(node, "normals")) {
        mesh.normals = read_points(*normals, "an array of vertex normals [x, y, z]");
        if (mesh.normals.size() != mesh.vertices.size()) {
            refuse(normals->path(), "expected one normal per vertex (" + std::to_string(mesh.vertices.size()) +
                                        "), got " + std::to_string(mesh.normals.size()));
        }
        for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
            if (is_zero(mesh.normals[i])) {
                refuse(index_path(normals->path(), i), "a normal must be non-zero, got [0, 0, 0]");
            }
            mesh.normals[i] = normalized(mesh.normals[i]);
        }
    }
    return mesh;
}

// A mesh file (scene/mesh_file.h), relative to the scene file's folder; its refusal keeps the file's own
// location (a line, an element, a node) behind the JSON path of `file`.
MeshFileResult read_mesh_from_file(const Node& node, const Node& file, const std::filesystem::path& base_directory,
                                   std::size_t triangles_allowed) {
    for (std::string_view inline_key : {"vertices", "triangles", "normals"}) {
        if (const std::optional<Node> extra = find_key(node, inline_key)) {
            refuse(extra->path(),
                   "a mesh gives either a \"file\" or its " + std::string(inline_key) + " inline, not both");
        }
    }
    const std::string_view name = require_string(file);
    if (name.empty()) {
        refuse(file.path(), "expected the name of an OBJ, PLY, STL or glTF file, got an empty string");
    }
    const std::filesystem::path path = base_directory / std::filesystem::path(std::string(name));
    try {
        MeshFileResult result = read_mesh_file(path, triangles_allowed);
        for (MeshData& mesh : result.meshes) {
            mesh.file = std::string(name);
            // The readers pass the file's normals as written (non-zero, finite): unit length the same way as inline.
            for (Vec3& normal : mesh.normals) {
                normal = normalized(normal);
            }
        }
        return result;
    } catch (const SceneError& error) {
        refuse(file.path(), error.what());
    }
}

// The shading normals `smooth` asks for: absent, interpolated where the mesh has normals; true without normals,
// area-weighted vertex normals; false, flat whatever it has. In the mesh's own space, before its transform, so
// that they go through the inverse transpose as given normals do, and as an instance's shape's do.
void shade_mesh(const Node& node, MeshData& mesh) {
    mesh.smooth = read_or(node, "smooth", !mesh.normals.empty(), require_boolean);
    if (mesh.smooth && mesh.normals.empty()) {
        mesh.normals = area_weighted_normals(mesh);
    }
}

[[noreturn]] void refuse_unknown_shape(const Node& name, const std::vector<std::string_view>& declared) {
    refuse(name.path(), "unknown shape " + describe(name.json()) + "; " +
                            (declared.empty() ? "no \"shapes\" were read before \"objects\" (a scene declares its "
                                                "shapes before its objects)"
                                              : "shapes declared: " + join(declared)));
}

// Calls visit(to_world) for each primitive of `tree` held in its own space (scene::Transformed).
template <typename Visit>
void for_each_part_transform(const Object& tree, Visit&& visit) {
    std::visit(
        [&](const auto& shape) {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (std::is_same_v<S, Csg>) {
                for (const Object& child : shape.children) {
                    for_each_part_transform(child, visit);
                }
            } else if constexpr (requires { shape.to_world(); }) {
                visit(shape.to_world());
            }
        },
        tree.shape);
}

// Reads the objects of one top-level element; `names` are the material names objects may use.
class ObjectReader {
public:
    // `shapes`: those an instance may place, or null where the scene declares none. `reading_shapes`: the objects
    // read are shapes, which may not hold an instance.
    // `primitives`: what the primitive limit has counted so far (Scene::primitive_count, kept as it grows: a scene
    // of a million instances would recount them all at each).
    ObjectReader(const std::vector<std::string>& names, std::size_t max_primitives, std::size_t& primitives,
                 Scene& scene, std::filesystem::path base_directory, const DeclaredShapes* shapes,
                 bool reading_shapes = false)
        : names_(names),
          max_primitives_(max_primitives),
          primitives_(primitives),
          scene_(scene),
          base_directory_(std::move(base_directory)),
          shapes_(shapes),
          reading_shapes_(reading_shapes) {}

    // `level` bounds the recursion (max_object_nesting); `inherited_material` is that of the nearest
    // ancestor naming one, else the default; `placement` the CSG ancestors' transforms composed, if any.
    Object read(const Node& node, int level, int inherited_material, const std::optional<Transform>& placement) {
        if (level > max_object_nesting) {
            refuse(node.path(), "objects nested deeper than " + std::to_string(max_object_nesting) +
                                    " levels; a top-level object is level 1 and each CSG child one level deeper");
        }
        const ObjectKind& kind = require_object_kind(node);
        require_keys_of(node, kind.schema);
        const int material = read_or(node, "material", inherited_material,
                                     [this](const Node& name) { return require_material_name(name); });
        const std::optional<Transform> to_world = placed_by(node, placement);
        if (const CsgOp* op = std::get_if<CsgOp>(&kind.shape)) {
            return Object{read_csg(node, *op, level, material, to_world), material, -1};
        }
        if (std::holds_alternative<MeshKind>(kind.shape)) {
            refuse(node.path(), "a mesh may not be a CSG child (meshes are surfaces, not solids); place it in objects");
        }
        if (std::holds_alternative<InstanceKind>(kind.shape)) {
            const DeclaredShape& shape = require_shape(node);
            if (shape.mesh >= 0) {
                refuse(node.path(),
                       "an instance of mesh shape " + in_quotes(shape.name) +
                           " may not be a CSG child (meshes are surfaces, not solids); place it in objects");
            }
            return read_instanced(node, shape, level, material, to_world);
        }
        if (primitives_ == max_primitives_) {
            refuse(node.path(),
                   over_primitive_limit("primitive number " + std::to_string(max_primitives_ + 1) + " of the scene",
                                        max_primitives_));
        }
        ++primitives_;
        Shape shape = std::get<Shape (*)(const Node&)>(kind.shape)(node);
        if (to_world) {
            shape = placed(shape, *to_world);
        }
        const int leaf = static_cast<int>(scene_.leaf_paths.size());
        scene_.leaf_paths.push_back(instance_path_.empty() ? node.path() : instance_path_ + " (" + node.path() + ")");
        scene_.leaf_materials.push_back(material);
        return Object{std::move(shape), material, leaf};
    }

    // A top-level instance of a mesh shape: one leaf, the shape's triangles shared. Of any other shape, the shape
    // read in its place.
    Object read_top_level_instance(const Node& node) {
        require_keys_of(node, require_object_kind(node).schema);
        const DeclaredShape& shape = require_shape(node);
        const int material =
            read_or(node, "material", 0, [this](const Node& name) { return require_material_name(name); });
        const std::optional<Transform> to_world = placed_by(node, std::nullopt);
        if (shape.mesh < 0 && shape.solid < 0) {
            return read_instanced(node, shape, 1, material, to_world);
        }
        if (primitives_ == max_primitives_) {
            refuse(node.path(), over_primitive_limit("the instance", max_primitives_));
        }
        if (shape.solid >= 0) {
            add_solid_instance(node, material, to_world ? *to_world : identity_transform(), shape.solid);
            return Object{};
        }
        const MeshShape& mesh = scene_.mesh_shapes[static_cast<std::size_t>(shape.mesh)];
        add_instance(node.path(), mesh.material >= 0 ? mesh.material : material,
                     to_world ? *to_world : identity_transform(), shape.mesh);
        return Object{};
    }

    // A mesh of `shapes`: its vertices in its own space (a file's nodes' meshes placed into one), its triangles
    // counted towards the limit once.
    MeshShape read_mesh_shape(const Node& node, std::string name) {
        require_keys_of(node, require_object_kind(node).schema);
        const int material =
            read_or(node, "material", -1, [this](const Node& value) { return require_material_name(value); });
        MeshFileResult contents = read_mesh_contents(node);
        return MeshShape{std::move(name), finished_mesh(node, merged_mesh(node, std::move(contents))), material};
    }

    // A top-level mesh: one leaf, its triangles counted towards the primitive limit; or, for a file whose nodes
    // place its meshes otherwise than once each as they stand, an instance of each mesh for each node.
    void read_mesh(const Node& node) {
        require_keys_of(node, require_object_kind(node).schema);
        const int material =
            read_or(node, "material", 0, [this](const Node& name) { return require_material_name(name); });
        MeshFileResult contents = read_mesh_contents(node);
        if (!placed_as_they_stand(contents)) {
            read_mesh_instances(node, material, std::move(contents));
            return;
        }
        std::shared_ptr<const MeshData> data = finished_mesh(node, merged_mesh(node, std::move(contents)));
        const int leaf = static_cast<int>(scene_.leaf_paths.size());
        scene_.leaf_paths.push_back(node.path());
        scene_.leaf_materials.push_back(material);
        scene_.meshes.push_back(Mesh{std::move(data), material, leaf, std::nullopt});
    }

private:
    // A mesh object's meshes and the nodes that place them: its file's, or its inline mesh placed once as it stands.
    MeshFileResult read_mesh_contents(const Node& node) {
        const std::size_t triangles_allowed = max_primitives_ - primitives_;
        const std::optional<Node> file = find_key(node, "file");
        if (!file) {
            MeshFileResult contents;
            contents.meshes.push_back(read_inline_mesh(node, triangles_allowed));
            contents.nodes.emplace_back();
            return contents;
        }
        MeshFileResult read = read_mesh_from_file(node, *file, base_directory_, triangles_allowed);
        for (const std::string& warning : read.warnings) {
            scene_.warnings.push_back(file->path() + ": " + read.meshes.front().file + ": " + warning);
        }
        return read;
    }

    // Every mesh placed by one node at the identity: the file's meshes are where they are to be drawn.
    static bool placed_as_they_stand(const MeshFileResult& contents) {
        // Every mesh is placed by a node (mesh_file.h), so as many nodes as meshes place each once.
        return contents.nodes.size() == contents.meshes.size() &&
               std::all_of(contents.nodes.begin(), contents.nodes.end(),
                           [](const MeshNode& file_node) { return file_node.is_identity(); });
    }

    // A file's node transform; refused, at the mesh object's `file`, where it may not place anything.
    static Transform node_transform(const Node& node, const std::string& file, const MeshNode& file_node,
                                    const std::optional<Transform>& own) {
        const Transform of_node = affine(file_node.linear, file_node.translation);
        const Transform to_world = own ? math::composed(*own, of_node) : of_node;
        if (const std::optional<std::string> problem = why_unusable(to_world)) {
            refuse(at(node, "file").path(), file + ": node " + in_quotes(file_node.name) +
                                                (own ? ", followed by the object's transform: " : ": ") + *problem);
        }
        return to_world;
    }

    // The file's meshes placed by its nodes (vertices in double, normals through the inverse transpose), all in one
    // mesh; what the nodes place counted towards the limit before anything is copied.
    MeshData merged_mesh(const Node& node, MeshFileResult contents) {
        if (contents.nodes.size() == 1 && contents.nodes.front().is_identity()) {
            return std::move(contents.meshes.front());
        }
        std::size_t triangles = 0;
        std::size_t vertices = 0;
        for (const MeshNode& file_node : contents.nodes) {
            triangles += contents.meshes[file_node.mesh].triangles.size();
            vertices += contents.meshes[file_node.mesh].vertices.size();
        }
        const std::size_t triangles_allowed = max_primitives_ - primitives_;
        const std::string file = contents.meshes.front().file;
        if (triangles > triangles_allowed || vertices > 3 * triangles_allowed) {
            refuse(at(node, "file").path(),
                   file + ": " +
                       over_primitive_limit("its nodes place " + std::to_string(contents.nodes.size()) + " meshes of " +
                                                std::to_string(triangles) + " triangles and " +
                                                std::to_string(vertices) + " vertices in all",
                                            triangles_allowed));
        }
        const bool every_mesh_has_normals = std::all_of(contents.meshes.begin(), contents.meshes.end(),
                                                        [](const MeshData& mesh) { return mesh.smooth; });
        if (!every_mesh_has_normals && std::any_of(contents.meshes.begin(), contents.meshes.end(),
                                                   [](const MeshData& mesh) { return mesh.smooth; })) {
            scene_.warnings.push_back(at(node, "file").path() + ": " + file +
                                      ": normals are not used: some of its meshes have none");
        }
        MeshData merged;
        merged.file = file;
        merged.smooth = every_mesh_has_normals;
        merged.vertices.reserve(vertices);
        merged.triangles.reserve(triangles);
        for (const MeshNode& file_node : contents.nodes) {
            MeshData placed = contents.meshes[file_node.mesh];
            place(placed, node_transform(node, file, file_node, std::nullopt));
            const auto first = static_cast<std::uint32_t>(merged.vertices.size());
            merged.vertices.insert(merged.vertices.end(), placed.vertices.begin(), placed.vertices.end());
            for (const std::array<std::uint32_t, 3>& triangle : placed.triangles) {
                merged.triangles.push_back({first + triangle[0], first + triangle[1], first + triangle[2]});
            }
            if (every_mesh_has_normals) {
                merged.normals.insert(merged.normals.end(), placed.normals.begin(), placed.normals.end());
            }
        }
        return merged;
    }

    // A mesh as a leaf or a shape holds it: shaded as `smooth` asks, in its own space; placed by its object's own
    // transform; its degenerate triangles listed and its triangles counted.
    std::shared_ptr<const MeshData> finished_mesh(const Node& node, MeshData mesh) {
        auto data = std::make_shared<MeshData>(std::move(mesh));
        shade_mesh(node, *data);
        if (const std::optional<Transform> to_world = placed_by(node, std::nullopt)) {
            place(*data, *to_world);
        }
        data->degenerate = degenerate_triangles(*data);
        primitives_ += data->triangles.size();
        return data;
    }

    // A file's nodes at the top level: each of its meshes a mesh shape, read once and counted once; each node an
    // instance of its mesh, one leaf counted one, placed by the node's world transform and then the object's own.
    void read_mesh_instances(const Node& node, int material, MeshFileResult contents) {
        std::size_t triangles = 0;
        for (const MeshData& mesh : contents.meshes) {
            triangles += mesh.triangles.size();
        }
        const std::size_t allowed = max_primitives_ - primitives_;
        const std::string file = contents.meshes.front().file;
        if (triangles > allowed || contents.nodes.size() > allowed - triangles) {
            refuse(at(node, "file").path(),
                   file + ": " +
                       over_primitive_limit("its " + std::to_string(contents.meshes.size()) + " meshes of " +
                                                std::to_string(triangles) + " triangles and the " +
                                                std::to_string(contents.nodes.size()) + " nodes that place them",
                                            allowed));
        }
        const std::optional<Transform> own = placed_by(node, std::nullopt);
        const auto first_shape = static_cast<int>(scene_.mesh_shapes.size());
        for (std::size_t m = 0; m < contents.meshes.size(); ++m) {
            auto data = std::make_shared<MeshData>(std::move(contents.meshes[m]));
            shade_mesh(node, *data);
            data->degenerate = degenerate_triangles(*data);
            scene_.mesh_shapes.push_back(MeshShape{file + " mesh " + std::to_string(m), std::move(data), -1, true});
        }
        primitives_ += triangles;
        for (const MeshNode& file_node : contents.nodes) {
            add_instance(node.path() + " node " + in_quotes(file_node.name), material,
                         node_transform(node, file, file_node, own), first_shape + static_cast<int>(file_node.mesh));
        }
    }

    // An instance of solid shape `shape`: one leaf, counted one towards the limit. Each part's transform composed with
    // the instance's is held to the condition limit, as where the loader composes them itself.
    void add_solid_instance(const Node& node, int material, const Transform& to_world, int shape) {
        const SolidShape& solid = scene_.solid_shapes[static_cast<std::size_t>(shape)];
        for_each_part_transform(solid.tree, [&](const Transform& part) {
            if (const std::optional<std::string> problem = why_unusable(math::composed(to_world, part))) {
                refuse(node.path(), "composed with a transform of shape " + in_quotes(solid.name) + ": " + *problem);
            }
        });
        ++primitives_;
        const int leaf = static_cast<int>(scene_.leaf_paths.size());
        scene_.leaf_paths.push_back(node.path());
        scene_.leaf_materials.push_back(material);
        scene_.solid_instances.push_back(SolidInstance{placement_of(to_world, shape), material, leaf});
    }

    // An instance of mesh shape `shape`: one leaf, counted one towards the limit.
    void add_instance(const std::string& path, int material, const Transform& to_world, int shape) {
        ++primitives_;
        const int leaf = static_cast<int>(scene_.leaf_paths.size());
        scene_.leaf_paths.push_back(path);
        scene_.leaf_materials.push_back(material);
        scene_.meshes.push_back(Mesh{scene_.mesh_shapes[static_cast<std::size_t>(shape)].data, material, leaf,
                                     placement_of(to_world, shape)});
    }

    const DeclaredShape& require_shape(const Node& instance) const {
        if (reading_shapes_) {
            refuse(instance.path(), "a shape may not hold an instance (instances are one level deep)");
        }
        const Node name = at(instance, "shape");
        if (shapes_ == nullptr) {
            refuse_unknown_shape(name, {});
        }
        return shapes_->require(name);
    }

    // The shape read where the instance stands: its primitives placed by the instance's transform (after their
    // own) and given the instance's material where they name none, each its own leaf named after the instance.
    Object read_instanced(const Node& instance, const DeclaredShape& shape, int level, int material,
                          const std::optional<Transform>& to_world) {
        instance_path_ = instance.path();
        Object object = read(shapes_->node_of(shape), level, material, to_world);
        instance_path_.clear();
        return object;
    }
    // The node's own transform, if it has one, applied before its ancestors' `placement`; none if neither has.
    static std::optional<Transform> placed_by(const Node& node, const std::optional<Transform>& placement) {
        const std::optional<Node> list = find_key(node, "transform");
        if (!list) {
            return placement;
        }
        Transform own = read_transform(*list);
        Transform to_world = placement ? math::composed(*placement, own) : own;
        require_usable(*list, to_world);
        return to_world;
    }

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

    Csg read_csg(const Node& node, CsgOp op, int level, int material, const std::optional<Transform>& placement) {
        const Node children = at(node, "children");
        const std::vector<Node> elements = require_array(children, "an array of objects");
        if (elements.size() < 2) {
            refuse(children.path(), "expected at least 2 objects, got " + std::to_string(elements.size()));
        }
        Csg csg{op, {}};
        for (const Node& child : elements) {
            csg.children.push_back(read(child, level + 1, material, placement));
        }
        return csg;
    }

    const std::vector<std::string>& names_;
    const std::size_t max_primitives_;
    std::size_t& primitives_;
    Scene& scene_;
    const std::filesystem::path base_directory_;  // where a mesh's file is looked for
    const DeclaredShapes* shapes_;
    const bool reading_shapes_;
    std::string instance_path_;  // while a shape is read for an instance: the instance's path
};

void require_csg_leaves_within_limit(const Node& element, std::size_t leaves) {
    if (leaves > static_cast<std::size_t>(max_csg_leaves)) {
        refuse(element.path(),
               "a CSG object may hold at most " + std::to_string(max_csg_leaves) +
                   " primitives (the SSE tracer keeps its span lists in fixed-size arrays), this one holds " +
                   std::to_string(leaves) + "; split it into several objects");
    }
}

}  // namespace

const DeclaredShape& DeclaredShapes::require(const Node& name) const {
    const std::string_view wanted = require_string(name);
    std::vector<std::string_view> names;
    for (const DeclaredShape& shape : list_) {
        if (shape.name == wanted) {
            return shape;
        }
        names.push_back(shape.name);
    }
    refuse_unknown_shape(name, names);
}

void read_shapes(const std::vector<std::string>& material_names, std::size_t max_primitives, std::size_t& primitives,
                 const std::filesystem::path& base_directory, Scene& scene, DeclaredShapes& out) {
    const Node& shapes = out.node();
    require_object(shapes);
    JsonValue member = shapes.json().first_child();
    for (std::size_t i = 0; i < shapes.json().size(); ++i, member = member.next_sibling()) {
        const Node node = shapes.member(member, member.key());
        if (member.key().empty()) {
            refuse(node.path(), "a shape needs a name, got an empty key");
        }
        const ObjectKind& kind = require_object_kind(node);
        if (std::holds_alternative<InstanceKind>(kind.shape)) {
            refuse(node.path(), "a shape may not be an instance (instances are one level deep)");
        }
        DeclaredShape shape{std::string(member.key()), member, -1};
        ObjectReader reader(material_names, max_primitives, primitives, scene, base_directory, nullptr, true);
        if (std::holds_alternative<MeshKind>(kind.shape)) {
            if (primitives == max_primitives) {
                refuse(node.path(), over_primitive_limit("the mesh", max_primitives));
            }
            shape.mesh = static_cast<int>(scene.mesh_shapes.size());
            scene.mesh_shapes.push_back(reader.read_mesh_shape(node, key_path("shapes", shape.name)));
        } else {
            // Read in the shape's own space, each part's material -1 where none is named (the instance's applies).
            Scene parts;
            std::size_t part_count = 0;
            ObjectReader checker(material_names, max_primitives, part_count, parts, base_directory, nullptr, true);
            Object tree = checker.read(node, 1, -1, std::nullopt);
            require_csg_leaves_within_limit(node, part_count);
            if (std::holds_alternative<Csg>(tree.shape)) {
                if (part_count > max_primitives - primitives) {
                    refuse(node.path(),
                           over_primitive_limit("its " + std::to_string(part_count) + " primitives", max_primitives));
                }
                primitives += part_count;
                shape.solid = static_cast<int>(scene.solid_shapes.size());
                scene.solid_shapes.push_back(SolidShape{key_path("shapes", shape.name), std::move(tree),
                                                        std::move(parts.leaf_paths), std::move(parts.leaf_materials)});
            }
        }
        out.add(std::move(shape));
    }
}

void read_top_level_object(const Node& element, const std::vector<std::string>& material_names,
                           std::size_t max_primitives, std::size_t& primitives,
                           const std::filesystem::path& base_directory, const DeclaredShapes* shapes, Scene& scene) {
    ObjectReader reader(material_names, max_primitives, primitives, scene, base_directory, shapes);
    const ObjectKind& kind = require_object_kind(element);
    if (std::holds_alternative<MeshKind>(kind.shape)) {
        if (primitives == max_primitives) {
            refuse(element.path(), over_primitive_limit("the mesh", max_primitives));
        }
        reader.read_mesh(element);
        return;
    }
    const std::size_t leaves_before = scene.leaf_paths.size();
    const std::size_t meshes_before = scene.meshes.size();
    const std::size_t solid_instances_before = scene.solid_instances.size();
    Object object = std::holds_alternative<InstanceKind>(kind.shape) ? reader.read_top_level_instance(element)
                                                                     : reader.read(element, 1, 0, std::nullopt);
    if (scene.meshes.size() > meshes_before || scene.solid_instances.size() > solid_instances_before) {
        return;  // an instance of a mesh shape or of a solid shape
    }
    scene.objects.push_back(std::move(object));
    require_csg_leaves_within_limit(element, scene.leaf_paths.size() - leaves_before);
}

}  // namespace twinray::scene
