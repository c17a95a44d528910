// The blocks of a scene file read against the contract (docs/scene-format.md), one function per block;
// loader.cpp calls them in the order that decides which refusal a scene with several faults gets.
#pragma once

#include "scene/json_tree.h"
#include "scene/read_values.h"
#include "scene/scene.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace twinray::scene {

extern const Schema scene_schema;

void require_format(const Node& node);
void read_image(const Node& node, Scene& scene);
Camera read_camera(const Node& node);
// Appends each material and its name to the scene, in file order.
void read_materials(const Node& node, Scene& scene);
std::vector<Light> read_lights(const Node& node);

// The names a scene's objects may use, as Scene::material_names will hold them: the built-in default
// first, then the keys of `materials` (an object) in file order.
std::vector<std::string> material_names_of(const JsonValue& materials);

// A "transform" list, its steps composed in the order they apply (docs/scene-format.md, "Transforms").
Transform read_transform(const Node& list);
// Why a transform (an object's, composed with its CSG ancestors', or a mesh file's node's) may not place anything:
// it is not finite, or its condition number exceeds max_transform_condition; nothing when it may.
std::optional<std::string> why_unusable(const Transform& to_world);
// Refuses, at `where`, a transform that why_unusable finds fault with.
void require_usable(const Node& where, const Transform& to_world);

// A shape of `shapes` (docs/scene-format.md, "Shapes and instances"): a mesh, read once (`mesh`: its index in
// Scene::mesh_shapes), or any other object, kept as its JSON and read again where an instance places it (-1).
struct DeclaredShape {
    std::string name;
    JsonValue json;
    int mesh = -1;   // index into Scene::mesh_shapes
    int solid = -1;  // index into Scene::solid_shapes
};

// The shapes a scene declares, found by name. Holds the nodes its shapes' paths are made from: not copied or
// moved once made.
class DeclaredShapes {
public:
    DeclaredShapes(const JsonTree& tree, JsonValue shapes)
        : root_(Node::root(tree.root())), shapes_(root_.member(shapes, "shapes")) {}
    DeclaredShapes(const DeclaredShapes&) = delete;
    DeclaredShapes& operator=(const DeclaredShapes&) = delete;

    const Node& node() const { return shapes_; }
    void add(DeclaredShape shape) { list_.push_back(std::move(shape)); }
    // The shape `name` (an instance's "shape") names, or a refusal listing the declared ones.
    const DeclaredShape& require(const Node& name) const;
    Node node_of(const DeclaredShape& shape) const { return shapes_.member(shape.json, shape.name); }

private:
    Node root_;
    Node shapes_;
    std::vector<DeclaredShape> list_;
};

// Reads every shape of `shapes` into `out`: each mesh into scene.mesh_shapes and each CSG tree into scene.solid_shapes,
// counted towards `max_primitives`; a primitive read once to refuse what it holds wrong, at its own path. A shape
// holding an instance is refused.
// `primitives`: the scene's count towards the limit so far (Scene::primitive_count), kept up to date.
void read_shapes(const std::vector<std::string>& material_names, std::size_t max_primitives, std::size_t& primitives,
                 const std::filesystem::path& base_directory, Scene& scene, DeclaredShapes& out);

// Reads one element of `objects` (a primitive, or a CSG tree) into the scene: the object, and each of
// its primitives' path and material. `material_names` as in material_names_of. Refuses the primitive that
// would make the scene's count (`primitives`, as read_shapes keeps it) exceed `max_primitives`.
// `base_directory`: where a mesh's "file" is looked for, the scene file's folder.
// `shapes`: those its instances may place, or null where the scene declares none.
void read_top_level_object(const Node& element, const std::vector<std::string>& material_names,
                           std::size_t max_primitives, std::size_t& primitives,
                           const std::filesystem::path& base_directory, const DeclaredShapes* shapes, Scene& scene);

}  // namespace twinray::scene
