// Mesh files (scene/mesh_file.h): each format read with its exact counts and coordinates, each refusal with its
// message, the reader process's crash, abort and hang turned into errors, the topology report, and real files
// from Debian's assimp-testmodels package.
#include "scene/mesh_file.h"
#include "scene/loader.h"
#include "scene/mesh_wire.h"
#include "tests/gltf_files.h"
#include "tests/test_output.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace twinray::scene {
namespace {

namespace fs = std::filesystem;
using Triangle = std::array<std::uint32_t, 3>;

const fs::path meshes_dir = fs::path(TWINRAY_SOURCE_DIR) / "tests" / "data" / "meshes";
const fs::path testmodels_dir = "/usr/share/assimp/models";
constexpr std::size_t limit = max_scene_primitives;

// Called more than once in a test, so made, not emptied.
fs::path output_dir() {
    const fs::path dir = test::own_output_path("mesh_file");
    fs::create_directories(dir);
    return dir;
}

fs::path write_file(const std::string& name, const std::string& text) {
    const fs::path file = output_dir() / name;
    std::ofstream(file, std::ios::binary) << text;
    return file;
}

// gtest parameter names allow only letters, digits and underscores.
std::string test_name(std::string name) {
    std::replace_if(
        name.begin(), name.end(), [](unsigned char c) { return !std::isalnum(c); }, '_');
    return name;
}

// A stand-in for the mesh reader: a shell script.
fs::path fake_reader(const std::string& name, const std::string& script) {
    const fs::path file = write_file(name, "#!/bin/sh\n" + script + "\n");
    fs::permissions(file, fs::perms::owner_all);
    return file;
}

// The refusal of `file`, checked to name it; nullopt when it was read.
std::optional<SceneError> refusal_of(const fs::path& file, std::size_t max_triangles = limit,
                                     const MeshReader& reader = MeshReader{}) {
    try {
        read_mesh_file(file, max_triangles, reader);
    } catch (const SceneError& error) {
        EXPECT_EQ(error.file(), file.string());
        return error;
    }
    return std::nullopt;
}

// An OBJ, PLY or STL file's one mesh, checked to be placed once as it stands.
const MeshData& only_mesh(const MeshFileResult& result) {
    EXPECT_EQ(result.meshes.size(), 1U);
    EXPECT_EQ(result.nodes.size(), 1U);
    EXPECT_TRUE(!result.nodes.empty() && result.nodes[0].mesh == 0 && result.nodes[0].is_identity());
    return result.meshes.at(0);
}

// The unit cube of tests/data/meshes/make_meshes.py, scaled, and its quads' fans.
std::vector<Vec3> cube_vertices(double side) {
    std::vector<Vec3> vertices;
    for (const auto& [x, y, z] : std::vector<std::array<int, 3>>{
             {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}) {
        vertices.push_back({side * x, side * y, side * z});
    }
    return vertices;
}

const std::vector<Triangle> cube_triangles = {{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                              {2, 3, 7}, {2, 7, 6}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};

// ---------------------------------------------------------------------------------------------------
// Each format.

TEST(MeshFile, ObjCubeOfQuadsInTwoGroupsIsOneMeshOfFans) {
    const MeshFileResult result = read_mesh_file(meshes_dir / "cube.obj", limit);
    EXPECT_EQ(only_mesh(result).vertices, cube_vertices(1));
    EXPECT_EQ(only_mesh(result).triangles, cube_triangles);
    EXPECT_TRUE(only_mesh(result).normals.empty());
    EXPECT_FALSE(only_mesh(result).smooth);
    EXPECT_TRUE(only_mesh(result).degenerate.empty());
    EXPECT_TRUE(result.warnings.empty());
    EXPECT_EQ(only_mesh(result).file, (meshes_dir / "cube.obj").string());
    EXPECT_TRUE(topology_of(only_mesh(result)).closed());
}

TEST(MeshFile, ConcavePolygonIsCutAlongADiagonalInsideIt) {
    // The dart (0,0) (2,1) (4,0) (2,3): the fan from its first corner would give (0,1,2), outside it.
    const MeshFileResult result = read_mesh_file(meshes_dir / "concave.obj", limit);
    EXPECT_EQ(only_mesh(result).triangles, (std::vector<Triangle>{{1, 2, 3}, {0, 1, 3}}));
}

TEST(MeshFile, ObjNormalsSplitEachVertexTheFacesGiveSeveral) {
    // Each cube corner is on three faces, each face with its own normal: the file's eight vertices keep their
    // first normal and sixteen copies take the others. Relative indices, a normal of length 2, passed on as the
    // file writes it (the loader makes every mesh's normals unit length, inline or from a file, one way).
    const MeshFileResult result = read_mesh_file(meshes_dir / "cube_normals.obj", limit);
    const MeshData& mesh = only_mesh(result);
    ASSERT_EQ(mesh.vertices.size(), 24U);
    ASSERT_EQ(mesh.triangles.size(), 12U);
    EXPECT_TRUE(mesh.smooth);
    ASSERT_EQ(mesh.normals.size(), 24U);
    EXPECT_EQ(std::vector<Vec3>(mesh.vertices.begin(), mesh.vertices.begin() + 8), cube_vertices(1));
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const std::array<Vec3, 6> face_normals{{{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 0, 0}}};
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t vertex = mesh.triangles[t][k];
            const Vec3& normal = mesh.normals[vertex];
            EXPECT_EQ(normal / length(normal), face_normals[t / 2])
                << "triangle " << t << ": " << normal.x << ", " << normal.y << ", " << normal.z;
            EXPECT_EQ(mesh.vertices[vertex], cube_vertices(1)[cube_triangles[t][k]]) << "triangle " << t;
        }
    }
    EXPECT_EQ(result.warnings, std::vector<std::string>{"materials are not used: mtllib \"cube.mtl\"; usemtl \"red\""});
    // Split vertices are welded back for the topology.
    EXPECT_TRUE(topology_of(mesh).closed());
}

TEST(MeshFile, PlyAsciiAndBinaryReadTheSameDoubles) {
    // A cube of side 0.1: ASCII text and binary doubles alike give the double nearest 0.1, not a float's.
    for (const char* name : {"cube_ascii.ply", "cube_binary.ply", "cube_binary_big_endian.ply"}) {
        SCOPED_TRACE(name);
        const MeshFileResult result = read_mesh_file(meshes_dir / name, limit);
        EXPECT_EQ(only_mesh(result).vertices, cube_vertices(0.1));
        EXPECT_EQ(only_mesh(result).triangles, cube_triangles);
        EXPECT_FALSE(only_mesh(result).smooth);
        EXPECT_TRUE(result.warnings.empty());
        EXPECT_TRUE(topology_of(only_mesh(result)).closed());
    }
}

TEST(MeshFile, StlAsciiAndBinaryAreWeldedToTheCubesEightFloatVertices) {
    // 36 corners in the file, 8 positions: welded in the order they first appear. STL stores floats.
    const double side = static_cast<double>(0.1F);
    const std::vector<Vec3> expected_vertices = {{0, 0, 0},    {0, side, 0},    {side, side, 0},    {side, 0, 0},
                                                 {0, 0, side}, {side, 0, side}, {side, side, side}, {0, side, side}};
    const std::vector<Triangle> expected_triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}, {0, 3, 5}, {0, 5, 4},
                                                      {2, 1, 7}, {2, 7, 6}, {0, 4, 7}, {0, 7, 1}, {3, 2, 6}, {3, 6, 5}};
    for (const char* name : {"cube_ascii.stl", "cube_binary.stl"}) {
        SCOPED_TRACE(name);
        const MeshFileResult result = read_mesh_file(meshes_dir / name, limit);
        EXPECT_EQ(only_mesh(result).vertices, expected_vertices);
        EXPECT_EQ(only_mesh(result).triangles, expected_triangles);
        EXPECT_TRUE(only_mesh(result).normals.empty());
        EXPECT_TRUE(result.warnings.empty());
        EXPECT_TRUE(topology_of(only_mesh(result)).closed());
    }
}

TEST(MeshFile, DegenerateTrianglesAreKeptAndListed) {
    const fs::path file = write_file("degenerate.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 1 2\nf 2 3 3\n");
    const MeshFileResult result = read_mesh_file(file, limit);
    EXPECT_EQ(only_mesh(result).triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 0, 1}, {1, 2, 2}}));
    EXPECT_EQ(only_mesh(result).degenerate, (std::vector<std::uint32_t>{1, 2}));
}

TEST(MeshFile, ExtensionIsReadInAnyCase) {
    const fs::path file = output_dir() / "CUBE.OBJ";
    fs::copy_file(meshes_dir / "cube.obj", file, fs::copy_options::overwrite_existing);
    EXPECT_EQ(only_mesh(read_mesh_file(file, limit)).triangles.size(), 12U);
}

// ---------------------------------------------------------------------------------------------------
// Refusals: the file, where, and what is wrong.

struct Refused {
    std::string file;
    std::size_t max_triangles;
    std::string location;
    std::string problem;
};

void PrintTo(const Refused& refused, std::ostream* out) {
    *out << refused.file << " at most " << refused.max_triangles;
}

class MeshFileRefusal : public testing::TestWithParam<Refused> {};

TEST_P(MeshFileRefusal, NamesTheFileWhereAndWhat) {
    const Refused& refused = GetParam();
    const std::optional<SceneError> error = refusal_of(meshes_dir / refused.file, refused.max_triangles);
    ASSERT_TRUE(error) << "read, not refused";
    EXPECT_EQ(error->location(), refused.location);
    EXPECT_EQ(error->problem(), refused.problem);
}

const std::string over_eleven =
    ": more than the limit of 11 primitives (about 165 bytes of memory each when rendered; "
    "no scene may hold more than 4194304)";

INSTANTIATE_TEST_SUITE_P(
    Files, MeshFileRefusal,
    testing::Values(
        Refused{"no_such_file.obj", limit, "", "cannot open file: No such file or directory"},
        Refused{"cube.fbx", limit, "",
                "unknown mesh file extension \".fbx\": twinray reads .obj, .ply, .stl, .gltf and .glb"},
        Refused{"bad_number.obj", limit, "line 3", "\"1x\" is not a number"},
        Refused{"truncated_binary.ply", limit, "face[11]", "the file ends inside this face of 12: truncated"},
        Refused{"points_only.ply", limit, "", "no triangles: the file has 3 vertices and no faces"},
        Refused{"nan_vertex.obj", limit, "line 3", "\"nan\" is not a finite number"},
        Refused{"out_of_range.obj", limit, "line 6",
                "vertex index 9 refers to no vertex: 4 are defined before this line"},
        // Past the limit: OBJ at the face that passes it, PLY and binary STL from the header's counts, before
        // anything is read.
        Refused{"cube.obj", 11, "line 17", "this face brings the triangles to 12" + over_eleven},
        Refused{"cube_ascii.ply", 5, "header",
                "element face declares 6 faces, each at least one triangle: more than the limit of 5 primitives "
                "(about 165 bytes of memory each when rendered; no scene may hold more than 4194304)"},
        Refused{"cube_ascii.ply", 11, "line 24 (face[5])", "this face brings the triangles to 12" + over_eleven},
        Refused{"cube_binary.ply", 11, "header",
                "element face declares 12 faces, each at least one triangle" + over_eleven},
        Refused{"cube_binary.stl", 11, "header", "it declares 12 triangles" + over_eleven},
        Refused{"cube_ascii.stl", 11, "", "its facets number more than 11" + over_eleven}),
    [](const testing::TestParamInfo<Refused>& refused) {
        return test_name(refused.param.file + "_" + std::to_string(refused.param.max_triangles));
    });

TEST(MeshFile, DirectoryAndFifoAreRefused) {
    const fs::path dir = output_dir() / "folder.obj";
    fs::create_directories(dir);
    std::optional<SceneError> error = refusal_of(dir);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->problem(), "cannot read file: it is a directory");
    // Opening a FIFO for reading waits for a writer: refused before anything opens it so.
    const fs::path fifo = output_dir() / "fifo.obj";
    fs::remove(fifo);
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    error = refusal_of(fifo);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->problem(), "cannot read file: it is not a regular file");
}

TEST(MeshFile, BinaryStlOfTheWrongSizeIsRefusedBeforeAssimpReadsIt) {
    std::ifstream in(meshes_dir / "cube_binary.stl", std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const fs::path file = write_file("cut.stl", bytes.substr(0, bytes.size() - 10));
    const std::optional<SceneError> error = refusal_of(file);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->problem(),
              "neither ASCII STL (it does not begin with \"solid\") nor binary STL (its header declares 12 triangles, "
              "which take 84 + 50 x 12 bytes, and the file has 674): truncated, or not an STL file");
}

TEST(MeshFile, PlyIndexOutOfRangeIsRefusedAtItsFace) {
    const fs::path file = write_file("index.ply",
                                     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                     "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
    const std::optional<SceneError> error = refusal_of(file);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->location(), "line 13 (face[0])");
    EXPECT_EQ(error->problem(), "vertex index 3 is out of range: the file has 3 vertices");
}

TEST(MeshFile, PlyNonFiniteCoordinateIsRefusedAtItsVertex) {
    const fs::path file = write_file("inf.ply",
                                     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                     "end_header\n0 0 0\n1 -inf 0\n0 1 0\n3 0 1 2\n");
    const std::optional<SceneError> error = refusal_of(file);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->location(), "line 11 (vertex[1])");
    EXPECT_EQ(error->problem(), "coordinate y is not finite (-inf)");
}

TEST(MeshFile, PlyClaimingMoreThanTheFileHoldsIsRefusedBeforeAllocating) {
    const fs::path file = write_file("claims.ply",
                                     "ply\nformat binary_little_endian 1.0\nelement vertex 4000000\nproperty double x\n"
                                     "property double y\nproperty double z\nelement face 1\n"
                                     "property list uchar int vertex_indices\nend_header\n");
    const std::optional<SceneError> error = refusal_of(file);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->problem(),
              "truncated: the elements the header declares take at least 96000001 bytes, and the file has 0 after "
              "its header");
}

// ---------------------------------------------------------------------------------------------------
// The reader process: whatever it does, twinray gets an error naming the file.

TEST(MeshFileReader, CrashIsAnError) {
    const MeshReader reader{fake_reader("segfault.sh", "kill -SEGV $$"), std::chrono::seconds(30)};
    const std::optional<SceneError> error = refusal_of(meshes_dir / "cube.obj", limit, reader);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->problem(), "the mesh reader crashed on this file (signal 11, Segmentation fault)");
}

TEST(MeshFileReader, AbortIsAnErrorWithItsLastWords) {
    const MeshReader reader{fake_reader("abort.sh", "echo 'free(): double free detected' >&2; kill -ABRT $$"),
                            std::chrono::seconds(30)};
    const std::optional<SceneError> error = refusal_of(meshes_dir / "cube.obj", limit, reader);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->problem(),
              "the mesh reader crashed on this file (signal 6, Aborted): free(): double free detected");
}

TEST(MeshFileReader, HangIsStoppedAtTheTimeLimit) {
    const MeshReader reader{fake_reader("hang.sh", "exec sleep 60"), std::chrono::milliseconds(300)};
    const auto start = std::chrono::steady_clock::now();
    const std::optional<SceneError> error = refusal_of(meshes_dir / "cube.obj", limit, reader);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
    ASSERT_TRUE(error);
    EXPECT_EQ(error->problem(), "the mesh reader took longer than 0.3 s on this file and was stopped");
}

TEST(MeshFileReader, GarbageIsAMalformedResult) {
    const MeshReader reader{fake_reader("garbage.sh", "echo 'a mesh, honestly'"), std::chrono::seconds(30)};
    const std::optional<SceneError> error = refusal_of(meshes_dir / "cube.obj", limit, reader);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->problem(), "the mesh reader sent a malformed result: it does not begin as one does");
}

TEST(MeshFileReader, FailureIsAnError) {
    const MeshReader reader{fake_reader("fails.sh", "echo 'cannot load the mesh library module' >&2; exit 3"),
                            std::chrono::seconds(30)};
    const std::optional<SceneError> error = refusal_of(meshes_dir / "cube.obj", limit, reader);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->problem(),
              "the mesh reader failed on this file (exit status 3): cannot load the mesh library module");
}

TEST(MeshFileReader, MissingReaderIsAnError) {
    const MeshReader reader{output_dir() / "no_such_reader", std::chrono::seconds(30)};
    const std::optional<SceneError> error = refusal_of(meshes_dir / "cube.obj", limit, reader);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->problem(),
              "the mesh reader did not run: cannot start " + reader.program.string() + ": No such file or directory");
}

// A reader's message as the bytes it writes on its standard output.
std::string as_reader_output(const wire::Message& message) {
    const fs::path file = output_dir() / "reader_output.bin";
    const int descriptor = ::open(file.c_str(), O_CREAT | O_TRUNC | O_RDWR | O_CLOEXEC, 0600);
    EXPECT_GE(descriptor, 0);
    EXPECT_TRUE(wire::send(descriptor, message));
    ::close(descriptor);
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(MeshFileReader, ReceivingEndRefusesAZeroNormalThatTheLoaderWouldTurnIntoNaN) {
    wire::Message message;
    MeshData& mesh = message.meshes.emplace_back();
    message.nodes.emplace_back();
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {{0, 1, 2}};
    mesh.normals = {{0, 0, 2}, {0, 0, 0}, {0, 0, 1}};
    mesh.smooth = true;
    try {
        mesh_from_reader_output("model.obj", as_reader_output(message), limit);
        ADD_FAILURE() << "a zero normal from the reader was accepted";
    } catch (const SceneError& error) {
        EXPECT_EQ(error.problem(), "the mesh reader sent a malformed result: a normal of zero length");
    }
    mesh.normals[1] = {0, 0, 1e-300};
    const MeshFileResult received = mesh_from_reader_output("model.obj", as_reader_output(message), limit);
    EXPECT_EQ(only_mesh(received).normals[1].z, 1e-300);
    EXPECT_EQ(only_mesh(received).file, "model.obj");
}

// A reader's meshes and nodes, one of which `spoil` breaks: each refused as a malformed result saying what is wrong.
std::string malformed_problem(void (*spoil)(wire::Message&)) {
    wire::Message message;
    for (int m = 0; m < 2; ++m) {
        MeshData& mesh = message.meshes.emplace_back();
        mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        mesh.triangles = {{0, 1, 2}};
        message.nodes.emplace_back().mesh = static_cast<std::uint32_t>(m);
    }
    spoil(message);
    try {
        mesh_from_reader_output("model.gltf", as_reader_output(message), limit);
    } catch (const SceneError& error) {
        return error.problem();
    }
    return "accepted";
}

TEST(MeshFileReader, ReceivingEndRefusesNodesThatPlaceNoMeshSentOrAreNotFinite) {
    EXPECT_EQ(malformed_problem([](wire::Message& message) { message.nodes[1].mesh = 2; }),
              "the mesh reader sent a malformed result: a node places mesh 2 of 2");
    EXPECT_EQ(malformed_problem([](wire::Message& message) { message.nodes.pop_back(); }),
              "the mesh reader sent a malformed result: a mesh that no node places");
    EXPECT_EQ(malformed_problem([](wire::Message& message) { message.nodes[0].linear.row[2].y = NAN; }),
              "the mesh reader sent a malformed result: a node's matrix is not finite");
    EXPECT_EQ(malformed_problem([](wire::Message& message) { message.nodes.clear(); }),
              "the mesh reader sent a malformed result: 2 meshes of 2 triangles and 6 vertices, placed by 0 nodes");
    EXPECT_EQ(malformed_problem([](wire::Message& message) { message.meshes[1].triangles[0][2] = 3; }),
              "the mesh reader sent a malformed result: mesh 1 triangle 0 has an index out of range");
    EXPECT_EQ(malformed_problem([](wire::Message&) {}), "accepted");
}

// ---------------------------------------------------------------------------------------------------
// Topology.

TEST(MeshTopology, SingleQuadIsOpenWithFourBoundaryEdges) {
    const MeshTopology topology = topology_of(only_mesh(read_mesh_file(meshes_dir / "quad.obj", limit)));
    EXPECT_EQ(topology.boundary_edges, 4U);
    EXPECT_EQ(topology.non_manifold_edges, 0U);
    EXPECT_EQ(topology.inconsistently_wound_edges, 0U);
    EXPECT_FALSE(topology.closed());
}

TEST(MeshTopology, VerticesAtOnePositionAreOneForTheTopology) {
    // The cube with three vertices of its own per triangle, as STL has it, is as closed as the shared one.
    MeshData mesh;
    for (const Triangle& triangle : cube_triangles) {
        const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
        for (const std::uint32_t vertex : triangle) {
            mesh.vertices.push_back(cube_vertices(1)[vertex]);
        }
        mesh.triangles.push_back({first, first + 1, first + 2});
    }
    EXPECT_TRUE(topology_of(mesh).closed());
}

TEST(MeshTopology, FlippedTriangleAndFinAreFound) {
    MeshData mesh;
    mesh.vertices = cube_vertices(1);
    mesh.triangles = cube_triangles;
    std::swap(mesh.triangles[0][1], mesh.triangles[0][2]);  // its three edges now run as its neighbours' do
    EXPECT_EQ(topology_of(mesh).inconsistently_wound_edges, 3U);
    EXPECT_EQ(topology_of(mesh).boundary_edges, 0U);
    mesh.triangles = cube_triangles;
    // A fin inside from the bottom's diagonal (0-2) to the front's (0-5): three triangles on each, and its third
    // edge (2-5) on it alone.
    mesh.triangles.push_back({0, 2, 5});
    const MeshTopology topology = topology_of(mesh);
    EXPECT_EQ(topology.non_manifold_edges, 2U);
    EXPECT_EQ(topology.boundary_edges, 1U);
    EXPECT_FALSE(topology.closed());
}

TEST(MeshTopology, DegenerateTrianglesAreLeftOut) {
    MeshData mesh;
    mesh.vertices = cube_vertices(1);
    mesh.triangles = cube_triangles;
    mesh.triangles.push_back({0, 0, 1});
    EXPECT_TRUE(topology_of(mesh).closed());
}

// ---------------------------------------------------------------------------------------------------
// Real files: Debian's assimp-testmodels (assimp's own test models).

struct RealFile {
    std::string file;  // under /usr/share/assimp/models
    std::size_t vertices;
    std::size_t triangles;
    bool smooth;
    std::array<std::size_t, 3> edges;  // boundary, non-manifold, inconsistently wound
    std::size_t degenerate;
    std::string warning;  // the beginning of one of its warnings, or "" for none
};

void PrintTo(const RealFile& real, std::ostream* out) {
    *out << real.file;
}

class AssimpTestModel : public testing::TestWithParam<RealFile> {};

TEST_P(AssimpTestModel, IsReadWithItsCountsAndTopology) {
    if (!fs::is_directory(testmodels_dir)) {
        GTEST_SKIP() << "Debian's assimp-testmodels is not installed (" << testmodels_dir << "); ci/setup installs it";
    }
    const RealFile& real = GetParam();
    const MeshFileResult result = read_mesh_file(testmodels_dir / real.file, limit);
    EXPECT_EQ(only_mesh(result).vertices.size(), real.vertices);
    EXPECT_EQ(only_mesh(result).triangles.size(), real.triangles);
    EXPECT_EQ(only_mesh(result).smooth, real.smooth);
    const MeshTopology topology = topology_of(only_mesh(result));
    EXPECT_EQ((std::array{topology.boundary_edges, topology.non_manifold_edges, topology.inconsistently_wound_edges}),
              real.edges);
    EXPECT_EQ(only_mesh(result).degenerate.size(), real.degenerate);
    if (real.warning.empty()) {
        EXPECT_TRUE(result.warnings.empty()) << result.warnings[0];
    } else {
        EXPECT_TRUE(std::any_of(result.warnings.begin(), result.warnings.end(),
                                [&real](const std::string& warning) { return warning.starts_with(real.warning); }))
            << "no warning begins with " << real.warning;
    }
}

// The same models in several formats agree: Wuson's 3732 triangles and 412 boundary edges in OBJ, PLY (a vertex per
// corner, welded for the topology) and STL; the spider's 1368 triangles in OBJ and both STLs, whose floats make
// 56 of them degenerate.
INSTANTIATE_TEST_SUITE_P(
    Files, AssimpTestModel,
    testing::Values(
        RealFile{"OBJ/box.obj", 8, 12, false, {0, 0, 0}, 0, "materials are not used: usemtl \"Default\""},
        RealFile{"OBJ/cube_usemtl.obj",
                 24,
                 12,
                 true,
                 {0, 0, 0},
                 0,
                 "materials are not used: mtllib \"cube_usemtl.mtl\"; usemtl \"mtl\", \"mtl2\", \"mtl3\""},
        RealFile{"OBJ/cube_with_vertexcolors.obj", 24, 12, true, {0, 0, 0}, 0, "vertex colours"},
        RealFile{"OBJ/concave_polygon.obj", 64, 64, true, {64, 0, 0}, 0, "materials are not used"},
        RealFile{"OBJ/spider.obj", 918, 1368, false, {72, 0, 10}, 0, "normals (vn) are not used: normal 488"},
        RealFile{"OBJ/WusonOBJ.obj", 2117, 3732, true, {412, 0, 0}, 0, "texture coordinates (vt) are not used"},
        RealFile{"PLY/cube.ply", 8, 12, false, {0, 0, 0}, 0, ""},
        RealFile{"PLY/cube_binary.ply", 8, 12, false, {0, 0, 0}, 0, ""},
        RealFile{"PLY/Wuson.ply", 11184, 3732, true, {412, 0, 0}, 0, "header line 3 is not PLY and was passed over"},
        RealFile{"PLY/float-color.ply", 3, 1, false, {3, 0, 0}, 0, "vertex colours (red, green, blue, alpha)"},
        RealFile{"STL/Spider_ascii.stl", 722, 1368, false, {72, 0, 10}, 56, ""},
        RealFile{"STL/Spider_binary.stl", 722, 1368, false, {72, 0, 10}, 56, ""},
        RealFile{"STL/Wuson.stl", 2117, 3732, false, {412, 0, 0}, 0, ""},
        RealFile{"STL/sphereWithHole.stl", 146, 285, false, {9, 0, 0}, 0, ""},
        RealFile{"STL/triangle_with_two_solids.stl", 6, 2, false, {6, 0, 0}, 0, ""},
        RealFile{"STL/3DSMaxExport.STL", 1042, 2000, false, {0, 16, 0}, 0, ""}),
    [](const testing::TestParamInfo<RealFile>& real) { return test_name(real.param.file); });

TEST(AssimpTestModels, RefusalsNameWhereTheFileIsWrong) {
    if (!fs::is_directory(testmodels_dir)) {
        GTEST_SKIP() << "Debian's assimp-testmodels is not installed (" << testmodels_dir << "); ci/setup installs it";
    }
    // "3.1+e2" is no number (assimp's own reader takes it for 3.1).
    std::optional<SceneError> error = refusal_of(testmodels_dir / "OBJ/number_formats.obj");
    ASSERT_TRUE(error);
    EXPECT_EQ(error->location(), "line 11");
    EXPECT_EQ(error->problem(), "\"3.1+e2\" is not a number");
    error = refusal_of(testmodels_dir / "PLY/points.ply");
    ASSERT_TRUE(error);
    EXPECT_EQ(error->problem(), "no triangles: the file has 4 vertices and no faces");
    error = refusal_of(testmodels_dir / "invalid/malformed.obj");
    ASSERT_TRUE(error);
    EXPECT_EQ(error->location(), "line 23");
    EXPECT_EQ(error->problem(), "vertex index 12 refers to no vertex: 8 are defined before this line");
}

TEST(AssimpTestModels, ConcavePolygonsAreCoveredWithoutOverlap) {
    if (!fs::is_directory(testmodels_dir)) {
        GTEST_SKIP() << "Debian's assimp-testmodels is not installed (" << testmodels_dir << "); ci/setup installs it";
    }
    // Two concave 32-gons (LightWave's test): every triangle faces the way its polygon does, so none overlaps
    // another or leaves the polygon (the fan from the first corner would fold triangles over).
    const MeshData mesh = only_mesh(read_mesh_file(testmodels_dir / "OBJ/concave_polygon.obj", limit));
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& [a, b, c] = mesh.triangles[t];
        const Vec3 normal = cross(mesh.vertices[b] - mesh.vertices[a], mesh.vertices[c] - mesh.vertices[a]);
        EXPECT_GT(dot(normal, mesh.normals[a]), 0) << "triangle " << t << " is folded over";
    }
}

// ---------------------------------------------------------------------------------------------------
// glTF: a file written here, then assimp-testmodels' own.

TEST(GltfFile, AMeshThreeNodesPlaceIsSentOnceWithEachNodesWorldTransform) {
    const fs::path file = write_file("three_gems.gltf", test::octahedron_gltf(test::three_gems_nodes, "[0]"));
    const MeshFileResult result = read_mesh_file(file, limit);
    ASSERT_EQ(result.meshes.size(), 1U);
    const MeshData& gem = result.meshes[0];
    ASSERT_EQ(gem.vertices.size(), 6U);
    EXPECT_EQ(gem.vertices[0], (Vec3{0.5, 0, 0}));
    EXPECT_EQ(gem.vertices[5], (Vec3{0, 0, -0.5}));
    EXPECT_EQ(gem.triangles,
              (std::vector<Triangle>{
                  {0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}}));
    EXPECT_FALSE(gem.smooth);
    EXPECT_TRUE(result.warnings.empty()) << result.warnings[0];
    ASSERT_EQ(result.nodes.size(), 3U);
    const auto rows = [](const MeshNode& node) {
        return std::array{node.linear.row[0], node.linear.row[1], node.linear.row[2]};
    };
    EXPECT_EQ(result.nodes[0].name, "Left");
    EXPECT_EQ(rows(result.nodes[0]), (std::array<Vec3, 3>{{{0.5, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5}}}));
    EXPECT_EQ(result.nodes[0].translation, (Vec3{-0.75, 0.625, -0.25}));
    EXPECT_EQ(result.nodes[1].name, "Big");
    EXPECT_EQ(rows(result.nodes[1]), (std::array<Vec3, 3>{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}));
    EXPECT_EQ(result.nodes[1].translation, (Vec3{0.5, 0.75, -1}));
    EXPECT_EQ(result.nodes[2].name, "Turned");
    EXPECT_EQ(rows(result.nodes[2]), (std::array<Vec3, 3>{{{0, 0, 0.5}, {0, 0.5, 0}, {-0.5, 0, 0}}}));
    EXPECT_EQ(result.nodes[2].translation, (Vec3{0, 0.125, 0.5}));
    for (const MeshNode& node : result.nodes) {
        EXPECT_EQ(node.mesh, 0U);
    }
}

TEST(GltfFile, TrianglesOrNodesPastTheLimitAreRefusedBeforeTheyAreSent) {
    // The octahedron's 8 triangles placed by ten nodes: a limit of 7 refuses the triangles, one of 9 the tenth node
    // (each node will be a primitive of the scene at least).
    std::string nodes = R"([{"name": "Row", "children": [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]})";
    for (int k = 1; k <= 10; ++k) {
        nodes += R"(, {"name": "Gem )" + std::to_string(k) + R"(", "mesh": 0, "translation": [)" + std::to_string(k) +
                 ", 0, 0]}";
    }
    const fs::path file = write_file("ten_gems.gltf", test::octahedron_gltf(nodes + "]", "[0]"));
    std::optional<SceneError> error = refusal_of(file, 7);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->location(), "mesh \"gem\"");
    EXPECT_EQ(error->problem(),
              "it brings the triangles to 8: more than the limit of 7 primitives (about 165 bytes of memory each when "
              "rendered; no scene may hold more than 4194304)");
    error = refusal_of(file, 9);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->location(), "node \"Gem 10\"");
    EXPECT_EQ(error->problem(),
              "its nodes that carry meshes number more than 9: more than the limit of 9 primitives (about 165 bytes "
              "of memory each when rendered; no scene may hold more than 4194304)");
    EXPECT_EQ(read_mesh_file(file, 10).nodes.size(), 10U);
}

TEST(GltfFile, AWorldTransformThatOverflowsIsRefusedNamingTheNode) {
    // Each node scales by 1e38, a float's range: nine of them pass a double's.
    std::string nodes = "[";
    for (int k = 0; k < 9; ++k) {
        nodes += (k == 0 ? "" : ", ") + std::string(R"({"name": "Level )") + std::to_string(k) +
                 R"(", "scale": [1e38, 1e38, 1e38], )" +
                 (k == 8 ? std::string(R"("mesh": 0})") : R"("children": [)" + std::to_string(k + 1) + "]}");
    }
    const fs::path file = write_file("deep.gltf", test::octahedron_gltf(nodes + "]", "[0]"));
    const std::optional<SceneError> error = refusal_of(file);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->location(), "node \"Level 8\"");
    EXPECT_EQ(error->problem(), "its world transform (its matrix after its ancestors') overflows: not all finite");
}

TEST(GltfFile, ANodeMatrixThatIsNotAffineIsRefusedNamingTheNode) {
    const fs::path file = write_file(
        "projective.gltf",
        test::octahedron_gltf(
            R"([{"name": "Lens", "mesh": 0, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.5, 0, 0, 0, 1]}])", "[0]"));
    const std::optional<SceneError> error = refusal_of(file);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->location(), "node \"Lens\"");
    EXPECT_EQ(error->problem(), "its matrix is not affine: its last row is 0 0 0.5 1, not 0 0 0 1");
}

// The octahedron's .gltf as a .glb: its JSON chunk (padded with spaces to four bytes, as the format asks) without
// the buffer's data URI, and the buffer as its BIN chunk.
std::string glb_of(std::string json) {
    const std::size_t uri = json.find(R"(, "uri": ")");
    json.erase(uri, json.find('"', uri + 10) + 1 - uri);
    json.append((4 - json.size() % 4) % 4, ' ');
    std::string buffer(reinterpret_cast<const char*>(test::octahedron_vertices.data()),
                       sizeof test::octahedron_vertices);
    buffer.append(reinterpret_cast<const char*>(test::octahedron_triangles.data()), sizeof test::octahedron_triangles);
    const auto word = [](std::uint32_t value) { return std::string(reinterpret_cast<const char*>(&value), 4); };
    return "glTF" + word(2) + word(static_cast<std::uint32_t>(28 + json.size() + buffer.size())) +
           word(static_cast<std::uint32_t>(json.size())) + "JSON" + json +
           word(static_cast<std::uint32_t>(buffer.size())) + std::string("BIN\0", 4) + buffer;
}

// assimp reads a file as if an extension it lacks were absent: a required one that may change the meshes is refused
// (Draco's accessors have no data of their own), in a .gltf and in a .glb's JSON chunk; one on materials is not.
TEST(GltfFile, ARequiredExtensionThatMayChangeTheMeshesIsRefusedAndOneOnMaterialsIsNot) {
    const std::string gltf = test::octahedron_gltf(R"([{"name": "Gem", "mesh": 0}])", "[0]");
    const auto requiring = [&gltf](const std::string& extension) {
        return R"({"extensionsRequired": [")" + extension + R"("], "extensionsUsed": [")" + extension + R"("],)" +
               gltf.substr(1);
    };
    for (const auto& [name, text] :
         {std::pair<std::string, std::string>{"meshopt.gltf", requiring("EXT_meshopt_compression")},
          {"meshopt.glb", glb_of(requiring("EXT_meshopt_compression"))}}) {
        const std::optional<SceneError> error = refusal_of(write_file(name, text));
        ASSERT_TRUE(error) << name << " read, not refused";
        EXPECT_EQ(error->problem(),
                  "it requires the extension \"EXT_meshopt_compression\", which assimp 5.2 does not "
                  "read (it would read the meshes as if it were absent); required extensions "
                  "allowed: KHR_materials_*, KHR_texture_*, KHR_lights_punctual")
            << name;
    }
    for (const auto& [name, text] :
         {std::pair<std::string, std::string>{"unlit.gltf", requiring("KHR_materials_unlit")},
          {"unlit.glb", glb_of(requiring("KHR_materials_unlit"))}}) {
        EXPECT_EQ(only_mesh(read_mesh_file(write_file(name, text), limit)).triangles.size(), 8u) << name;
    }
}

// assimp allocates and clears what a .glb's header and chunks say before it reads them: lengths past the file's end
// are refused first (a fuzzed file of 91 bytes claimed a 1.2 GB JSON chunk).
TEST(GltfFile, AGlbWhoseLengthsRunPastItsEndIsRefusedBeforeAssimpReadsIt) {
    const std::string glb = glb_of(test::octahedron_gltf(R"([{"name": "Gem", "mesh": 0}])", "[0]"));
    std::string long_chunk = glb;
    const std::uint32_t claimed = 0x4500029e;
    std::memcpy(long_chunk.data() + 12, &claimed, sizeof claimed);
    std::optional<SceneError> error = refusal_of(write_file("long_chunk.glb", long_chunk));
    ASSERT_TRUE(error) << "read, not refused";
    EXPECT_EQ(error->location(), "chunk at byte 12");
    EXPECT_EQ(error->problem(),
              "its length, 1157628574 bytes, runs past the file's end (" + std::to_string(glb.size()) + " bytes)");
    error = refusal_of(write_file("truncated.glb", glb.substr(0, glb.size() - 4)));
    ASSERT_TRUE(error) << "read, not refused";
    EXPECT_EQ(error->problem(), "its header says " + std::to_string(glb.size()) + " bytes, more than the file's " +
                                    std::to_string(glb.size() - 4));
    error = refusal_of(write_file("header_cut.glb", glb.substr(0, 10)));
    ASSERT_TRUE(error) << "read, not refused";
    EXPECT_EQ(error->problem(),
              "it begins as a binary glTF (\"glTF\") but is 10 bytes long, shorter than the 12-byte header");
}

struct RealGltf {
    std::string file;  // under /usr/share/assimp/models/glTF2
    std::size_t meshes;
    std::size_t triangles;
    std::size_t nodes;
    bool smooth;
    std::vector<std::string> warnings;  // the beginning of each
};

void PrintTo(const RealGltf& real, std::ostream* out) {
    *out << real.file;
}

class AssimpGltfModel : public testing::TestWithParam<RealGltf> {};

TEST_P(AssimpGltfModel, GivesItsMeshesOnceAndANodeForEachPlacement) {
    if (!fs::is_directory(testmodels_dir)) {
        GTEST_SKIP() << "Debian's assimp-testmodels is not installed (" << testmodels_dir << "); ci/setup installs it";
    }
    const RealGltf& real = GetParam();
    const MeshFileResult result = read_mesh_file(testmodels_dir / "glTF2" / real.file, limit);
    std::size_t triangles = 0;
    for (const MeshData& mesh : result.meshes) {
        triangles += mesh.triangles.size();
        EXPECT_EQ(mesh.smooth, real.smooth);
    }
    EXPECT_EQ(result.meshes.size(), real.meshes);
    EXPECT_EQ(triangles, real.triangles);
    EXPECT_EQ(result.nodes.size(), real.nodes);
    ASSERT_EQ(result.warnings.size(), real.warnings.size());
    for (std::size_t w = 0; w < real.warnings.size(); ++w) {
        EXPECT_TRUE(result.warnings[w].starts_with(real.warnings[w])) << result.warnings[w];
    }
}

// The engine: 29 meshes, 20 of them placed more than once (a bolt by 20 nodes), 67 nodes in all.
INSTANTIATE_TEST_SUITE_P(
    Files, AssimpGltfModel,
    testing::Values(RealGltf{"2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
                             29,
                             75730,
                             67,
                             true,
                             {"materials (and their textures) are not used: \"Material_16\"",
                              "1 cameras are not used"}},
                    RealGltf{"BoxTextured-glTF/BoxTextured.gltf",
                             1,
                             12,
                             1,
                             true,
                             {"materials (and their textures) are not used: \"Texture\"",
                              "texture coordinates are not used: mesh \"Mesh\""}},
                    RealGltf{"BoxBadNormals-glTF-Binary/BoxBadNormals.glb",
                             1,
                             12,
                             1,
                             false,
                             {"normals of mesh \"Mesh\" are not used: vertex 0's has no direction",
                              "materials (and their textures) are not used: \"Red\""}},
                    RealGltf{"simple_skin/simple_skin.gltf",
                             1,
                             8,
                             1,
                             false,
                             {"skins are not used (the meshes are drawn as the nodes place them): mesh",
                              "1 animations are not used"}},
                    RealGltf{"glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
                             1,
                             12,
                             1,
                             true,
                             {"materials (and their textures) are not used: \"Material\"",
                              "morph targets are not used: mesh \"Cube\"", "1 animations are not used"}}),
    [](const testing::TestParamInfo<RealGltf>& real) { return test_name(real.param.file); });

TEST(AssimpGltfModels, ABoxTurnedByItsNodeGivesTheTurnExactlyAndReadsAsGlbAndInAnyCase) {
    if (!fs::is_directory(testmodels_dir)) {
        GTEST_SKIP() << "Debian's assimp-testmodels is not installed (" << testmodels_dir << "); ci/setup installs it";
    }
    const fs::path file = output_dir() / "BOX.GLB";
    fs::copy_file(testmodels_dir / "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", file,
                  fs::copy_options::overwrite_existing);
    const MeshFileResult result = read_mesh_file(file, limit);
    ASSERT_EQ(result.nodes.size(), 1U);
    // The file's node matrix turns -90° about x.
    const MeshNode& node = result.nodes[0];
    EXPECT_EQ(node.linear.row[0], (Vec3{1, 0, 0}));
    EXPECT_EQ(node.linear.row[1], (Vec3{0, 0, 1}));
    EXPECT_EQ(node.linear.row[2], (Vec3{0, -1, 0}));
    EXPECT_EQ(node.translation, (Vec3{0, 0, 0}));
    ASSERT_EQ(result.meshes.size(), 1U);
    EXPECT_EQ(result.meshes[0].vertices.size(), 24U);
    EXPECT_TRUE(std::any_of(result.warnings.begin(), result.warnings.end(),
                            [](const std::string& warning) { return warning == "1 embedded textures are not used"; }));
}

struct RefusedGltf {
    std::string file;  // under /usr/share/assimp/models/glTF2
    std::string location;
    std::string problem;
};

void PrintTo(const RefusedGltf& refused, std::ostream* out) {
    *out << refused.file;
}

class AssimpGltfRefusal : public testing::TestWithParam<RefusedGltf> {};

TEST_P(AssimpGltfRefusal, NamesTheFileWhereAndWhat) {
    if (!fs::is_directory(testmodels_dir)) {
        GTEST_SKIP() << "Debian's assimp-testmodels is not installed (" << testmodels_dir << "); ci/setup installs it";
    }
    const RefusedGltf& refused = GetParam();
    const std::optional<SceneError> error = refusal_of(testmodels_dir / "glTF2" / refused.file);
    ASSERT_TRUE(error) << "read, not refused";
    EXPECT_EQ(error->location(), refused.location);
    EXPECT_EQ(error->problem(), refused.problem);
}

INSTANTIATE_TEST_SUITE_P(
    Files, AssimpGltfRefusal,
    testing::Values(RefusedGltf{"RecursiveNodes/RecursiveNodes.gltf", "",
                                "assimp: GLTF: Object at index 0 in array \"nodes\" has recursive reference to itself"},
                    RefusedGltf{
                        "IndexOutOfRange/IndexOutOfRange.gltf", "",
                        "a triangle's vertex index is out of range (assimp dropped the triangles that have one)"},
                    RefusedGltf{"IndexOutOfRange/AllIndicesOutOfRange.gltf", "", "assimp: Mesh \"Mesh\" has no faces"},
                    RefusedGltf{"MissingBin/BoxTextured.gltf", "",
                                "assimp: GLTF: could not open referenced file \"BoxTextured0.bin\""},
                    RefusedGltf{"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "mesh \"Mesh\"",
                                "vertex 0 is not finite (-inf -0.5 0.5)"},
                    RefusedGltf{"TestNoRootNode/SceneWithoutNodes.gltf", "",
                                "no triangles: the file's 0 mesh primitives hold none"},
                    RefusedGltf{"TestNoRootNode/NoScene.gltf", "", "assimp: GLTF: No scene"},
                    RefusedGltf{"glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_00.gltf", "",
                                "no triangles: the file's 1 mesh primitives hold none"},
                    RefusedGltf{"draco/2CylinderEngine.gltf", "",
                                "it requires the extension \"KHR_draco_mesh_compression\", which assimp 5.2 does not "
                                "read (it would read the meshes as if it were absent); required extensions allowed: "
                                "KHR_materials_*, KHR_texture_*, KHR_lights_punctual"}),
    [](const testing::TestParamInfo<RefusedGltf>& refused) { return test_name(refused.param.file); });

// ---------------------------------------------------------------------------------------------------
// The measurement of docs/performance.md ("Mesh files: the library"), run by ci/measure-mesh-files on each of
// its files: TWINRAY_MESH_FILE=F mesh_file_test --gtest_also_run_disabled_tests --gtest_filter='*MeasureOneFile'

TEST(MeshFileMeasurement, DISABLED_MeasureOneFile) {
    const char* file = std::getenv("TWINRAY_MESH_FILE");
    if (!file) {
        GTEST_SKIP() << "TWINRAY_MESH_FILE names no file";
    }
    const auto start = std::chrono::steady_clock::now();
    const MeshFileResult result = read_mesh_file(file, limit);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    rusage twinray_side{};
    rusage reader_side{};
    getrusage(RUSAGE_SELF, &twinray_side);
    getrusage(RUSAGE_CHILDREN, &reader_side);
    const auto triangles = static_cast<double>(only_mesh(result).triangles.size());
    std::cout << file << ": " << only_mesh(result).triangles.size() << " triangles, "
              << only_mesh(result).vertices.size() << " vertices in " << seconds << " s; peak RSS "
              << twinray_side.ru_maxrss / 1024 << " MiB here + " << reader_side.ru_maxrss / 1024
              << " MiB in the reader = "
              << 1024.0 * static_cast<double>(twinray_side.ru_maxrss + reader_side.ru_maxrss) / triangles
              << " bytes per triangle\n";
}

}  // namespace
}  // namespace twinray::scene
