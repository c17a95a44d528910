// Reads and validates twinray-scene/1 JSON. Every rule of the contract is checked before anything is
// rendered; a refusal names the file, the JSON path (or line and column), what is wrong and what is
// allowed.
#pragma once

#include "scene/scene.h"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace twinray::scene {

class SceneError : public std::runtime_error {
public:
    // `location` is a JSON path such as "objects[3].radius" ("(root)" for the document itself),
    // "line L, column C" for a syntax error, or "" when the file itself cannot be read.
    SceneError(std::string file, std::string location, std::string problem);

    const std::string& file() const { return file_; }
    const std::string& location() const { return location_; }
    const std::string& problem() const { return problem_; }

private:
    std::string file_;
    std::string location_;
    std::string problem_;
};

// `source_name` names the text in messages (a file path, or e.g. "<string>"), and its folder is where a
// mesh's "file" is looked for (the current folder for a name without one). A scene of more than
// `max_primitives` primitives (at most max_scene_primitives: a larger number is not honoured) is refused as
// it is read, before the loader holds or reserves memory for more.
Scene parse_scene(std::string_view json_text, const std::string& source_name,
                  std::size_t max_primitives = max_scene_primitives);
Scene load_scene(const std::filesystem::path& file, std::size_t max_primitives = max_scene_primitives);

}  // namespace twinray::scene
