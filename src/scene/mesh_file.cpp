#include "scene/mesh_file.h"

#include "io/shared_module.h"
#include "scene/loader.h"
#include "scene/mesh_wire.h"
#include "scene/read_values.h"
#include "scene/reader_process.h"
#include "scene/refusal.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <system_error>

namespace twinray::scene {
namespace {

// What the reader may send at most for meshes at the limit: vertices and normals (three per triangle), triangles,
// as many nodes (their mesh, matrix and a name of at most a few hundred bytes), and a megabyte of counts and
// warnings.
std::size_t max_message_size(std::size_t max_triangles) {
    constexpr std::size_t node_size = 2 * sizeof(std::uint64_t) + sizeof(math::Matrix3<double>) + sizeof(Vec3) + 256;
    return (std::size_t{1} << 20) +
           max_triangles * (3 * 2 * sizeof(Vec3) + sizeof(std::array<std::uint32_t, 3>) + node_size);
}

// Before the reader is started: a file that cannot be opened, or is no regular file (a FIFO would block the
// reader until its time is up), is refused here.
void check_readable(const std::string& name) {
    const int descriptor = ::open(name.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (descriptor < 0) {
        throw SceneError(name, "", "cannot open file: " + std::error_code(errno, std::generic_category()).message());
    }
    struct stat status {};
    const bool known = ::fstat(descriptor, &status) == 0;
    ::close(descriptor);
    if (known && S_ISDIR(status.st_mode)) {
        throw SceneError(name, "", "cannot read file: it is a directory");
    }
    if (!known || !S_ISREG(status.st_mode)) {
        throw SceneError(name, "", "cannot read file: it is not a regular file");
    }
}

void check_extension(const std::string& name, const std::filesystem::path& file) {
    std::string extension = file.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension != ".obj" && extension != ".ply" && extension != ".stl" && extension != ".gltf" &&
        extension != ".glb") {
        throw SceneError(name, "",
                         "unknown mesh file extension \"" + file.extension().string() +
                             "\": twinray reads .obj, .ply, .stl, .gltf and .glb");
    }
}

// The reader's last words (its standard error: an abort's or a sanitizer's message), on one line.
std::string last_words(const std::string& errors) {
    std::string words;
    for (const char c : errors) {
        words += std::isprint(static_cast<unsigned char>(c)) ? c : ' ';
    }
    words.erase(0, words.find_first_not_of(' '));
    words.erase(words.find_last_not_of(' ') + 1);
    return words.empty() ? "" : ": " + words;
}

std::string seconds(std::chrono::milliseconds duration) {
    return format_number(static_cast<double>(duration.count()) / 1000.0) + " s";
}

[[noreturn]] void wrong(const std::string& what) {
    throw std::runtime_error(what);
}

// One of the reader's meshes checked again; its degenerate triangles listed.
void check_mesh(MeshData& mesh, std::size_t index) {
    const std::string which = "mesh " + std::to_string(index) + " ";
    if (mesh.triangles.empty()) {
        wrong(which + "has no triangles");
    }
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.vertices.size()) {
        wrong(which + "has " + std::to_string(mesh.normals.size()) + " normals for " +
              std::to_string(mesh.vertices.size()) + " vertices");
    }
    if (mesh.smooth != !mesh.normals.empty()) {
        wrong("smooth without normals, or normals without smooth");
    }
    auto finite = [](const Vec3& v) { return is_finite(v); };
    if (!std::all_of(mesh.vertices.begin(), mesh.vertices.end(), finite) ||
        !std::all_of(mesh.normals.begin(), mesh.normals.end(), finite)) {
        wrong("a value that is not finite");
    }
    // The loader makes normals unit length: a zero one would become NaN.
    if (std::any_of(mesh.normals.begin(), mesh.normals.end(), is_zero)) {
        wrong("a normal of zero length");
    }
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& [a, b, c] = mesh.triangles[t];
        if (std::max({a, b, c}) >= mesh.vertices.size()) {
            wrong(which + "triangle " + std::to_string(t) + " has an index out of range");
        }
        if (a == b || b == c || c == a) {
            mesh.degenerate.push_back(static_cast<std::uint32_t>(t));
        }
    }
}

// The reader's message as meshes and nodes, everything it says checked again (the receiving end of the wire has
// checked each node's mesh index against the meshes sent).
MeshFileResult checked(wire::Message message, std::size_t max_triangles) {
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    for (const MeshData& mesh : message.meshes) {
        triangles += mesh.triangles.size();
        vertices += mesh.vertices.size();
    }
    if (message.meshes.empty() || message.nodes.empty() || triangles > max_triangles || vertices > 3 * max_triangles ||
        message.nodes.size() > max_triangles) {
        wrong(std::to_string(message.meshes.size()) + " meshes of " + std::to_string(triangles) + " triangles and " +
              std::to_string(vertices) + " vertices, placed by " + std::to_string(message.nodes.size()) + " nodes");
    }
    for (std::size_t m = 0; m < message.meshes.size(); ++m) {
        check_mesh(message.meshes[m], m);
    }
    std::vector<bool> placed(message.meshes.size(), false);
    for (const MeshNode& node : message.nodes) {
        if (!is_finite(node.translation) || !is_finite(node.linear.row[0]) || !is_finite(node.linear.row[1]) ||
            !is_finite(node.linear.row[2])) {
            wrong("a node's matrix is not finite");
        }
        placed[node.mesh] = true;
    }
    if (std::find(placed.begin(), placed.end(), false) != placed.end()) {
        wrong("a mesh that no node places");
    }
    return {std::move(message.meshes), std::move(message.nodes), std::move(message.texts)};
}

}  // namespace

std::filesystem::path MeshReader::default_program() {
    // Installed beside twinray, else in this build tree (both paths set by src/CMakeLists.txt).
    return io::installed_or_built(TWINRAY_MESH_READER_INSTALLED, TWINRAY_MESH_READER);
}

MeshFileResult read_mesh_file(const std::filesystem::path& file, std::size_t max_triangles) {
    return read_mesh_file(file, max_triangles, MeshReader{});
}

MeshFileResult read_mesh_file(const std::filesystem::path& file, std::size_t max_triangles, const MeshReader& reader) {
    const std::string name = file.string();
    check_extension(name, file);
    check_readable(name);
    const std::size_t limit = std::min(max_triangles, max_scene_primitives);
    ProcessOutcome outcome;
    try {
        outcome =
            run_process(reader.program, {name, std::to_string(limit)}, reader.time_limit, max_message_size(limit));
    } catch (const std::runtime_error& error) {
        throw SceneError(name, "", std::string("the mesh reader did not run: ") + error.what());
    }
    switch (outcome.end) {
        case ProcessOutcome::End::killed_by_signal:
            throw SceneError(name, "",
                             "the mesh reader crashed on this file (signal " + std::to_string(outcome.status) + ", " +
                                 strsignal(outcome.status) + ")" + last_words(outcome.errors));
        case ProcessOutcome::End::timed_out:
            throw SceneError(
                name, "",
                "the mesh reader took longer than " + seconds(reader.time_limit) + " on this file and was stopped");
        case ProcessOutcome::End::too_much_output:
            throw SceneError(name, "", "the mesh reader sent more than a mesh at the limit takes, and was stopped");
        case ProcessOutcome::End::exited: break;
    }
    if (outcome.status != 0) {
        throw SceneError(name, "",
                         "the mesh reader failed on this file (exit status " + std::to_string(outcome.status) + ")" +
                             last_words(outcome.errors));
    }
    return mesh_from_reader_output(name, std::move(outcome.output), limit);
}

MeshFileResult mesh_from_reader_output(const std::string& file, std::string output, std::size_t max_triangles) {
    const auto malformed = [&file](const std::runtime_error& error) {
        return SceneError(file, "", std::string("the mesh reader sent a malformed result: ") + error.what());
    };
    wire::Message message;
    try {
        message = wire::receive(output);
    } catch (const std::runtime_error& error) {
        throw malformed(error);
    }
    output = std::string();  // its memory back before the mesh is checked
    if (message.kind == wire::Kind::refusal) {
        throw SceneError(file, message.texts[0], message.texts[1]);
    }
    try {
        MeshFileResult result = checked(std::move(message), max_triangles);
        for (MeshData& mesh : result.meshes) {
            mesh.file = file;
        }
        return result;
    } catch (const std::runtime_error& error) {
        throw malformed(error);
    }
}

MeshTopology topology_of(const MeshData& mesh) {
    // Each vertex's representative: the first of those at its bits, found by sorting.
    const auto bits = [&mesh](std::uint32_t v) {
        const Vec3& p = mesh.vertices[v];
        return std::array{std::bit_cast<std::uint64_t>(p.x), std::bit_cast<std::uint64_t>(p.y),
                          std::bit_cast<std::uint64_t>(p.z)};
    };
    std::vector<std::uint32_t> order(mesh.vertices.size());
    std::iota(order.begin(), order.end(), 0U);
    std::stable_sort(order.begin(), order.end(),
                     [&bits](std::uint32_t a, std::uint32_t b) { return bits(a) < bits(b); });
    std::vector<std::uint32_t> welded(mesh.vertices.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        welded[order[i]] = i > 0 && bits(order[i]) == bits(order[i - 1]) ? welded[order[i - 1]] : order[i];
    }
    // Every edge as (lower vertex, higher vertex, 1 if it runs from higher to lower), sorted so that the
    // triangles sharing an edge are neighbours.
    std::vector<std::array<std::uint32_t, 3>> edges;
    edges.reserve(3 * mesh.triangles.size());
    for (const auto& triangle : mesh.triangles) {
        const std::array<std::uint32_t, 3> corners{welded[triangle[0]], welded[triangle[1]], welded[triangle[2]]};
        if (corners[0] == corners[1] || corners[1] == corners[2] || corners[2] == corners[0]) {
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t from = corners[k];
            const std::uint32_t to = corners[(k + 1) % 3];
            edges.push_back({std::min(from, to), std::max(from, to), from > to ? 1U : 0U});
        }
    }
    std::sort(edges.begin(), edges.end());
    MeshTopology topology;
    for (std::size_t first = 0; first < edges.size();) {
        std::size_t last = first + 1;
        while (last < edges.size() && edges[last][0] == edges[first][0] && edges[last][1] == edges[first][1]) {
            ++last;
        }
        const std::size_t uses = last - first;
        if (uses == 1) {
            ++topology.boundary_edges;
        } else if (uses > 2) {
            ++topology.non_manifold_edges;
        } else if (edges[first][2] == edges[first + 1][2]) {
            ++topology.inconsistently_wound_edges;
        }
        first = last;
    }
    return topology;
}

}  // namespace twinray::scene
