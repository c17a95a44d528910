// What the mesh reader process (meshio/reader_main.cpp) sends twinray on its standard output: a file's meshes and
// the nodes that place them (an OBJ, PLY or STL file's one mesh placed once, as it stands), or a refusal, in this
// machine's byte order (both ends are one build). The receiving end (mesh_file.cpp) trusts none of it: every count
// is checked against what the bytes can hold before anything is allocated, and the meshes and nodes are checked
// again.
#pragma once

#include "scene/mesh_node.h"
#include "scene/scene.h"

#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace twinray::scene::wire {

static_assert(sizeof(Vec3) == 3 * sizeof(double) && std::is_trivially_copyable_v<Vec3>);
static_assert(sizeof(math::Matrix3<double>) == 9 * sizeof(double) &&
              std::is_trivially_copyable_v<math::Matrix3<double>>);

constexpr std::uint64_t magic = 0x32687365'6d727774;  // "twrmesh2" in this machine's byte order
enum class Kind : std::uint8_t { mesh = 1, refusal = 2 };

struct Message {
    Kind kind = Kind::mesh;
    std::vector<MeshData> meshes;    // for Kind::mesh: vertices, triangles, normals, smooth of each
    std::vector<MeshNode> nodes;     // for Kind::mesh: each node that places one of `meshes`
    std::vector<std::string> texts;  // warnings; for Kind::refusal: location and problem
};

// Writes everything or returns false (the reader then exits with an error; twinray says the result was cut).
inline bool write_all(int descriptor, const void* data, std::size_t size) {
    const char* at = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t written = ::write(descriptor, at, size);
        if (written < 0 && errno == EINTR) {
            continue;
        }
        if (written <= 0) {
            return false;
        }
        at += written;
        size -= static_cast<std::size_t>(written);
    }
    return true;
}

inline bool send(int descriptor, const Message& message) {
    const auto put = [descriptor](std::uint64_t value) { return write_all(descriptor, &value, sizeof value); };
    const auto put_text = [&](const std::string& text) {
        return put(text.size()) && write_all(descriptor, text.data(), text.size());
    };
    bool ok = put(magic) && put(static_cast<std::uint64_t>(message.kind)) && put(message.texts.size());
    for (const std::string& text : message.texts) {
        ok = ok && put_text(text);
    }
    if (message.kind == Kind::mesh) {
        ok = ok && put(message.meshes.size());
        for (const MeshData& mesh : message.meshes) {
            ok = ok && put(mesh.vertices.size()) && put(mesh.triangles.size()) && put(mesh.normals.size()) &&
                 put(mesh.smooth) && write_all(descriptor, mesh.vertices.data(), mesh.vertices.size() * sizeof(Vec3)) &&
                 write_all(descriptor, mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0])) &&
                 write_all(descriptor, mesh.normals.data(), mesh.normals.size() * sizeof(Vec3));
        }
        ok = ok && put(message.nodes.size());
        for (const MeshNode& node : message.nodes) {
            ok = ok && put(node.mesh) && write_all(descriptor, &node.linear, sizeof node.linear) &&
                 write_all(descriptor, &node.translation, sizeof node.translation) && put_text(node.name);
        }
    }
    return ok;
}

// Throws std::runtime_error saying what is wrong with the bytes.
inline Message receive(std::string_view bytes) {
    const auto take = [&bytes](void* out, std::size_t size) {
        if (bytes.size() < size) {
            throw std::runtime_error("it ends early");
        }
        if (size == 0) {
            return;  // an empty list's data() may be null, which memcpy may not be given even for 0 bytes
        }
        std::memcpy(out, bytes.data(), size);
        bytes.remove_prefix(size);
    };
    const auto take_number = [&take] {
        std::uint64_t value = 0;
        take(&value, sizeof value);
        return value;
    };
    // A count of items of `size` bytes each, no more than the bytes left can hold.
    const auto take_count = [&](std::size_t size) {
        const std::uint64_t count = take_number();
        if (count > bytes.size() / size) {
            throw std::runtime_error("a count of " + std::to_string(count) + " is more than the bytes hold");
        }
        return static_cast<std::size_t>(count);
    };
    if (take_number() != magic) {
        throw std::runtime_error("it does not begin as one does");
    }
    Message message;
    const std::uint64_t kind = take_number();
    if (kind != static_cast<std::uint64_t>(Kind::mesh) && kind != static_cast<std::uint64_t>(Kind::refusal)) {
        throw std::runtime_error("unknown kind " + std::to_string(kind));
    }
    message.kind = static_cast<Kind>(kind);
    const auto take_text = [&](std::string& text) {
        text.resize(take_count(1));
        take(text.data(), text.size());
    };
    message.texts.resize(take_count(sizeof(std::uint64_t)));
    for (std::string& text : message.texts) {
        take_text(text);
    }
    if (message.kind == Kind::refusal && message.texts.size() != 2) {
        throw std::runtime_error("a refusal without its location and problem");
    }
    if (message.kind == Kind::mesh) {
        // A mesh takes its four counts at least; a node its mesh, its matrix and its name's length.
        message.meshes.resize(take_count(4 * sizeof(std::uint64_t)));
        for (MeshData& mesh : message.meshes) {
            mesh.vertices.resize(take_count(sizeof(Vec3)));
            mesh.triangles.resize(take_count(sizeof(mesh.triangles[0])));
            mesh.normals.resize(take_count(sizeof(Vec3)));
            mesh.smooth = take_number() != 0;
            take(mesh.vertices.data(), mesh.vertices.size() * sizeof(Vec3));
            take(mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]));
            take(mesh.normals.data(), mesh.normals.size() * sizeof(Vec3));
        }
        message.nodes.resize(take_count(2 * sizeof(std::uint64_t) + sizeof(math::Matrix3<double>) + sizeof(Vec3)));
        for (MeshNode& node : message.nodes) {
            const std::uint64_t mesh = take_number();
            if (mesh >= message.meshes.size()) {
                throw std::runtime_error("a node places mesh " + std::to_string(mesh) + " of " +
                                         std::to_string(message.meshes.size()));
            }
            node.mesh = static_cast<std::uint32_t>(mesh);
            take(&node.linear, sizeof node.linear);
            take(&node.translation, sizeof node.translation);
            take_text(node.name);
        }
    }
    if (!bytes.empty()) {
        throw std::runtime_error(std::to_string(bytes.size()) + " bytes follow its end");
    }
    return message;
}

}  // namespace twinray::scene::wire
