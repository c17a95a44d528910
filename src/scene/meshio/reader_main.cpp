// twinray_mesh_reader FILE MAX_TRIANGLES: reads one mesh file through the mesh library module and sends its
// meshes and nodes, or why it was refused, on its standard output (scene/mesh_wire.h). twinray runs it for each
// mesh file (scene/mesh_file.h), so that whatever the libraries do on a file — crash, abort, hang — happens here.
#include "io/shared_module.h"
#include "scene/mesh_wire.h"
#include "scene/meshio/library.h"

#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

namespace {

using twinray::scene::meshio::MeshLibraryFunctions;
using twinray::scene::meshio::MeshReading;

// The module installed beside this reader, else in this build tree (both set by src/CMakeLists.txt).
MeshReading read(const char* file, std::size_t max_triangles) {
    try {
        const auto& library = twinray::io::load_shared_module<MeshLibraryFunctions>(
            twinray::io::installed_or_built(TWINRAY_MESH_LIBRARY_INSTALLED, TWINRAY_MESH_LIBRARY).c_str(),
            "twinray_mesh_library_functions", "the mesh library module");
        return library.read(file, max_triangles);
    } catch (const std::exception& error) {
        MeshReading reading;
        reading.refusal = twinray::scene::Refusal{"", error.what()};
        return reading;
    }
}

}  // namespace

// The process ends after one file, and what a library leaks on a file it refuses ends with it (assimp 5.2.5 leaks
// on an ASCII STL it cannot parse): a LeakSanitizer build must not turn that into a failed read. Only a
// sanitizer runtime calls this.
extern "C" const char* __lsan_default_options() {
    return "detect_leaks=0";
}

int main(int argc, char** argv) {
    std::size_t max_triangles = 0;
    const char* limit = argc == 3 ? argv[2] : "";
    const auto [end, error] = std::from_chars(limit, limit + std::strlen(limit), max_triangles);
    if (error != std::errc{} || *end != '\0' || *limit == '\0') {
        std::fprintf(stderr, "usage: twinray_mesh_reader FILE MAX_TRIANGLES\n");
        return 2;
    }
    MeshReading reading = read(argv[1], max_triangles);
    twinray::scene::wire::Message message;
    if (reading.refusal) {
        message.kind = twinray::scene::wire::Kind::refusal;
        message.texts = {reading.refusal->location, reading.refusal->problem};
    } else {
        message.meshes = std::move(reading.meshes);
        message.nodes = std::move(reading.nodes);
        message.texts = std::move(reading.warnings);
    }
    return twinray::scene::wire::send(STDOUT_FILENO, message) ? 0 : 1;
}
