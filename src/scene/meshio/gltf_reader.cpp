// glTF 2 (.gltf with its buffers, or .glb) through assimp's importer: the meshes the file's nodes carry and each
// such node's world transform. assimp splits a glTF mesh into one aiMesh per primitive and gives a node the list
// of its mesh's primitives; the triangle primitives of one list are merged here into one mesh, so that nodes
// giving the same list share it. Points and lines are not drawn. assimp holds coordinates and each node's matrix
// in float (its TRS composed in float too); the matrices are composed down the hierarchy here in double.
// assimp drops a triangle whose index is out of range with no more than a line in its log: the log is read, and
// such a file refused. It reads a file that requires an extension it lacks (Draco-compressed meshes: their accessors
// then have no data, which glTF reads as zeros) as if the extension were not there: a file requiring an extension
// that may change its geometry is refused.
#include "math/transform.h"
#include "scene/meshio/readers.h"

#include <assimp/material.h>
#include <assimp/scene.h>
#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace twinray::scene::meshio {
namespace {

using Matrix3 = math::Matrix3<double>;

std::string node_location(const aiNode& node) {
    return "node " + quote_word(node.mName.C_Str());
}

std::string mesh_location(const aiMesh& primitive) {
    return "mesh " + quote_word(primitive.mName.C_Str());
}

std::string coordinates(double x, double y, double z) {
    return format_number(x) + " " + format_number(y) + " " + format_number(z);
}

// The node's own matrix (assimp's, row-major, translation in its last column) as p ↦ L·p + t.
MeshNode local_transform(const aiNode& node) {
    const aiMatrix4x4& m = node.mTransformation;
    const float entries[] = {m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4};
    for (const float entry : entries) {
        if (!std::isfinite(entry)) {
            refuse_at(node_location(node), "its matrix has an entry that is not finite (" + format_number(entry) + ")");
        }
    }
    if (m.d1 != 0 || m.d2 != 0 || m.d3 != 0 || m.d4 != 1) {
        refuse_at(node_location(node), "its matrix is not affine: its last row is " + coordinates(m.d1, m.d2, m.d3) +
                                           " " + format_number(m.d4) + ", not 0 0 0 1");
    }
    MeshNode local;
    local.linear = Matrix3{{{m.a1, m.a2, m.a3}, {m.b1, m.b2, m.b3}, {m.c1, m.c2, m.c3}}};
    local.translation = {m.a4, m.b4, m.c4};
    return local;
}

// `inner` placed by `outer`: p ↦ L_o·(L_i·p + t_i) + t_o, in double.
MeshNode composed(const MeshNode& outer, const MeshNode& inner) {
    MeshNode out;
    out.linear = math::product(outer.linear, inner.linear);
    out.translation = outer.linear * inner.translation + outer.translation;
    return out;
}

// The file's JSON: a .gltf's whole text, a .glb's first chunk (empty where it has no JSON chunk first). A .glb is
// refused where its header's length or a chunk's runs past the file's end: assimp allocates and clears what they
// say before it reads (a fuzzed file of 91 bytes claiming a 1.2 GB chunk took it more than 10 s).
std::string json_text_of(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    char header[12] = {};
    in.read(header, sizeof header);
    if (in.gcount() < 4 || std::memcmp(header, "glTF", 4) != 0) {
        in.clear();
        in.seekg(0);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    std::error_code error;
    const std::uint64_t size = std::filesystem::file_size(file, error);
    if (error) {
        refuse_at("", "its size cannot be read: " + error.message());
    }
    if (in.gcount() < static_cast<std::streamsize>(sizeof header)) {
        refuse_at("", "it begins as a binary glTF (\"glTF\") but is " + std::to_string(size) +
                          " bytes long, shorter than the 12-byte header");
    }
    std::uint32_t length = 0;  // the header's: magic, version, length
    std::memcpy(&length, header + 8, sizeof length);
    if (length > size) {
        refuse_at("",
                  "its header says " + std::to_string(length) + " bytes, more than the file's " + std::to_string(size));
    }
    std::string json;
    // Each chunk: its length and type (8 bytes), then its bytes.
    for (std::uint64_t at = sizeof header; at + 8 <= size;) {
        char head[8] = {};
        in.seekg(static_cast<std::streamoff>(at));
        in.read(head, sizeof head);
        std::uint32_t chunk = 0;
        std::memcpy(&chunk, head, sizeof chunk);
        if (chunk > size - at - 8) {
            refuse_at("chunk at byte " + std::to_string(at), "its length, " + std::to_string(chunk) +
                                                                 " bytes, runs past the file's end (" +
                                                                 std::to_string(size) + " bytes)");
        }
        if (at == sizeof header && std::memcmp(head + 4, "JSON", 4) == 0) {
            json.resize(chunk);
            in.read(json.data(), chunk);
        }
        at += 8 + chunk;
    }
    return json;
}

// Extensions a file may require and still be drawn as written: they change materials, textures or lights, which
// are not used.
bool leaves_geometry_alone(std::string_view extension) {
    return extension.starts_with("KHR_materials_") || extension.starts_with("KHR_texture_") ||
           extension == "KHR_lights_punctual";
}

void refuse_required_extensions(const std::filesystem::path& file) {
    const nlohmann::json json = nlohmann::json::parse(json_text_of(file), nullptr, false);
    const auto required = json.is_object() ? json.find("extensionsRequired") : json.end();
    if (!json.is_object() || required == json.end() || !required->is_array()) {
        return;
    }
    for (const nlohmann::json& extension : *required) {
        if (extension.is_string() && !leaves_geometry_alone(extension.get<std::string>())) {
            refuse_at("", "it requires the extension " + quote_word(extension.get<std::string>()) +
                              ", which assimp 5.2 does not read (it would read the meshes as if it were absent); "
                              "required extensions allowed: KHR_materials_*, KHR_texture_*, KHR_lights_punctual");
        }
    }
}

// assimp's warnings and errors while the importer runs (its logger is the process's: this reader's alone).
class AssimpLog {
public:
    AssimpLog() {
        Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
        Assimp::DefaultLogger::get()->attachStream(new Collector(lines_), Assimp::Logger::Warn | Assimp::Logger::Err);
    }
    AssimpLog(const AssimpLog&) = delete;
    AssimpLog& operator=(const AssimpLog&) = delete;
    ~AssimpLog() { Assimp::DefaultLogger::kill(); }  // deletes the collector

    bool says(std::string_view words) const {
        return std::any_of(lines_.begin(), lines_.end(),
                           [words](const std::string& line) { return line.find(words) != std::string::npos; });
    }

private:
    class Collector : public Assimp::LogStream {
    public:
        explicit Collector(std::vector<std::string>& lines) : lines_(lines) {}
        void write(const char* message) override { lines_.emplace_back(message); }

    private:
        std::vector<std::string>& lines_;
    };
    std::vector<std::string> lines_;
};

class GltfReader {
public:
    GltfReader(const aiScene& scene, std::size_t max_triangles)
        : scene_(scene), max_triangles_(max_triangles), placed_primitives_(scene.mNumMeshes, false) {}

    MeshReading read() {
        if (scene_.mRootNode == nullptr) {
            refuse_at("", "no nodes: the file's scene has none to place its meshes");
        }
        // Depth first, children in file order, with an explicit stack: assimp's hierarchy may be deep.
        std::vector<std::pair<const aiNode*, MeshNode>> pending{{scene_.mRootNode, local_transform(*scene_.mRootNode)}};
        while (!pending.empty()) {
            auto [node, to_world] = std::move(pending.back());
            pending.pop_back();
            place_meshes_of(*node, to_world);
            for (unsigned c = node->mNumChildren; c-- > 0;) {
                const aiNode& child = *node->mChildren[c];
                MeshNode child_to_world = composed(to_world, local_transform(child));
                if (!is_finite(child_to_world.translation) || !is_finite(child_to_world.linear.row[0]) ||
                    !is_finite(child_to_world.linear.row[1]) || !is_finite(child_to_world.linear.row[2])) {
                    refuse_at(node_location(child),
                              "its world transform (its matrix after its ancestors') overflows: "
                              "not all finite");
                }
                pending.emplace_back(&child, std::move(child_to_world));
            }
        }
        if (reading_.nodes.empty()) {
            refuse_at("", triangle_primitives() == 0 ? "no triangles: the file's " + std::to_string(scene_.mNumMeshes) +
                                                           " mesh primitives hold none"
                                                     : "no node carries a mesh of triangles: nothing is placed");
        }
        warn_unused();
        return std::move(reading_);
    }

private:
    static bool is_triangles(const aiMesh& primitive) { return primitive.mPrimitiveTypes == aiPrimitiveType_TRIANGLE; }

    std::size_t triangle_primitives() const {
        std::size_t count = 0;
        for (unsigned m = 0; m < scene_.mNumMeshes; ++m) {
            count += is_triangles(*scene_.mMeshes[m]);
        }
        return count;
    }

    void place_meshes_of(const aiNode& node, const MeshNode& to_world) {
        std::vector<unsigned> primitives;
        for (unsigned k = 0; k < node.mNumMeshes; ++k) {
            const unsigned m = node.mMeshes[k];
            if (m >= scene_.mNumMeshes) {
                refuse_at(node_location(node), "assimp gave mesh primitive " + std::to_string(m) + " of " +
                                                   std::to_string(scene_.mNumMeshes));
            }
            placed_primitives_[m] = true;
            if (is_triangles(*scene_.mMeshes[m])) {
                primitives.push_back(m);
            }
        }
        if (primitives.empty()) {
            return;
        }
        if (reading_.nodes.size() == max_triangles_) {
            refuse_too_many_triangles(node_location(node),
                                      "its nodes that carry meshes number more than " + std::to_string(max_triangles_),
                                      max_triangles_);
        }
        auto [known, added] = mesh_of_primitives_.try_emplace(primitives, reading_.meshes.size());
        if (added) {
            reading_.meshes.push_back(merged(primitives));
        }
        MeshNode placed = to_world;
        placed.mesh = static_cast<std::uint32_t>(known->second);
        placed.name = printable(node.mName.C_Str(), 60);
        reading_.nodes.push_back(std::move(placed));
    }

    // A glTF mesh: its triangle primitives' vertices one after the other, their triangles indexing them.
    MeshData merged(const std::vector<unsigned>& primitives) {
        MeshData mesh;
        bool every_vertex_has_a_normal = true;
        for (const unsigned m : primitives) {
            const aiMesh& primitive = *scene_.mMeshes[m];
            triangles_ += primitive.mNumFaces;
            vertices_ += primitive.mNumVertices;
            if (triangles_ > max_triangles_) {
                refuse_too_many_triangles(mesh_location(primitive),
                                          "it brings the triangles to " + std::to_string(triangles_), max_triangles_);
            }
            if (vertices_ > max_vertices_for(max_triangles_)) {
                refuse_too_many_vertices(mesh_location(primitive), vertices_, max_triangles_);
            }
            const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
            for (unsigned v = 0; v < primitive.mNumVertices; ++v) {
                const aiVector3D& p = primitive.mVertices[v];
                if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                    refuse_at(mesh_location(primitive),
                              "vertex " + std::to_string(v) + " is not finite (" + coordinates(p.x, p.y, p.z) + ")");
                }
                mesh.vertices.push_back({p.x, p.y, p.z});
            }
            for (unsigned f = 0; f < primitive.mNumFaces; ++f) {
                const aiFace& face = primitive.mFaces[f];
                if (face.mNumIndices != 3) {
                    refuse_at(mesh_location(primitive), "assimp gave triangle " + std::to_string(f) + " " +
                                                            std::to_string(face.mNumIndices) + " vertices");
                }
                std::array<std::uint32_t, 3> triangle{};
                for (int k = 0; k < 3; ++k) {
                    if (face.mIndices[k] >= primitive.mNumVertices) {
                        refuse_at(mesh_location(primitive), "triangle " + std::to_string(f) + " has vertex index " +
                                                                std::to_string(face.mIndices[k]) + ", out of range: " +
                                                                std::to_string(primitive.mNumVertices) + " vertices");
                    }
                    triangle[k] = first + face.mIndices[k];
                }
                mesh.triangles.push_back(triangle);
            }
            every_vertex_has_a_normal = every_vertex_has_a_normal && take_normals(primitive, mesh.normals);
        }
        if (every_vertex_has_a_normal) {
            mesh.smooth = true;
        } else {
            mesh.normals.clear();
        }
        return mesh;
    }

    // Appends the primitive's normals; false (with a warning) where it has none or one without a direction.
    bool take_normals(const aiMesh& primitive, std::vector<Vec3>& normals) {
        if (!primitive.HasNormals()) {
            return false;
        }
        for (unsigned v = 0; v < primitive.mNumVertices; ++v) {
            const Vec3 normal{primitive.mNormals[v].x, primitive.mNormals[v].y, primitive.mNormals[v].z};
            const double size = length(normal);
            if (!(size > 0) || !std::isfinite(size)) {
                reading_.warnings.push_back("normals of " + mesh_location(primitive) + " are not used: vertex " +
                                            std::to_string(v) + "'s has no direction");
                return false;
            }
            normals.push_back(normal);  // made unit length by the loader, as inline normals are
        }
        return true;
    }

    void warn_unused() {
        // assimp adds a material of its own, unnamed: only named ones are listed.
        std::set<std::string> materials;
        for (unsigned m = 0; m < scene_.mNumMaterials; ++m) {
            const std::string name = scene_.mMaterials[m]->GetName().C_Str();
            if (!name.empty() && name != AI_DEFAULT_MATERIAL_NAME) {
                materials.insert(name);
            }
        }
        std::set<std::string> unplaced, points_and_lines, skinned, morphed, textured, coloured;
        for (unsigned m = 0; m < scene_.mNumMeshes; ++m) {
            const aiMesh& primitive = *scene_.mMeshes[m];
            const std::string name = primitive.mName.C_Str();
            if (!placed_primitives_[m]) {
                unplaced.insert(name);
            }
            if (!is_triangles(primitive)) {
                points_and_lines.insert(name);
            }
            if (primitive.HasBones()) {
                skinned.insert(name);
            }
            if (primitive.mNumAnimMeshes > 0) {
                morphed.insert(name);
            }
            if (primitive.HasTextureCoords(0)) {
                textured.insert(name);
            }
            if (primitive.HasVertexColors(0)) {
                coloured.insert(name);
            }
        }
        const auto warn = [this](const std::string& what, const std::set<std::string>& names) {
            if (!names.empty()) {
                reading_.warnings.push_back(what + " " + quoted_names(names));
            }
        };
        warn("materials (and their textures) are not used:", materials);
        warn("points and lines are not drawn, only triangles: primitives of mesh", points_and_lines);
        warn("meshes no node places are not used:", unplaced);
        warn("skins are not used (the meshes are drawn as the nodes place them): mesh", skinned);
        warn("morph targets are not used: mesh", morphed);
        warn("texture coordinates are not used: mesh", textured);
        warn("vertex colours are not used: mesh", coloured);
        const auto warn_count = [this](unsigned count, const char* what) {
            if (count > 0) {
                reading_.warnings.push_back(std::to_string(count) + " " + what + " not used");
            }
        };
        warn_count(scene_.mNumTextures, "embedded textures are");
        warn_count(scene_.mNumCameras, "cameras are");
        warn_count(scene_.mNumLights, "lights are");
        warn_count(scene_.mNumAnimations, "animations are");
    }

    const aiScene& scene_;
    const std::size_t max_triangles_;
    MeshReading reading_;
    std::map<std::vector<unsigned>, std::size_t> mesh_of_primitives_;  // a node's triangle primitives -> its mesh
    std::vector<bool> placed_primitives_;                              // by a node
    std::size_t triangles_ = 0;                                        // in reading_.meshes
    std::size_t vertices_ = 0;
};

}  // namespace

MeshReading read_gltf(const std::filesystem::path& file, std::size_t max_triangles) {
    refuse_required_extensions(file);
    const AssimpLog log;
    Assimp::Importer importer;
    // No post-processing: the primitives as the file has them (assimp makes strips and fans triangles itself).
    const aiScene* scene = importer.ReadFile(file.string(), 0);
    if (!scene) {
        refuse_at("", "assimp: " + printable(importer.GetErrorString()));
    }
    if (log.says("out-of-range indices")) {
        refuse_at("", "a triangle's vertex index is out of range (assimp dropped the triangles that have one)");
    }
    return GltfReader(*scene, max_triangles).read();
}

}  // namespace twinray::scene::meshio
