// Reads twinray-scene/1 (docs/scene-format.md) in one streaming pass (scene/scene_stream.h): syntax
// errors, duplicate keys and runaway nesting are refused as the text is read, in document order; the
// values are then read against the contract, block by block (scene/read_scene.h), and every refusal
// names the JSON path of the offending value. The elements of `objects` are read as they arrive and
// dropped, once the material names they may use are known (materials before objects, as every scene
// here is written): a scene of a million spheres is never held as text or as a tree. Their first
// refusal is kept until the end, so that a fault earlier in the reading order (a syntax error
// anywhere, then format, image, camera, ..., lights) is the one reported, as if read in order.
#include "scene/loader.h"

#include "io/file_handle.h"
#include "scene/read_scene.h"
#include "scene/scene_stream.h"

#include <sys/mman.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <system_error>

namespace twinray::scene {
namespace {

// Asks for transparent huge pages under the array's reserve, where the system gives them on request
// (Debian's default): one page fault per 2 MiB instead of one per 4 KiB, for arrays of millions.
template <class T>
void ask_huge_pages(const std::vector<T>& array) {
    constexpr std::uintptr_t huge_page = std::uintptr_t{2} << 20;
    const auto begin = reinterpret_cast<std::uintptr_t>(array.data());
    const std::uintptr_t first = (begin + huge_page - 1) & ~(huge_page - 1);
    const std::uintptr_t last = (begin + array.capacity() * sizeof(T)) & ~(huge_page - 1);
    if (last > first) {
        madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
    }
}

// The fewest bytes a primitive takes in a scene file ({"type":"box","min":[0,0,0],"max":[1,1,1]}).
constexpr std::size_t smallest_primitive_text = 40;
// And an instance ({"type":"instance","shape":"s"}).
constexpr std::size_t smallest_instance_text = 32;

class SceneReader final : public ObjectsReader {
public:
    // The arrays of primitives are reserved for as many as `text_bytes` can hold, up to the limit, so that
    // they never move while growing: moving them touched twice their size in new pages, which cost more
    // than the parsing. Pages of the reserve that no primitive fills are never touched and take no memory,
    // but the address space counts: a file of gigabytes must not reserve it for more than the limit.
    SceneReader(const JsonTree& tree, std::size_t text_bytes, std::size_t max_primitives,
                std::filesystem::path base_directory)
        : tree_(tree),
          text_bytes_(text_bytes),
          max_primitives_(std::min(max_primitives, max_scene_primitives)),
          base_directory_(std::move(base_directory)) {
        const std::size_t most_primitives = std::min(text_bytes / smallest_primitive_text, max_primitives_);
        scene_.objects.reserve(most_primitives);
        scene_.leaf_paths.reserve(most_primitives);
        scene_.leaf_materials.reserve(most_primitives);
        ask_huge_pages(scene_.objects);
        ask_huge_pages(scene_.leaf_materials);
    }

    // Only once the material names are known: an object may name one. The shapes its instances place are read
    // then, if they came before `objects`.
    bool stream_elements(const JsonTree& read_so_far) override {
        const std::optional<JsonValue> materials = read_so_far.root().find("materials");
        if (materials) {
            material_names_ = material_names_of(*materials);
        }
        streamed_ = materials.has_value();
        if (streamed_) {
            try {
                read_shapes_if_any(read_so_far.root(), material_names_);
            } catch (const Refusal& refusal) {
                first_refusal_ = refusal;
            }
        }
        return streamed_;
    }

    std::size_t most_elements() const override { return max_primitives_; }

    void element(JsonValue array, JsonValue value, std::size_t index) override {
        if (first_refusal_) {
            return;
        }
        try {
            const Node root = Node::root(tree_.root());
            const Node objects = root.member(array, "objects");
            read_top_level_object(objects.element(value, index), material_names_, max_primitives_, primitives_,
                                  base_directory_, shapes_.get(), scene_);
        } catch (const Refusal& refusal) {
            first_refusal_ = refusal;
        }
    }

    Scene read(const Node& root) {
        require_keys_of(root, scene_schema);
        if (const std::optional<Node> format = find_key(root, "format")) {
            require_format(*format);
        }
        if (const std::optional<Node> image = find_key(root, "image")) {
            read_image(*image, scene_);
        }
        scene_.camera = read_camera(at(root, "camera"));
        scene_.background = read_or(root, "background", scene_.background, require_color);
        scene_.ambient_light = read_or(root, "ambient_light", scene_.ambient_light, require_color);
        scene_.max_depth = read_or(root, "max_depth", scene_.max_depth, integer_in(1, max_trace_depth));
        if (const std::optional<Node> min_weight = find_key(root, "min_weight")) {
            scene_.min_weight = require_number_in(*min_weight, non_negative);
        }
        if (const std::optional<Node> materials = find_key(root, "materials")) {
            read_materials(*materials, scene_);
        }
        scene_.lights = read_or(root, "lights", scene_.lights, read_lights);
        if (!streamed_) {
            read_shapes_if_any(root.json(), scene_.material_names);
        }
        read_objects(at(root, "objects"));
        return std::move(scene_);
    }

private:
    void read_objects(const Node& objects) {
        if (streamed_) {
            if (first_refusal_) {
                throw *first_refusal_;
            }
            return;
        }
        for (const Node& element : require_array(objects, "an array of objects")) {
            read_top_level_object(element, scene_.material_names, max_primitives_, primitives_, base_directory_,
                                  shapes_.get(), scene_);
        }
    }

    void read_shapes_if_any(const JsonValue& root, const std::vector<std::string>& material_names) {
        if (const std::optional<JsonValue> shapes = root.find("shapes")) {
            shapes_ = std::make_unique<DeclaredShapes>(tree_, *shapes);
            read_shapes(material_names, max_primitives_, primitives_, base_directory_, scene_, *shapes_);
            if (!scene_.mesh_shapes.empty()) {
                // Every instance of a mesh shape is a mesh: reserved as the primitives are, not grown.
                scene_.meshes.reserve(std::min(text_bytes_ / smallest_instance_text, max_primitives_));
                ask_huge_pages(scene_.meshes);
            }
        }
    }

    const JsonTree& tree_;
    const std::size_t text_bytes_;
    const std::size_t max_primitives_;
    const std::filesystem::path base_directory_;
    Scene scene_;
    std::vector<std::string> material_names_;
    std::unique_ptr<DeclaredShapes> shapes_;  // none where the scene declares no shapes
    std::size_t primitives_ = 0;              // Scene::primitive_count of what has been read
    bool streamed_ = false;
    std::optional<Refusal> first_refusal_;
};

// Mesh files are looked for beside the scene file (`source`).
template <class Input>
Scene read_scene(Input input, std::size_t text_bytes, std::size_t max_primitives, const std::filesystem::path& source) {
    JsonTree tree;
    SceneReader reader(tree, text_bytes, max_primitives, source.parent_path());
    read_json(input, tree, reader);
    return reader.read(Node::root(tree.root()));
}

std::string error_message(const std::string& file, const std::string& location, const std::string& problem) {
    return location.empty() ? file + ": " + problem : file + ": " + location + ": " + problem;
}

std::string system_error_text() {
    return std::error_code(errno, std::generic_category()).message();
}

}  // namespace

SceneError::SceneError(std::string file, std::string location, std::string problem)
    : std::runtime_error(error_message(file, location, problem)),
      file_(std::move(file)),
      location_(std::move(location)),
      problem_(std::move(problem)) {}

Scene parse_scene(std::string_view json_text, const std::string& source_name, std::size_t max_primitives) {
    try {
        return read_scene(json_text, json_text.size(), max_primitives, source_name);
    } catch (const Refusal& refusal) {
        throw SceneError(source_name, refusal.location, refusal.problem);
    }
}

Scene load_scene(const std::filesystem::path& file, std::size_t max_primitives) {
    const io::FileHandle stream(std::fopen(file.c_str(), "rb"));
    if (!stream) {
        throw SceneError(file.string(), "", "cannot open file: " + system_error_text());
    }
    struct stat status {};
    const std::size_t text_bytes =
        fstat(fileno(stream.get()), &status) == 0 ? static_cast<std::size_t>(status.st_size) : 0;
    try {
        return read_scene(stream.get(), text_bytes, max_primitives, file);
    } catch (const Refusal& refusal) {
        throw SceneError(file.string(), refusal.location, refusal.problem);
    } catch (const std::system_error& error) {
        // A directory opens but cannot be read (EISDIR).
        throw SceneError(file.string(), "", "cannot read file: " + error.code().message());
    }
}

}  // namespace twinray::scene
