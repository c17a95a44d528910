// A twinray-scene/1 file written as it is produced, for scenes too large to build as a JSON tree first
// (`twinray generate` writes a million primitives this way in about a second, holding a mebibyte).
// Every coordinate is put on a decimal grid and printed as the shortest text that reads back as the
// same double, so a file is byte for byte the same on every machine and standard library, and short.
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace twinray::cli {

using Vec3 = scene::Vec3;

// Receives the text in order, in pieces of about a mebibyte.
using TextSink = std::function<void(std::string_view)>;

// A mesh's lists, each written by the function it is given being called once per element, in order, so
// that a mesh of a million triangles streams like any other object instead of being held first. A list may be
// asked for more than once (a mesh file counts before it writes) and gives the same elements each time.
using PointEmitter = std::function<void(Vec3)>;
using TriangleEmitter = std::function<void(int, int, int)>;
struct MeshLists {
    std::function<void(const PointEmitter&)> vertices;
    // Indices into the vertices, counter-clockwise seen from the front.
    std::function<void(const TriangleEmitter&)> triangles;
    // One unit normal per vertex, in the vertices' order, for a smooth mesh; empty for a flat one.
    std::function<void(const PointEmitter&)> normals;
};

// The shortest decimal text that reads back as `value` (fixed notation, never an exponent).
void append_shortest(std::string& text, double value);

struct MeshCounts {
    std::int64_t vertices = 0, triangles = 0;
};
// Writes a mesh's lists (already on the writer's grid) to a file of its own and returns the name the scene
// refers to it by, relative to the scene file.
using MeshFileSink = std::function<std::string(const MeshLists&, MeshCounts)>;

// Where a generated scene goes: its text, and its meshes to files of their own where `mesh_file` is set
// (else inline, as lists in the text).
struct SceneSink {
    TextSink text;
    MeshFileSink mesh_file;
};

class SceneTextWriter {
public:
    // Coordinates and sizes are rounded to multiples of 10^-decimals (0..9): choose it so that the
    // smallest feature spans a thousand steps or more.
    SceneTextWriter(SceneSink sink, int decimals);

    // Everything but the shapes and the objects, from `header`: image, camera, background, ambient light, depth,
    // its named materials (not the built-in default, materials[0]) and lights. The shapes follow (shape_mesh), then
    // the objects, whose list the first object opens.
    void begin(const scene::Scene& header);
    // Closes the objects list and the document, and hands the rest of the text to the sink.
    void end();

    // `material` indexes the header's materials; 0 writes no material key (the CSG node's, or the default).
    void plane(Vec3 normal, double offset, int material);
    void sphere(Vec3 center, double radius, int material = 0);
    void cylinder(Vec3 base, Vec3 cap, double radius, int material = 0);
    void box(Vec3 min, Vec3 max, int material = 0);
    // One leaf, at the top level only (a mesh is never a CSG child): inline, one list element per line, or as
    // `"file"` (SceneSink::mesh_file) with the same doubles. Normals are put on the coordinates' grid too, so
    // their lengths are within a grid step of 1.
    void mesh(const MeshLists& lists, int material);
    // A mesh shape named `name` for instances to place, its `material` (0: none, each instance's applies); before
    // the first object. Its triangles count once, and it is no primitive of its own.
    void shape_mesh(std::string_view name, const MeshLists& lists, int material);
    // Where an instance stands: turned about the vertical axis, scaled evenly, then moved.
    struct Placement {
        double turn_deg;
        double scale;
        Vec3 position;
    };
    // One leaf, at the top level: shape `shape` placed.
    void instance(std::string_view shape, const Placement& placement, int material);
    // A union, intersection or difference: its children are the objects written until end_csg().
    void begin_csg(std::string_view operation, int material);
    void end_csg();

    // Primitives (leaves, a mesh one of them) and triangles of meshes written so far.
    std::int64_t primitives() const { return primitives_; }
    std::int64_t triangles() const { return triangles_; }

private:
    enum class Section { header, shapes, objects };

    void open_objects();
    void begin_object(std::string_view type);
    void open_object(std::string_view type);
    void mesh_object(const MeshLists& lists, int material);
    void material_key(int material);
    void end_object(int material);
    void flush_if_full();
    void begin_mesh_list(std::string_view name);
    void next_mesh_list_element(std::int64_t& count);
    void end_mesh_list(std::int64_t count);
    double on_grid(double value) const;
    Vec3 on_grid(Vec3 value) const;
    MeshCounts counted(const MeshLists& lists) const;
    void mesh_file(const MeshLists& lists);
    void number(double value);
    void vector(Vec3 value);
    void integer(int value);
    void key(std::string_view name);

    SceneSink sink_;
    double grid_scale_;  // 10^decimals, exactly
    std::string text_;
    std::vector<std::string> material_names_;
    // One entry per open list of objects (the top level, then each open CSG node's children): whether
    // an element has been written to it, so the next one starts with a comma.
    std::vector<bool> list_has_elements_;
    Section section_ = Section::header;
    std::int64_t primitives_ = 0;
    std::int64_t triangles_ = 0;
};

}  // namespace twinray::cli
