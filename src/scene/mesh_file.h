// Triangle meshes from OBJ, PLY and STL files (ASCII and binary) and glTF 2 files (.gltf, .glb), read in a process
// of their own
// (twinray_mesh_reader, through the mesh library module: meshio/library.h), so that a library that crashes,
// aborts or hangs on a file costs an error message naming the file, never twinray; twinray itself maps no
// mesh library and parses no mesh file's bytes. Which library reads what, and in which precision:
// docs/performance.md, "Mesh files: the library".
#pragma once

#include "scene/mesh_node.h"
#include "scene/scene.h"

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace twinray::scene {

// A file's meshes, each in its own space, and the nodes that place them: every mesh placed by one node at least.
// An OBJ, PLY or STL file gives one mesh and one node at the identity.
struct MeshFileResult {
    std::vector<MeshData> meshes;
    std::vector<MeshNode> nodes;
    std::vector<std::string> warnings;  // what the file has that is not used: materials, colours, texture coordinates
};

// The process that reads the file, and how long it may take before it is stopped.
struct MeshReader {
    std::filesystem::path program = default_program();
    std::chrono::milliseconds time_limit{60'000};

    static std::filesystem::path default_program();
};

// The file's format by its extension (.obj, .ply, .stl, .gltf, .glb, any case). glTF: each mesh a node of the file's
// scene carries is one mesh (its triangle primitives merged, in its own space, in assimp's float), shared by every node
// that carries it, and each such node places it by its world transform (its matrix and its ancestors', assimp's floats
// composed from the root in double); points, lines and what is not geometry are warned of.
// OBJ, PLY, STL: all of a file's groups, objects and solids make one mesh: polygons triangulated by ear clipping
// (meshio/polygon.h: a convex polygon gives the fan from its first corner), triangles in file order, degenerate ones
// kept and listed (those with a repeated index; three collinear vertices are left to the caller). Vertices: OBJ's and
// PLY's as the file numbers them, STL's welded by bit-identical coordinates. Normals, when the file gives every vertex
// one (OBJ's vn on every face corner, PLY's nx ny nz, glTF's NORMAL): as the file writes them, each non-zero and finite
// (the loader makes them unit length, as it does inline normals), one per vertex (an OBJ vertex given with several
// normals is split, the copies appended), and `smooth` set; STL's facet normals are not read. Throws SceneError (file,
// location such as "line 12", "face[3]" or `mesh "Wheel"`, problem) for an unreadable file, an unknown extension, a
// malformed or truncated file, no triangles, no node carrying a mesh, a coordinate or node matrix that is not finite,
// an index out of range, more than `max_triangles` triangles in its meshes or nodes carrying them (at most
// max_scene_primitives: larger is not honoured; PLY and binary STL are refused from their header, before anything is
// read) or more than three vertices per triangle of that limit, and when the reader crashes, fails or runs out of time.
// What the scene holds of them (instances, or the nodes' meshes placed into one) the loader counts again.
MeshFileResult read_mesh_file(const std::filesystem::path& file, std::size_t max_triangles);
MeshFileResult read_mesh_file(const std::filesystem::path& file, std::size_t max_triangles, const MeshReader& reader);

// The reader process's standard output (scene/mesh_wire.h) as the meshes and nodes of `file`, trusting none of
// it: a refusal becomes its SceneError; bytes that are no message, counts past what they hold or past the limit,
// an index out of range, a value that is not finite, normals that do not match the vertices, a node placing no
// mesh sent or a mesh no node places become a SceneError saying the result was malformed. Degenerate triangles
// (a repeated index) are listed here.
MeshFileResult mesh_from_reader_output(const std::string& file, std::string output, std::size_t max_triangles);

// Edges are vertex pairs after welding vertices at bit-identical positions (so that an OBJ or PLY file with a
// vertex repeated per face, as STL always has, is judged by its shape); degenerate triangles are left out.
struct MeshTopology {
    std::size_t boundary_edges = 0;              // used by one triangle
    std::size_t non_manifold_edges = 0;          // used by three or more
    std::size_t inconsistently_wound_edges = 0;  // used by two that run along it the same way

    // Watertight and consistently wound: every edge is shared by exactly two triangles, in opposite directions
    // (what "inside" needs: a ray enters at a front and leaves at a back).
    bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0 && inconsistently_wound_edges == 0; }
};

MeshTopology topology_of(const MeshData& mesh);

}  // namespace twinray::scene
