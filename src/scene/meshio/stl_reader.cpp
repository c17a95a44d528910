// STL, binary and ASCII, through assimp. The header is checked first, before assimp reads a byte: a binary
// file's triangle count against the limit and the file's size (assimp calls a file of the wrong size
// "Failed to determine STL storage representation"), an ASCII file's facets counted against the limit.
// STL gives every triangle three vertices of its own; they are welded here by bit-identical coordinates
// (floats, as STL stores them), so that triangles share the vertices they share in the model. Facet normals
// are not read: a triangle faces the way its winding says, as STL requires the normal to.
#include "scene/meshio/readers.h"

#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>

namespace twinray::scene::meshio {
namespace {

constexpr std::size_t binary_header_size = 84;
constexpr std::size_t binary_triangle_size = 50;

void check_header(const std::filesystem::path& file, std::size_t max_triangles) {
    const MappedFile mapped(file);
    const std::string_view bytes = mapped.bytes();
    std::optional<std::uint32_t> declared;
    if (bytes.size() >= binary_header_size) {
        std::uint32_t count = 0;
        std::memcpy(&count, bytes.data() + 80, sizeof count);  // little-endian, as this machine
        declared = count;
        if (binary_header_size + std::uint64_t{count} * binary_triangle_size == bytes.size()) {
            if (count == 0) {
                refuse_at("", "no triangles: the header of this binary STL declares 0");
            }
            if (count > max_triangles) {
                refuse_too_many_triangles("header", "it declares " + std::to_string(count) + " triangles",
                                          max_triangles);
            }
            return;
        }
    }
    const std::size_t text = bytes.find_first_not_of(" \t\r\n");
    if (text == std::string_view::npos || bytes.substr(text, 5) != "solid") {
        const std::string as_binary =
            declared ? "its header declares " + std::to_string(*declared) + " triangles, which take 84 + 50 x " +
                           std::to_string(*declared) + " bytes, and the file has " + std::to_string(bytes.size())
                     : "it has " + std::to_string(bytes.size()) + " bytes, fewer than a binary header's 84";
        refuse_at("", "neither ASCII STL (it does not begin with \"solid\") nor binary STL (" + as_binary +
                          "): truncated, or not an STL file");
    }
    std::size_t facets = 0;
    for (std::size_t at = bytes.find("endfacet"); at != std::string_view::npos; at = bytes.find("endfacet", at + 8)) {
        if (++facets > max_triangles) {
            refuse_too_many_triangles("", "its facets number more than " + std::to_string(max_triangles),
                                      max_triangles);
        }
    }
}

// Vertices by their bits: open addressing over the welded vertices' indices.
class Welder {
public:
    explicit Welder(std::size_t corners) {
        std::size_t capacity = 16;
        while (capacity < 2 * corners) {
            capacity *= 2;
        }
        slots_.assign(capacity, empty);
    }

    std::uint32_t index_of(const aiVector3D& position) {
        const std::array<std::uint32_t, 3> key{std::bit_cast<std::uint32_t>(position.x),
                                               std::bit_cast<std::uint32_t>(position.y),
                                               std::bit_cast<std::uint32_t>(position.z)};
        std::uint64_t hash =
            (key[0] * 0x9E3779B97F4A7C15ULL) ^ (key[1] * 0xC2B2AE3D27D4EB4FULL) ^ (key[2] * 0x165667B19E3779F9ULL);
        const std::size_t mask = slots_.size() - 1;
        for (std::size_t slot = (hash ^ hash >> 29) & mask;; slot = (slot + 1) & mask) {
            if (slots_[slot] == empty) {
                slots_[slot] = static_cast<std::uint32_t>(keys_.size());
                keys_.push_back(key);
                return slots_[slot];
            }
            if (keys_[slots_[slot]] == key) {
                return slots_[slot];
            }
        }
    }

    std::vector<Vec3> vertices() const {
        std::vector<Vec3> vertices;
        vertices.reserve(keys_.size());
        for (const auto& key : keys_) {
            vertices.push_back(
                {std::bit_cast<float>(key[0]), std::bit_cast<float>(key[1]), std::bit_cast<float>(key[2])});
        }
        return vertices;
    }

private:
    static constexpr std::uint32_t empty = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> slots_;
    std::vector<std::array<std::uint32_t, 3>> keys_;
};

}  // namespace

MeshReading read_stl(const std::filesystem::path& file, std::size_t max_triangles) {
    check_header(file, max_triangles);
    Assimp::Importer importer;
    // No post-processing: the triangles as the file has them.
    const aiScene* scene = importer.ReadFile(file.string(), 0);
    if (!scene) {
        refuse_at("", "assimp: " + printable(importer.GetErrorString()));
    }
    std::size_t triangle_count = 0;
    bool colours = false;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        triangle_count += scene->mMeshes[m]->mNumFaces;
        colours = colours || scene->mMeshes[m]->HasVertexColors(0);
    }
    if (triangle_count == 0) {
        refuse_at("", "no triangles: the file has no facets");
    }
    if (triangle_count > max_triangles) {
        refuse_too_many_triangles("", "it has " + std::to_string(triangle_count) + " triangles", max_triangles);
    }
    MeshReading reading = one_mesh_reading();
    if (colours) {
        reading.warnings.push_back("facet colours are not used");
    }
    Welder welder(3 * triangle_count);
    std::vector<std::array<std::uint32_t, 3>>& triangles = reading.meshes.front().triangles;
    triangles.reserve(triangle_count);
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh& mesh = *scene->mMeshes[m];
        for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
            const aiFace& face = mesh.mFaces[f];
            const std::string location = "triangle[" + std::to_string(triangles.size()) + "]";
            if (face.mNumIndices != 3) {
                refuse_at(location, "assimp gave " + std::to_string(face.mNumIndices) + " vertices");
            }
            std::array<std::uint32_t, 3> triangle{};
            for (int k = 0; k < 3; ++k) {
                const aiVector3D& position = mesh.mVertices[face.mIndices[k]];
                if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z)) {
                    refuse_at(location, "vertex " + std::to_string(k) + " is not finite (" + format_number(position.x) +
                                            " " + format_number(position.y) + " " + format_number(position.z) + ")");
                }
                triangle[k] = welder.index_of(position);
            }
            triangles.push_back(triangle);
        }
    }
    importer.FreeScene();
    reading.meshes.front().vertices = welder.vertices();
    return reading;
}

}  // namespace twinray::scene::meshio
