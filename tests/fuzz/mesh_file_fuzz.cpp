// libFuzzer target for mesh files: arbitrary bytes, saved as an OBJ, PLY, STL or glTF file, through the mesh library
// module's readers (scene/meshio/library.h: our PLY reader, tinyobjloader, assimp), here in this process, where
// a render runs them in twinray_mesh_reader; then twinray's receiving end (mesh_from_reader_output, which checks
// what the reader process sends) on the reading as sent, and on the bytes themselves as a reader gone wrong.
//
// What it holds them to, beyond what ASan and UBSan catch: a reader refuses only with a refusal that says what
// is wrong; an accepted reading has meshes and nodes, every mesh a triangle and a node placing it, no more
// triangles (in all its meshes) nor nodes than the limit nor vertices than three per triangle of it, every index in
// range, finite vertices and node matrices, one finite non-zero normal per vertex or none; the receiving end gives
// back exactly the meshes and nodes sent, and refuses other bytes only with a SceneError. A broken
// promise aborts and libFuzzer keeps the input.
// tinyobjloader is compiled here, so coverage sees it; assimp is Debian's uninstrumented build, seen by ASan only
// through the calls it intercepts (docs/reliability.md). Built only with -DTWINRAY_FUZZ=ON (preset `fuzz`).
#include "promise.h"
#include "scene/loader.h"
#include "scene/mesh_file.h"
#include "scene/mesh_wire.h"
#include "scene/meshio/library.h"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace {

namespace fs = std::filesystem;
using twinray::scene::MeshData;
using twinray::scene::MeshNode;
using twinray::scene::Vec3;

// Small, so that inputs reach the refusals past the limit, which the seeds' counts are near.
constexpr std::size_t fuzz_triangle_limit = 500;

void expect(bool holds, const char* what) {
    twinray::fuzz::expect(holds, "mesh_file_fuzz", what);
}

// The format by the bytes, so that the seeds are real files as they are: "ply" begins a PLY, "solid" an ASCII
// STL, "glTF" a binary glTF and "{" a glTF, and a binary STL is 84 bytes and 50 per triangle its header declares;
// anything else is read as OBJ.
const char* extension_for(std::string_view bytes) {
    if (bytes.starts_with("ply")) {
        return ".ply";
    }
    if (bytes.starts_with("glTF")) {
        return ".glb";
    }
    if (bytes.starts_with("{")) {
        return ".gltf";
    }
    if (bytes.starts_with("solid")) {
        return ".stl";
    }
    if (bytes.size() >= 84) {
        std::uint32_t triangles = 0;
        std::memcpy(&triangles, bytes.data() + 80, sizeof triangles);
        if (84 + std::uint64_t{triangles} * 50 == bytes.size()) {
            return ".stl";
        }
    }
    return ".obj";
}

void check_accepted(const MeshData& mesh) {
    expect(!mesh.triangles.empty(), "an accepted mesh has a triangle");
    for (const Vec3& vertex : mesh.vertices) {
        expect(is_finite(vertex), "vertices are finite");
    }
    for (const auto& triangle : mesh.triangles) {
        for (const std::uint32_t index : triangle) {
            expect(index < mesh.vertices.size(), "triangle indices are in range");
        }
    }
    expect(mesh.normals.empty() || mesh.normals.size() == mesh.vertices.size(), "one normal per vertex, or none");
    expect(mesh.smooth == !mesh.normals.empty(), "a mesh is smooth exactly when it has normals");
    for (const Vec3& normal : mesh.normals) {
        expect(is_finite(normal) && (normal.x != 0 || normal.y != 0 || normal.z != 0), "normals are finite, non-zero");
    }
}

void check_accepted(const std::vector<MeshData>& meshes, const std::vector<MeshNode>& nodes) {
    expect(!meshes.empty() && !nodes.empty(), "an accepted reading has meshes and nodes");
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    for (const MeshData& mesh : meshes) {
        check_accepted(mesh);
        triangles += mesh.triangles.size();
        vertices += mesh.vertices.size();
    }
    expect(triangles <= fuzz_triangle_limit, "an accepted reading's meshes are within the triangle limit");
    expect(vertices <= 3 * fuzz_triangle_limit, "an accepted reading has at most three vertices a triangle");
    expect(nodes.size() <= fuzz_triangle_limit, "an accepted reading's nodes are within the limit");
    std::vector<bool> placed(meshes.size(), false);
    for (const MeshNode& node : nodes) {
        expect(node.mesh < meshes.size(), "a node places a mesh sent");
        expect(is_finite(node.translation) && is_finite(node.linear.row[0]) && is_finite(node.linear.row[1]) &&
                   is_finite(node.linear.row[2]),
               "node matrices are finite");
        placed[node.mesh] = true;
    }
    expect(std::find(placed.begin(), placed.end(), false) == placed.end(), "every mesh is placed by a node");
}

bool same_vectors(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0);
}

// What the reader process would send, through a file in memory (a pipe could fill up: this is one process).
std::string as_sent(const twinray::scene::wire::Message& message) {
    const int descriptor = ::memfd_create("mesh_file_fuzz", MFD_CLOEXEC);
    expect(descriptor >= 0, "memfd_create works");
    expect(twinray::scene::wire::send(descriptor, message), "a reading can be sent");
    const off_t size = ::lseek(descriptor, 0, SEEK_CUR);
    std::string bytes(static_cast<std::size_t>(size), '\0');
    expect(::pread(descriptor, bytes.data(), bytes.size(), 0) == size, "what was sent can be read back");
    ::close(descriptor);
    return bytes;
}

void check_received_as_sent(const twinray::scene::meshio::MeshReading& reading) {
    twinray::scene::wire::Message message;
    message.meshes = reading.meshes;
    message.nodes = reading.nodes;
    message.texts = reading.warnings;
    const twinray::scene::MeshFileResult received =
        twinray::scene::mesh_from_reader_output("fuzz.mesh", as_sent(message), fuzz_triangle_limit);
    expect(received.meshes.size() == reading.meshes.size(), "the receiving end gives back every mesh sent");
    for (std::size_t m = 0; m < received.meshes.size(); ++m) {
        const MeshData& got = received.meshes[m];
        const MeshData& sent = reading.meshes[m];
        expect(same_vectors(got.vertices, sent.vertices) && same_vectors(got.normals, sent.normals) &&
                   got.triangles == sent.triangles && got.smooth == sent.smooth,
               "the receiving end gives back the meshes sent");
    }
    expect(received.nodes.size() == reading.nodes.size(), "the receiving end gives back every node sent");
    for (std::size_t n = 0; n < received.nodes.size(); ++n) {
        const MeshNode& got = received.nodes[n];
        const MeshNode& sent = reading.nodes[n];
        expect(got.mesh == sent.mesh && std::memcmp(&got.linear, &sent.linear, sizeof got.linear) == 0 &&
                   std::memcmp(&got.translation, &sent.translation, sizeof got.translation) == 0 &&
                   got.name == sent.name,
               "the receiving end gives back the nodes sent");
    }
    expect(received.warnings == reading.warnings, "the receiving end gives back the warnings sent");
}

// The bytes as a reader process's output: refused with a SceneError, or a mesh every promise holds for.
void check_bytes_as_output(std::string_view bytes) {
    try {
        const twinray::scene::MeshFileResult received =
            twinray::scene::mesh_from_reader_output("fuzz.mesh", std::string(bytes), fuzz_triangle_limit);
        check_accepted(received.meshes, received.nodes);
        for (const MeshData& mesh : received.meshes) {
            for (const std::uint32_t triangle : mesh.degenerate) {
                expect(triangle < mesh.triangles.size(), "degenerate triangles are in range");
            }
        }
    } catch (const twinray::scene::SceneError& error) {
        expect(std::strlen(error.what()) > 0, "a refused output says why");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    // One file per process and format, rewritten for each input.
    static const fs::path folder = fs::temp_directory_path() / ("twinray_mesh_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(folder);
    const fs::path file = folder / (std::string("input") + extension_for(bytes));
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        expect(static_cast<bool>(out), "the input can be written to a file");
    }
    const twinray::scene::meshio::MeshReading reading = twinray::scene::meshio::read_mesh(file, fuzz_triangle_limit);
    if (reading.refusal) {
        expect(!reading.refusal->problem.empty(), "a refusal says what is wrong");
    } else {
        check_accepted(reading.meshes, reading.nodes);
        check_received_as_sent(reading);
    }
    check_bytes_as_output(bytes);
    return 0;
}
