// glTF 2 files written by the tests: one mesh, an octahedron of half-width 0.5 (instance_test's inline one), its
// buffer a base64 data URI in the file, placed by the nodes a test gives.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace twinray::test {

inline std::string base64(const std::string& bytes) {
    static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string text;
    for (std::size_t at = 0; at < bytes.size(); at += 3) {
        const std::size_t left = bytes.size() - at;
        std::uint32_t group = static_cast<std::uint8_t>(bytes[at]) << 16;
        group |= left > 1 ? static_cast<std::uint8_t>(bytes[at + 1]) << 8 : 0;
        group |= left > 2 ? static_cast<std::uint8_t>(bytes[at + 2]) : 0;
        text += digits[group >> 18 & 63];
        text += digits[group >> 12 & 63];
        text += left > 1 ? digits[group >> 6 & 63] : '=';
        text += left > 2 ? digits[group & 63] : '=';
    }
    return text;
}

// The octahedron's vertices and triangles, wound outward.
constexpr std::array<std::array<float, 3>, 6> octahedron_vertices{
    {{0.5F, 0, 0}, {-0.5F, 0, 0}, {0, 0.5F, 0}, {0, -0.5F, 0}, {0, 0, 0.5F}, {0, 0, -0.5F}}};
constexpr std::array<std::array<std::uint16_t, 3>, 8> octahedron_triangles{
    {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}}};

// A .gltf whose scene has the root nodes `roots` (a JSON array of indices) of `nodes` (the JSON array of nodes);
// mesh 0 is the octahedron.
inline std::string octahedron_gltf(const std::string& nodes, const std::string& roots) {
    std::string buffer(reinterpret_cast<const char*>(octahedron_vertices.data()), sizeof octahedron_vertices);
    buffer.append(reinterpret_cast<const char*>(octahedron_triangles.data()), sizeof octahedron_triangles);
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": )" + roots + R"(}],
  "nodes": )" +
           nodes +
           R"(,
  "meshes": [{"name": "gem", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "buffers": [{"byteLength": 120, "uri": "data:application/octet-stream;base64,)" +
           base64(buffer) + R"("}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 72, "target": 34962},
                  {"buffer": 0, "byteOffset": 72, "byteLength": 48, "target": 34963}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
                 "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]},
                {"bufferView": 1, "componentType": 5123, "count": 24, "type": "SCALAR"}]})";
}

// Three nodes placing the octahedron under a parent "Gems" that halves them and lifts them by 0.5 (glTF applies
// scale, then rotation, then translation; "Turned"'s matrix, column-major, turns 90° about y and moves). Their world
// transforms, exact in float and double: Left 0.5·p + (-0.75, 0.625, -0.25); Big p + (0.5, 0.75, -1); Turned
// (0.5·z, 0.5·y, -0.5·x) + (0, 0.125, 0.5).
inline const std::string three_gems_nodes = R"([
  {"name": "Gems", "translation": [0, 0.5, 0], "scale": [0.5, 0.5, 0.5], "children": [1, 2, 3]},
  {"name": "Left", "mesh": 0, "translation": [-1.5, 0.25, -0.5]},
  {"name": "Big", "mesh": 0, "scale": [2, 2, 2], "translation": [1, 0.5, -2]},
  {"name": "Turned", "mesh": 0, "matrix": [0, 0, -1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, -0.75, 1, 1]}])";

}  // namespace twinray::test
