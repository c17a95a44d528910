// The blocks of a scene file read against the contract (docs/scene-format.md), one function per block;
// loader.cpp calls them in the order that decides which refusal a scene with several faults gets.
#pragma once

#include "scene/read_values.h"
#include "scene/scene.h"

#include <filesystem>
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
// Refuses, at `where`, a transform (an object's, composed with its CSG ancestors') that is not finite or whose
// condition number exceeds max_transform_condition.
void require_usable(const Node& where, const Transform& to_world);

// Reads one element of `objects` (a primitive, or a CSG tree) into the scene: the object, and each of
// its primitives' path and material. `material_names` as in material_names_of. Refuses the primitive that
// would make the scene's count exceed `max_primitives`.
// `base_directory`: where a mesh's "file" is looked for, the scene file's folder.
void read_top_level_object(const Node& element, const std::vector<std::string>& material_names,
                           std::size_t max_primitives, const std::filesystem::path& base_directory, Scene& scene);

}  // namespace twinray::scene
