// The mesh file libraries (tinyobjloader, assimp) and our PLY reader in a module of our own
// (libtwinray_mesh_library.so), loaded with dlopen by the mesh reader process (reader_main.cpp) only: twinray
// never maps them, so a command that reads no mesh file never pays for them, and a library that crashes or
// hangs on a file takes down that process, never twinray (scene/mesh_file.h).
#pragma once

#include "scene/mesh_node.h"
#include "scene/refusal.h"
#include "scene/scene.h"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace twinray::scene::meshio {

// A file read, or why not: its meshes and the nodes that place them (mesh_node.h). Each mesh's `degenerate` and
// `file` are left for the receiving end to fill.
struct MeshReading {
    std::vector<MeshData> meshes;
    std::vector<MeshNode> nodes;
    std::vector<std::string> warnings;
    std::optional<Refusal> refusal;  // location: "line 12", "face 3", ... or "" for the file as a whole
};

// The file's format by its extension (.obj, .ply, .stl, .gltf or .glb, any case), at most `max_triangles` triangles
// in all its meshes, as many nodes, and three vertices per triangle of that limit. Never throws: whatever goes
// wrong is a refusal.
MeshReading read_mesh(const std::filesystem::path& file, std::size_t max_triangles);

// What the module offers, returned by its one exported symbol, twinray_mesh_library_functions.
struct MeshLibraryFunctions {
    MeshReading (*read)(const std::filesystem::path& file, std::size_t max_triangles);
};

}  // namespace twinray::scene::meshio

extern "C" const twinray::scene::meshio::MeshLibraryFunctions* twinray_mesh_library_functions();
