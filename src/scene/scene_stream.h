// Reading a scene file's JSON in one streaming pass (RapidJSON's SAX reader), into a JsonTree, except
// the elements of the root object's "objects" array, which can be handed over one by one as each is
// read and then dropped: a scene of a million spheres never holds its text or its whole tree.
// Syntax errors are reported in nlohmann::json's words, as they always were (docs/scene-format.md).
#pragma once

#include "scene/json_tree.h"

#include <cstddef>
#include <cstdio>
#include <string_view>

namespace twinray::scene {

// What the loader does with the elements of the root's "objects" array.
class ObjectsReader {
public:
    virtual ~ObjectsReader() = default;
    // Asked when the array opens, with what has been read so far: whether each element is handed to
    // element() and then dropped (true), or kept in the tree like any other value (false).
    virtual bool stream_elements(const JsonTree& read_so_far) = 0;
    virtual void element(JsonValue array, JsonValue value, std::size_t index) = 0;
    // Each element holds a primitive at least: an array kept in the tree is refused past this many
    // elements as it is read, before the tree grows with it (streamed elements are counted by element()).
    virtual std::size_t most_elements() const = 0;
};

// Reads `text` or the open file into `tree`, or throws a Refusal: a syntax error with its line and
// column, a duplicate key, or nesting deeper than max_json_depth (all in document order). A file that
// cannot be read throws std::system_error.
void read_json(std::string_view text, JsonTree& tree, ObjectsReader& objects);
void read_json(std::FILE* file, JsonTree& tree, ObjectsReader& objects);

}  // namespace twinray::scene
