// The module's readers, one per format, and what they share. Each throws a Refusal naming where the file
// is wrong (plugin.cpp turns it into MeshReading::refusal).
#pragma once

#include "scene/meshio/library.h"

#include <cstddef>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>

namespace twinray::scene::meshio {

MeshReading read_obj(const std::filesystem::path& file, std::size_t max_triangles);
MeshReading read_ply(const std::filesystem::path& file, std::size_t max_triangles);
MeshReading read_stl(const std::filesystem::path& file, std::size_t max_triangles);
MeshReading read_gltf(const std::filesystem::path& file, std::size_t max_triangles);

// OBJ, PLY and STL have no nodes: a reading of their one mesh (to fill), placed once as it stands.
inline MeshReading one_mesh_reading() {
    MeshReading reading;
    reading.meshes.emplace_back();
    reading.nodes.emplace_back();
    return reading;
}

// Vertices a file may hold: enough for every triangle of the limit to have three of its own.
constexpr std::size_t max_vertices_for(std::size_t max_triangles) {
    return 3 * max_triangles;
}

[[noreturn]] inline void refuse_at(std::string location, std::string problem) {
    throw Refusal{std::move(location), std::move(problem)};
}

// The refusal of a mesh past the limit, `what` saying how far it got ("line 7 brings the triangles to 13").
[[noreturn]] inline void refuse_too_many_triangles(std::string location, const std::string& what,
                                                   std::size_t max_triangles) {
    refuse_at(std::move(location), over_primitive_limit(what, max_triangles));
}

[[noreturn]] inline void refuse_too_many_vertices(std::string location, std::size_t vertices,
                                                  std::size_t max_triangles) {
    refuse_at(std::move(location), std::to_string(vertices) +
                                       " vertices: more than three per triangle of the limit of " +
                                       std::to_string(max_triangles) + " triangles");
}

// Text from the file or a library, for messages: cut short, and anything but printable ASCII replaced by '?',
// since the file's bytes are not to be trusted with a terminal. `quoted` puts a word from the file in quotes.
std::string printable(std::string_view text, std::size_t longest = 300);
std::string quote_word(std::string_view text);
// Names from the file, each quoted, comma-separated, the first eight of them and how many more.
std::string quoted_names(const std::set<std::string>& names);

// A file mapped read-only for the reader's lifetime (the OBJ and PLY readers parse it in place).
class MappedFile {
public:
    explicit MappedFile(const std::filesystem::path& file);
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;
    ~MappedFile();

    std::string_view bytes() const { return {data_, size_}; }

private:
    const char* data_ = nullptr;
    std::size_t size_ = 0;
};

}  // namespace twinray::scene::meshio
