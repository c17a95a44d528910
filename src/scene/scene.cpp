#include "scene/scene.h"

#include "scene/refusal.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace twinray::scene {

namespace {

// Walks the tree rather than leaf_materials, so that it also answers for scenes built in code.
template <class Predicate>
bool any_leaf(const std::vector<Object>& objects, const Predicate& predicate) {
    return std::any_of(objects.begin(), objects.end(), [&predicate](const Object& object) {
        const Csg* csg = std::get_if<Csg>(&object.shape);
        return csg ? any_leaf(csg->children, predicate) : predicate(object);
    });
}

int checked_side(const char* name, long long side) {
    if (side < 1 || side > max_image_side) {
        throw std::invalid_argument("image " + std::string(name) + " must be from 1 to " +
                                    std::to_string(max_image_side) + ", got " + std::to_string(side));
    }
    return static_cast<int>(side);
}

// The side that keeps the scene's aspect ratio, given the other one. Exact in double: every operand is
// at most max_image_side, so only the final division rounds, and halves round away from zero.
int side_keeping_aspect(const char* name, int given, int scene_side, int scene_given_side) {
    const double side = static_cast<double>(given) * scene_side / scene_given_side;
    return checked_side(name, std::max(1LL, std::llround(side)));
}

// Whether any material a hit can find (a leaf's, a mesh's, an instance's part's) satisfies `predicate`.
template <class Predicate>
bool any_material_used(const Scene& scene, const Predicate& predicate) {
    auto of = [&](int material) { return predicate(scene.materials[static_cast<std::size_t>(material)]); };
    auto of_instance = [&](const SolidInstance& instance) {
        const SolidShape& shape = scene.solid_shapes[static_cast<std::size_t>(instance.placement.shape)];
        for (std::size_t part = 0; part < shape.part_materials.size(); ++part) {
            if (of(instance.material_of(shape, static_cast<int>(part)))) {
                return true;
            }
        }
        return false;
    };
    return any_leaf(scene.objects, [&](const Object& leaf) { return of(leaf.material); }) ||
           std::any_of(scene.meshes.begin(), scene.meshes.end(), [&](const Mesh& mesh) { return of(mesh.material); }) ||
           std::any_of(scene.solid_instances.begin(), scene.solid_instances.end(), of_instance);
}

}  // namespace

bool Scene::has_csg() const {
    return !solid_instances.empty() || std::any_of(objects.begin(), objects.end(), [](const Object& object) {
        return std::holds_alternative<Csg>(object.shape);
    });
}

bool Scene::has_transparency() const {
    return any_material_used(*this, [](const Material& material) { return material.transmission > 0; });
}

bool Scene::has_reflection() const {
    return any_material_used(*this, [](const Material& material) { return material.reflection > 0; });
}

std::size_t Scene::primitive_count() const {
    std::size_t count = leaf_paths.size() - meshes.size();
    for (const Mesh& mesh : meshes) {
        count += mesh.placement ? 1 : mesh.data->triangles.size();
    }
    for (const MeshShape& shape : mesh_shapes) {
        count += shape.data->triangles.size();
    }
    for (const SolidShape& shape : solid_shapes) {
        count += shape.part_paths.size();
    }
    return count;
}

const SolidInstance* Scene::solid_instance_of_leaf(int leaf) const {
    const auto found =
        std::lower_bound(solid_instances.begin(), solid_instances.end(), leaf,
                         [](const SolidInstance& instance, int wanted) { return instance.leaf < wanted; });
    return found != solid_instances.end() && found->leaf == leaf ? &*found : nullptr;
}

int Scene::material_of(int leaf, int part) const {
    if (part >= 0) {
        if (const SolidInstance* instance = solid_instance_of_leaf(leaf)) {
            return instance->material_of(solid_shapes[static_cast<std::size_t>(instance->placement.shape)], part);
        }
    }
    return leaf_materials[static_cast<std::size_t>(leaf)];
}

const Mesh* Scene::mesh_of_leaf(int leaf) const {
    const auto found = std::lower_bound(meshes.begin(), meshes.end(), leaf,
                                        [](const Mesh& mesh, int wanted) { return mesh.leaf < wanted; });
    return found != meshes.end() && found->leaf == leaf ? &*found : nullptr;
}

namespace {

constexpr std::string_view element_prefix = "objects[";

// k where `path` is "objects[k]" with k written as the loader writes an index (no sign, no leading zero) and below
// 2^31; else nothing.
std::optional<std::uint32_t> element_index(std::string_view path) {
    if (!path.starts_with(element_prefix) || !path.ends_with(']')) {
        return std::nullopt;
    }
    const std::string_view digits = path.substr(element_prefix.size(), path.size() - element_prefix.size() - 1);
    if (digits.empty() || (digits.size() > 1 && digits.front() == '0') ||
        !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        return std::nullopt;
    }
    std::uint32_t index = 0;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
    if (error != std::errc{} || end != digits.data() + digits.size() || index >= (std::uint32_t{1} << 31)) {
        return std::nullopt;
    }
    return index;
}

}  // namespace

void LeafPaths::push_back(std::string_view path) {
    if (const std::optional<std::uint32_t> index = element_index(path)) {
        entries_.push_back(element_flag | *index);
        return;
    }
    if (text_.size() + sizeof(std::uint32_t) + path.size() >= element_flag) {
        throw std::length_error("the scene's object paths take more than 2 GiB of text");
    }
    entries_.push_back(static_cast<std::uint32_t>(text_.size()));
    const auto length = static_cast<std::uint32_t>(path.size());
    text_.append(reinterpret_cast<const char*>(&length), sizeof length);
    text_ += path;
}

void LeafPaths::clear() {
    text_.clear();
    entries_.clear();
}

std::string LeafPaths::operator[](std::size_t leaf) const {
    const std::uint32_t entry = entries_[leaf];
    if ((entry & element_flag) != 0) {
        return std::string(element_prefix) + std::to_string(entry & ~element_flag) + "]";
    }
    std::uint32_t length = 0;
    std::memcpy(&length, text_.data() + entry, sizeof length);
    return text_.substr(entry + sizeof length, length);
}

std::string LeafPaths::at(std::size_t leaf) const {
    if (leaf >= entries_.size()) {
        throw std::out_of_range("no leaf " + std::to_string(leaf) + " among " + std::to_string(entries_.size()));
    }
    return (*this)[leaf];
}

bool LeafPaths::operator==(const std::vector<std::string>& paths) const {
    if (paths.size() != size()) {
        return false;
    }
    for (std::size_t leaf = 0; leaf < paths.size(); ++leaf) {
        if (paths[leaf] != (*this)[leaf]) {
            return false;
        }
    }
    return true;
}

std::string Scene::leaf_name(int leaf, int part) const {
    const std::string path = leaf_paths[static_cast<std::size_t>(leaf)];
    if (const SolidInstance* instance = solid_instance_of_leaf(leaf)) {
        const SolidShape& shape = solid_shapes[static_cast<std::size_t>(instance->placement.shape)];
        return path + " (" + (part >= 0 ? shape.part_paths[static_cast<std::size_t>(part)] : shape.name) + ")";
    }
    const Mesh* mesh = mesh_of_leaf(leaf);
    if (mesh == nullptr || !mesh->placement) {
        return path;
    }
    return path + " (" + mesh_shapes[static_cast<std::size_t>(mesh->placement->shape)].name + ")";
}

ImageSize resolve_image_size(const Scene& scene, int requested_width, int requested_height) {
    if (requested_width == 0 && requested_height == 0) {
        return {scene.width, scene.height};
    }
    if (requested_height == 0) {
        const int width = checked_side("width", requested_width);
        return {width, side_keeping_aspect("height", width, scene.height, scene.width)};
    }
    if (requested_width == 0) {
        const int height = checked_side("height", requested_height);
        return {side_keeping_aspect("width", height, scene.width, scene.height), height};
    }
    return {checked_side("width", requested_width), checked_side("height", requested_height)};
}

}  // namespace twinray::scene
