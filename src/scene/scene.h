// The scene model: what a twinray-scene/1 file says, validated and resolved, in double precision.
// Both tracers read this and nothing else of each other (see ../shared contract, docs/scene-format.md).
#pragma once

#include "math/transform.h"
#include "math/type_list.h"
#include "math/vec3.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace twinray::scene {

// Plain data in double: each tracer converts to its own precision.
using Vec3 = math::Vec3<double>;

struct Material {
    Vec3 color{1, 1, 1};
    double ambient = 0.1;
    double diffuse = 0.6;
    double phong = 0;
    double phong_size = 40;
    double reflection = 0;
    double transmission = 0;
    double ior = 1;
};

struct Camera {
    Vec3 eye{};
    Vec3 look_at{};
    Vec3 up{0, 1, 0};
    double fov_deg = 50;  // horizontal field of view
};

struct Light {
    Vec3 position{};
    Vec3 color{1, 1, 1};
};

// The surface n·p = offset with n of unit length; the inside is n·p < offset.
struct Plane {
    Vec3 normal{};
    double offset = 0;
};

struct Sphere {
    Vec3 center{};
    double radius = 0;
};

// Solid, closed, flat caps at base and cap.
struct Cylinder {
    Vec3 base{};
    Vec3 cap{};
    double radius = 0;
};

struct Box {
    Vec3 min{};
    Vec3 max{};
};

// Object space to world: p ↦ L·p + t, L invertible and well conditioned (the loader's limit,
// max_transform_condition), L⁻¹ beside it.
using Transform = math::Transform<double>;

// κ(L) = ‖L‖_F·‖L⁻¹‖_F, at most this: a float ray carried into object space and its hit carried back lose up
// to κ·u of the object's size each way (docs/numerics.md, "Transforms"), 0.6 % at the limit. An eccentricity
// of 1e4 (κ ≈ 1.4e4) passes; a uniform scale, however small, has κ = 3.
constexpr double max_transform_condition = 1e5;

// A primitive in its own space, placed by a transform that no primitive of its kind can express: a sphere
// scaled unevenly (an ellipsoid), a cylinder scaled across its axis, a box turned off the axes. Every other
// transform the loader applies to the primitive itself, in double (docs/scene-format.md, "Transforms"), so
// both tracers see a plain primitive and pay nothing for it.
// Held apart, shared by copies: every Object stays the size of the largest plain primitive, so scenes without
// transforms hold no more per primitive than before.
template <typename S>
class Transformed {
public:
    Transformed(const S& shape, const Transform& to_world)
        : placed_(std::make_shared<const Placed>(Placed{shape, to_world})) {}

    const S& shape() const { return placed_->shape; }
    const Transform& to_world() const { return placed_->to_world; }

private:
    struct Placed {
        S shape;
        Transform to_world;
    };
    std::shared_ptr<const Placed> placed_;
};

enum class CsgOp { union_, intersection, difference };

struct Object;

// `difference` is children[0] minus all the others.
struct Csg {
    CsgOp op = CsgOp::union_;
    std::vector<Object> children;
};

// The one list of primitive types, in the order every per-type loop visits them. Each dispatch on a
// primitive's type — both tracers' compilation and kernels, numerics, accuracy, the exporter — is generated
// from it; docs/adding-a-primitive.md lists what a new entry needs.
using PrimitiveTypes =
    math::TypeList<Plane, Sphere, Cylinder, Box, Transformed<Sphere>, Transformed<Cylinder>, Transformed<Box>>;

template <typename S>
constexpr bool is_primitive = PrimitiveTypes::contains<S>;

// A primitive, or a CSG operation on objects.
using Shape = PrimitiveTypes::append<Csg>::apply<std::variant>;

struct Object {
    Shape shape;
    // Only meaningful for primitives (leaves): index into Scene::materials, with CSG inheritance
    // already applied (own material, else nearest ancestor's, else the built-in default, index 0).
    int material = 0;
    // Only meaningful for primitives: index into Scene::leaf_paths; leaves are numbered in document
    // order, so a smaller leaf index means "earlier in objects" (the tie-break rule).
    int leaf = -1;
};

// A triangle mesh's shared data: vertices in double as the scene file gives them (a file's values as its
// reader rounds them, docs/scene-format.md), triangles as three vertex indices, counter-clockwise seen from
// the front. Degenerate triangles (a repeated index, or three collinear vertices) are kept, so that indices
// stay those of the file, and listed in `degenerate`: neither tracer ever reports a hit on one.
struct MeshData {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<Vec3> normals;  // empty, or one unit normal per vertex: shading normals when `smooth`
    bool smooth = false;
    std::vector<std::uint32_t> degenerate;  // triangle indices, ascending
    std::string file;                       // the file it was read from, or empty for an inline mesh
};

// A mesh is one leaf (one material, one path in leaf_paths); a hit on it names the leaf and the triangle.
// Meshes are surfaces, not solids: they are never CSG children, and a ray crossing a mesh enters where it
// meets a triangle's front (its geometric normal facing the ray) and leaves where it meets a back.
// Which shape an instance places and where, x ↦ L·x + t. L's inverse is not held but found where it is needed, as the
// loader finds it (math::inverse_of): 72 bytes an instance, 72 MB at a million instances.
struct Placement {
    math::Matrix3<double> linear;
    Vec3 translation;
    int shape;  // index into Scene::mesh_shapes, or for a SolidInstance into Scene::solid_shapes

    Transform transform() const { return {linear, math::inverse_of(linear), translation}; }
};

struct Mesh {
    std::shared_ptr<const MeshData> data;
    int material = 0;
    int leaf = -1;
    // An instance's (docs/scene-format.md, "Shapes and instances"): `data` is its shape's, in the shape's own space
    // and shared by every instance of it, and this places it in the world. Empty for a mesh written in `objects`,
    // whose vertices are world coordinates.
    std::optional<Placement> placement;
};

// A mesh declared once in `shapes`, or a mesh of a glTF file at the top level of `objects`, placed by instances: its
// vertices in its own space. `material`: the one it names, which every instance keeps; -1 where it names none, so
// that each instance's applies.
struct MeshShape {
    std::string name;  // what a hit on an instance names besides the instance: "shapes.tree", "truck.gltf mesh 2"
    std::shared_ptr<const MeshData> data;
    int material = -1;
    bool name_begins_with_file = false;  // a glTF file's mesh, named after the file
};

// Every leaf's path: a top-level element's, "objects[k]" as the loader writes it, in 4 bytes (k alone), any other in
// a block of text (its length, then its bytes; the 4 bytes its place there). A million instances' paths take 4 MB
// where a std::string each took 32.
class LeafPaths {
public:
    void reserve(std::size_t leaves) { entries_.reserve(leaves); }
    void push_back(std::string_view path);
    void clear();
    std::size_t size() const { return entries_.size(); }
    bool empty() const { return entries_.empty(); }
    std::string operator[](std::size_t leaf) const;
    std::string at(std::size_t leaf) const;  // throws std::out_of_range past the last leaf
    std::string front() const { return (*this)[0]; }
    std::string back() const { return (*this)[entries_.size() - 1]; }
    bool operator==(const std::vector<std::string>& paths) const;

private:
    static constexpr std::uint32_t element_flag = std::uint32_t{1} << 31;
    std::string text_;
    std::vector<std::uint32_t> entries_;  // element_flag | k, or the path's place in text_
};

// A shape of `shapes` that holds several primitives (a CSG tree), read once in its own space for the instances that
// place it at the top level of `objects` (an instance inside a CSG tree reads its shape where it stands). Its
// primitives are its parts, numbered from 0 in document order (Object::leaf): a hit on an instance names the instance's
// leaf and the part. A part's material is -1 where neither it nor a CSG ancestor in the shape names one, so that the
// instance's applies.
struct SolidShape {
    std::string name;  // "shapes.cup"
    Object tree;
    LeafPaths part_paths;  // "shapes.cup.children[1]"
    std::vector<int> part_materials;
};

// An instance of a solid shape: one leaf, counted one towards the primitive limit (its shape's parts count once).
// `material`: where a part names none.
struct SolidInstance {
    Placement placement;
    int material = 0;
    int leaf = -1;

    int material_of(const SolidShape& shape, int part) const {
        const int own = shape.part_materials[static_cast<std::size_t>(part)];
        return own >= 0 ? own : material;
    }
};

struct Scene {
    int width = 320;
    int height = 240;
    Camera camera;
    Vec3 background{0, 0, 0};
    Vec3 ambient_light{1, 1, 1};
    int max_depth = 5;
    // A secondary ray whose weight is below this is not traced (POV-Ray's adc_bailout); 0 traces every
    // ray. Without it, the proven cutoff of scene/depth_control.h decides (docs/reference-tracer.md).
    std::optional<double> min_weight;
    // materials[0] is the built-in default; named materials follow, in file order.
    std::vector<Material> materials{Material{}};
    std::vector<std::string> material_names{"(default)"};
    std::vector<Light> lights;
    std::vector<Object> objects;
    // The meshes among `objects`' elements and the instances of mesh shapes, in file order; each has its leaf
    // number like any primitive.
    std::vector<Mesh> meshes;
    // The mesh shapes that instances place (Mesh::shape): each counted towards the primitive limit once.
    std::vector<MeshShape> mesh_shapes;
    // The solid shapes top-level instances place, each counted once, and those instances, in file order.
    std::vector<SolidShape> solid_shapes;
    std::vector<SolidInstance> solid_instances;
    // The stable id of every primitive: its index path in the file, e.g. "objects[4].children[1]".
    LeafPaths leaf_paths;

    bool has_csg() const;  // solid instances included
    bool has_meshes() const { return !meshes.empty(); }
    bool has_instances() const { return !mesh_shapes.empty(); }
    // What the primitive limit counts: every leaf but a mesh, each of a mesh's triangles, an instance of a mesh
    // shape or of a solid shape once, and the triangles or parts of each shape once.
    std::size_t primitive_count() const;
    bool has_transparency() const;
    bool has_reflection() const;
    // On an instance of a solid shape, its `part`'s.
    const Material& material_of_leaf(int leaf, int part = -1) const {
        return materials[static_cast<std::size_t>(material_of(leaf, part))];
    }
    // The mesh or instance whose leaf this is, or null (meshes are in leaf order, as the loader reads them).
    const Mesh* mesh_of_leaf(int leaf) const;
    // The instance of a solid shape whose leaf this is, or null.
    const SolidInstance* solid_instance_of_leaf(int leaf) const;
    // The material of what a hit names: a leaf's, or on an instance of a solid shape its `part`'s.
    int material_of(int leaf, int part) const;
    // What a hit names: the leaf's path, and for an instance of a mesh shape the shape it places,
    // "objects[4] (shapes.tree)", "objects[3] node \"Wheel\" (truck.gltf mesh 2)". Only an instance's path is held,
    // so that a million of them fit in short strings.
    // On an instance of a solid shape, the part's: "objects[6] (shapes.cup.children[1])".
    std::string leaf_name(int leaf, int part = -1) const;

    // Filled by the loader beside leaf_paths: leaf index -> material index.
    std::vector<int> leaf_materials;
    // What the loader read but does not use (a mesh file's materials and colours), each naming its JSON path
    // and file: for the commands to show.
    std::vector<std::string> warnings;
};

constexpr int max_image_side = 16384;
constexpr int max_trace_depth = 64;
// Primitives (leaves, CSG children included, and every triangle of a mesh) in one scene. Memory sets this limit,
// not the ids (int32, 2^31): `twinray render` peaks at about 165 bytes per primitive (the scene model, the compiled
// scene and the BVH; docs/scene-format.md, "Limits"), so a scene at the limit needs about 0.7 GB (the reference
// tracer's render about 2 GB). Four times the most `twinray generate` writes. The loader refuses a scene past it as
// it reads, before it holds more.
constexpr std::size_t max_scene_primitives = std::size_t{1} << 22;  // 4 194 304
// What one primitive costs at the peak of a render, measured (docs/scene-format.md): for messages.
constexpr std::size_t bytes_per_primitive = 165;

// Primitives in one top-level CSG object. The SSE tracer keeps a CSG object's span lists in
// fixed-capacity arrays on the stack (at most max_csg_leaves + 1 spans), so the loader refuses more.
constexpr int max_csg_leaves = 64;

struct ImageSize {
    int width;
    int height;
};

// A command-line size replaces the scene's; giving only one side (the other 0) keeps the scene's
// aspect ratio, rounded to the nearest integer and at least 1. Throws std::invalid_argument when a
// side, given or derived, is outside 1..max_image_side (0 means "not given"; negatives are refused).
ImageSize resolve_image_size(const Scene& scene, int requested_width, int requested_height);

}  // namespace twinray::scene
