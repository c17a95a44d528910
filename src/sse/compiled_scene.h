// The scene as the SSE tracer sees it: one flat array per primitive type (scene::PrimitiveTypes), so a
// packet loops only over the types a scene has; CSG objects apart (and culled by a bound), so scenes
// without CSG pay nothing for it. Built once per render. Every primitive record is 16-byte aligned, on
// the heap too (std::vector of an alignas(16) type uses C++17 aligned new).
#pragma once

#include "math/camera.h"
#include "render/large_array.h"
#include "scene/depth_control.h"
#include "sse/box.h"
#include "sse/bvh.h"
#include "sse/csg.h"
#include "sse/cylinder.h"
#include "sse/plane.h"
#include "sse/sphere.h"
#include "sse/tracer.h"
#include "sse/transformed.h"
#include "sse/triangle.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace twinray::sse {

// Each primitive's packet record and hit surface are what its make_shape and make_surface return
// (sphere.h, plane.h, ...).
template <typename S>
using ShapeOf = decltype(make_shape(std::declval<const S&>()));
template <typename S>
using SurfaceOf = decltype(make_surface(std::declval<const S&>()));

// Primitives of one type. `ids` are global leaf indices at top level and slots within a CSG object;
// `transmission` is that of each primitive's material, for shadow rays.
// `bound_centers`/`bound_radii` are a sphere around each primitive (radius +∞ for planes), for
// culling whole tiles of primary rays: only the lists every ray tests have them (CompiledScene::flat, 32 bytes a
// primitive), made once the rest is compiled; lists found through the BVH and CSG objects' leaves never do.
template <typename Shape>
struct PrimitiveList {
    using shape_type = Shape;
    LargeArray<Shape> items;
    LargeArray<std::int32_t> ids;
    LargeArray<float> transmission;
    LargeArray<scene::Vec3> bound_centers;
    LargeArray<double> bound_radii;

    void clear() {
        items.clear();
        ids.clear();
        transmission.clear();
    }
    void reserve(std::size_t count) {
        items.reserve(count);
        ids.reserve(count);
        transmission.reserve(count);
    }
    void swap(std::size_t i, std::size_t j) {
        std::swap(items[i], items[j]);
        std::swap(ids[i], ids[j]);
        std::swap(transmission[i], transmission[j]);
    }
    void push_back_from(const PrimitiveList& other, std::size_t i) {
        items.push_back(other.items[i]);
        ids.push_back(other.ids[i]);
        transmission.push_back(other.transmission[i]);
    }
};

template <typename S>
using PrimitiveListOf = PrimitiveList<ShapeOf<S>>;

// The position of primitive type S in scene::PrimitiveTypes: its list's BvhItem::list.
template <typename S>
constexpr std::uint32_t list_index_of() {
    std::uint32_t index = 0, found = 0;
    scene::PrimitiveTypes::for_each([&](auto type) {
        if (std::is_same_v<typename decltype(type)::type, S>) {
            found = index;
        }
        ++index;
    });
    return found;
}

// BvhItem::list of a CSG object (an index into CompiledScene::csg_objects).
constexpr std::uint32_t csg_list = scene::PrimitiveTypes::size;
// BvhItem::list of a mesh's triangle (an index into CompiledScene::triangles).
constexpr std::uint32_t triangle_list = csg_list + 1;
// BvhItem::list of an instance of a mesh shape (an index into CompiledScene::instances).
constexpr std::uint32_t instance_list = triangle_list + 1;
static_assert(instance_list < BvhInput::list_count && scene::max_scene_primitives <= std::size_t{1}
                                                                                         << BvhInput::index_bits,
              "every BvhItem packs into a BvhInput");

// Every mesh's triangles that can be hit (degenerate ones are left out): without a BVH mesh after mesh in file
// order and each mesh's in its own order; with one, in the order of its leaves (CompiledScene::primitives').
// 44 bytes a triangle.
struct TriangleList {
    LargeArray<TriangleRecord> items;
    // With a BVH and transparent materials only: the places of the triangles in file order, the order brute
    // force multiplies shadow rays' transmissions in (4 bytes a triangle more).
    LargeArray<std::uint32_t> file_order;
    // Where some mesh is smooth, every triangle's vertex indices by place, for its normals (12 bytes a triangle
    // more); beside the records, so that the hits of one leaf find theirs on one cache line.
    LargeArray<std::array<std::uint32_t, 3>> corners;
};

// What a mesh's hits need beyond the triangle: the vertex normals it shades with, if smooth.
struct CompiledMesh {
    LargeArray<Vec3> normals;  // by vertex (TriangleList::corners); empty when flat
};

// A mesh shape (scene::MeshShape) compiled once for all its instances, in its own space: its triangles (their records'
// leaf is -1: an instance names the hit), in the order of its own BVH's leaves where it has one (a leaf's triangles are
// triangles[first, first + count), and its BVH keeps no items: 8 bytes a triangle that would only repeat their places),
// and its normals, if smooth (then its triangles' corners too). Its vertex box as a centre and a half extent (rounded
// up to hold the double box), from which an instance's box in the world is made (instance_box).
struct CompiledShape {
    Packed4 center, half_extent;  // w = 0
    TriangleList triangles;
    // Each triangle's unit normal and longest edge, by place as `triangles`: made once for all the instances' hits
    // (16 bytes a triangle of a shape, none for a scene's own meshes).
    LargeArray<TriangleFrame> frames;
    Bvh bvh;
    // With a BVH: `triangles` four by four (blocks[k] holds places 4k to 4k + 3), for one ray's test of a leaf's four
    // at once; each leaf then starts at a multiple of four, its last triangle repeated up to the next (36 bytes a
    // triangle, and about 1.5 triangles a leaf repeated in every array by place).
    LargeArray<TriangleBlock> blocks;
    CompiledMesh mesh;
};

// An instance of a compiled shape (116 bytes): its transform, relative to the compiled scene's origin, and the
// norms its hits' rounding bounds need (scene::transformed_spawn_offset). A walk reads L⁻¹ and t. Its leaf has no
// entry in CompiledScene::leaves: its material is here (for a solid shape, where a part names none).
struct InstanceRecord {
    math::Transform<float> to_world;
    scene::TransformNorms<float> norms;
    // Index into CompiledScene::shapes, or for a solid shape's instance into ::solids: fewer than the primitive limit,
    // far below 2³¹, so that `mirrors` (det L < 0: a triangle's front turns, scene.h) takes its top bit rather than
    // four bytes of padding, 4 MB of a million instances' peak, which is when the records are made.
    std::uint32_t shape : 31;
    std::uint32_t mirrors : 1;
    std::int32_t leaf;
    std::int32_t material;

    static InstanceRecord of(const scene::Transform& to_world, std::size_t shape, std::int32_t leaf,
                             std::int32_t material);
};
static_assert(sizeof(InstanceRecord) == 116, "docs/sse-tracer.md states an instance's bytes");
static_assert(scene::max_scene_primitives < (std::size_t{1} << 31), "a shape's index fits InstanceRecord::shape");

// An instance's box in the world and its record (an index into CompiledScene::instances): what a walk tests before it
// carries a packet into the instance (test_instance_box). Made once (instance_box), and kept apart from the records
// in the order the walk meets them, so that a leaf's instances are tested from consecutive bytes and a record is read
// only where a ray enters its box. 28 bytes.
struct InstanceBox {
    float low[3];
    float high[3];
    std::uint32_t record;
};

// One list per primitive type, in the order of scene::PrimitiveTypes.
struct PrimitiveLists {
    scene::PrimitiveTypes::map<PrimitiveListOf>::apply<std::tuple> of_type;

    template <typename S>
    PrimitiveListOf<S>& of() {
        return std::get<PrimitiveListOf<S>>(of_type);
    }
    template <typename S>
    const PrimitiveListOf<S>& of() const {
        return std::get<PrimitiveListOf<S>>(of_type);
    }
    // visit(list) for each type's list, in list order.
    template <typename Visit>
    void for_each(Visit&& visit) const {
        std::apply([&](const auto&... list) { (visit(list), ...); }, of_type);
    }
    // visit(mine, theirs) for each type's two lists.
    template <typename Visit>
    void for_each_pair(PrimitiveLists& other, Visit&& visit) const {
        for_each_index(other, visit, std::make_index_sequence<scene::PrimitiveTypes::size>{});
    }
    // visit(list) for the list at `list_index` in scene::PrimitiveTypes (BvhItem::list).
    template <typename Visit>
    void visit_list(std::uint32_t list_index, Visit&& visit) const {
        visit_at(list_index, visit, std::make_index_sequence<scene::PrimitiveTypes::size>{});
    }
    bool any_uses_inverse_direction() const {
        bool uses = false;
        for_each([&](const auto& list) {
            using Shape = typename std::decay_t<decltype(list)>::shape_type;
            uses = uses || (uses_inverse_direction<Shape> && !list.items.empty());
        });
        return uses;
    }

private:
    template <typename Visit, std::size_t... I>
    void visit_at(std::uint32_t list_index, Visit& visit, std::index_sequence<I...>) const {
        ((list_index == I ? visit(std::get<I>(of_type)) : void()), ...);
    }
    template <typename Visit, std::size_t... I>
    void for_each_index(PrimitiveLists& other, Visit& visit, std::index_sequence<I...>) const {
        (visit(std::get<I>(of_type), std::get<I>(other.of_type)), ...);
    }
};

struct CsgNode {
    scene::CsgOp op;
    int first_child;  // index into CsgTree::children_of
    int child_count;
    int slot;  // >= 0: a leaf, its slot in the object's leaf spans; -1: an operation
};

// A CSG tree compiled for four rays: a top-level object's in the world, or a solid shape's in its own space, shared
// by the shape's instances.
struct CsgTree {
    PrimitiveLists leaves;                // ids are slots
    std::vector<std::int32_t> slot_leaf;  // slot -> global leaf index, or a solid shape's part
    std::vector<CsgNode> nodes;           // nodes[0] is the root
    std::vector<int> children_of;         // child node indices, grouped per node
    bool uses_inverse_direction = false;  // some leaf is a box
};

// A top-level CSG object, or an instance of a solid shape (`instance` >= 0: its record in
// CompiledScene::solid_instances, whose tree is its shape's and whose crossings name the instance's leaf and the
// part). 112 bytes beside the tree.
struct CsgObject {
    std::shared_ptr<const CsgTree> tree;
    BoxShape bound;  // in the world, axis-aligned, ±∞ where a half-space leaves it unbounded
    std::int32_t instance = -1;
};

// What the normal of a hit and its re-projection onto the surface need, per leaf (looked up once per
// hit, not per test).
// A mesh's leaf names its CompiledMesh; the triangle comes with the hit.
struct MeshSurface {
    std::uint32_t mesh;
};
using LeafSurface = scene::PrimitiveTypes::map<SurfaceOf>::append<MeshSurface>::apply<std::variant>;

struct Leaf {
    LeafSurface surface;
    int material = 0;
};

// Each leaf's Leaf, by its global index, but an instance's: its record holds its material and its hit names the
// record, so that a million instances do not hold 48 MB of entries no one reads. The runs of instances' leaves left
// out are kept to find the others' entries; a scene without instances has none and is indexed directly.
class LeafTable {
public:
    // `instance_leaves` ascending.
    void assign(std::size_t leaf_count, const std::vector<std::int32_t>& instance_leaves) {
        runs_.clear();
        for (std::int32_t leaf : instance_leaves) {
            const auto at = static_cast<std::uint32_t>(leaf);
            if (!runs_.empty() && runs_.back().end == at) {
                ++runs_.back().end;
            } else {
                const std::uint32_t before =
                    runs_.empty() ? 0 : runs_.back().left_out_before + (runs_.back().end - runs_.back().first);
                runs_.push_back({at, at + 1, before});
            }
        }
        entries_.assign(leaf_count - instance_leaves.size(), Leaf{});
    }
    // Never an instance's leaf.
    Leaf& operator[](std::size_t leaf) { return entries_[entry_of(leaf)]; }
    const Leaf& operator[](std::size_t leaf) const { return entries_[entry_of(leaf)]; }

private:
    struct Run {
        std::uint32_t first, end;       // leaves [first, end) are instances'
        std::uint32_t left_out_before;  // instances' leaves below `first`
    };
    std::size_t entry_of(std::size_t leaf) const {
        if (runs_.empty()) {
            return leaf;
        }
        auto after = std::upper_bound(runs_.begin(), runs_.end(), leaf,
                                      [](std::size_t at, const Run& run) { return at < run.first; });
        if (after == runs_.begin()) {
            return leaf;
        }
        const Run& run = *(after - 1);
        return leaf - run.left_out_before - (run.end - run.first);
    }

    LargeArray<Leaf> entries_;
    std::vector<Run> runs_;
};

// A solid shape (scene::SolidShape) compiled once for its instances, in its own space: its tree, and each part's
// surface there and material (-1 where the instance's applies).
struct CompiledSolid {
    std::shared_ptr<const CsgTree> tree;
    std::vector<Leaf> parts;
};

struct Material {
    Color color;
    float ambient, diffuse, phong, phong_size, reflection, transmission, ior;
};

struct Light {
    Vec3 position;
    Color color;
};

// Everything here is relative to `origin` (origin_of: the eye, for a scene far from the world's origin),
// so the float numbers are small; the per-ray API and the ray tree translate to and from world coordinates
// in double.
struct CompiledScene {
    explicit CompiledScene(const scene::Scene& scene) : depth_control(scene) {}

    scene::Vec3 origin;
    // Top-level primitives; ids are leaf indices. In file order without a BVH; with one in the order of its
    // leaves, the unbounded ones last (bvh.file_order holds the file order).
    PrimitiveLists primitives;
    std::vector<CsgObject> csg_objects;
    TriangleList triangles;  // found through the BVH where there is one, else each tested by every ray
    std::vector<CompiledMesh> meshes;
    std::vector<CompiledShape> shapes;
    // In file order; found through the BVH where there is one, else each tested by every ray after the triangles.
    LargeArray<InstanceRecord> instances;
    // One per instance: with a BVH in the order of its leaves (an instance's BvhItem::index is its place here), else
    // in file order.
    LargeArray<InstanceBox> instance_boxes;
    // What the top level pads its rays' origins by, a share of |o|∞ (top_level_rays), with or without a BVH alike:
    // bvh_padding, which the kernels of primitives, CSG objects and a scene's own triangles need, or where every
    // bounded item is an instance of a mesh shape, instance_ray_padding of the largest κ among them.
    float top_ray_padding = static_cast<float>(bvh_padding);
    // The solid shapes and their instances (InstanceRecord::shape indexes `solids`), in file order; each instance
    // is also a CSG object.
    std::vector<CompiledSolid> solids;
    LargeArray<InstanceRecord> solid_instances;
    // With a BVH (its nodes not empty), the bounded primitives and CSG objects are found through it and only
    // the rest (planes, unbounded CSG objects) are tested by every ray.
    Bvh bvh;
    double bvh_build_cpu_seconds = 0;  // build_bvh alone (one thread), for twinray bench
    // With Accel::automatic, what brute force would spend per packet on the bounded items, in sphere tests: it builds
    // the BVH above `crossover`, bvh_crossover or bvh_crossover_with_secondary_rays (twinray bench --scaling's
    // crossover table sets them beside the measured ones).
    double brute_force_weight = 0;
    std::size_t crossover = bvh_crossover;
    PrimitiveLists unbounded;
    std::vector<std::int32_t> unbounded_csg;  // indices into csg_objects, ascending

    LeafTable leaves;
    std::vector<Material> materials;
    std::vector<Light> lights;
    Color background, ambient_light;
    int max_depth = 1;
    scene::DepthControl depth_control;  // which secondary rays are traced: the reference's rule, in double
    // Model only what the scene requires: without transparent materials a shadow ray stops at its first
    // blocker and no refracted ray is ever traced; without boxes no ray computes its reciprocal.
    bool any_transparency = false;
    bool any_inverse_direction = false;  // boxes, in CSG too, or CSG bounds

    math::CameraBasis<float> camera;  // its eye relative to `origin`

    // The primitives every ray tests one by one: all of them, or with a BVH the ones it leaves out.
    const PrimitiveLists& flat() const { return bvh.empty() ? primitives : unbounded; }
    // The material of `part` as the solid shape's instance `instance` (its index in solid_instances) places it: the
    // part's own, else the instance's.
    int part_material(std::int32_t instance, std::int32_t part) const {
        const InstanceRecord& record = solid_instances[static_cast<std::size_t>(instance)];
        const int own = solids[record.shape].parts[static_cast<std::size_t>(part)].material;
        return own >= 0 ? own : record.material;
    }
};

// `accel`: automatic builds a BVH where brute force would cost more than bvh_crossover sphere tests (tracer.h).
// `given_up`, if given, is `scene` itself, whose leaf paths, objects and meshes are emptied as soon as compiling has
// read them: the paths first (compiling reads none), the objects before the BVH is built, the meshes before the
// instances' boxes are made.
CompiledScene compile(const scene::Scene& scene, Accel accel = Accel::automatic, scene::Scene* given_up = nullptr);

// An instance's box in the world decides which instances a ray enters, alike for the BVH and brute force, which both
// test it against the same rays (instance_item_padding, CompiledScene::top_ray_padding). What it must hold is every
// crossing its shape's walk can find: a point within a few ulps of the shape's box in its own space, so in the world
// within the rounding of the ray's trip there of the exactly placed box, κ·12u·(|o − t|∞ + s) with κ = ‖L‖_F·‖L⁻¹‖_F
// and s the crossing's distance, at most |o|∞ and the box's reach (docs/conformance.md, "The band"). The box's padding
// holds the part that grows with the shape's place: κ·2⁻¹⁸ (64·κ u) of its largest |coordinate|, and 2⁻²⁰ more for
// the rounding of making it; the ray's padding holds the part that grows with |o|∞: instance_ray_padding. At κ = 3
// (any evenly scaled instance), 208 u where bvh_padding is 2048.
inline double instance_box_padding(double condition) {
    return condition * 0x1p-18 + 0x1p-20;
}

// The ray's part (above), κ·2⁻¹⁸ of |o|∞, at most bvh_padding: past κ = 32 a ray's padding stays what it was before
// instances had their own, so that one badly conditioned instance does not widen every box for every ray; a crossing
// its box then leaves out lies within the trip's rounding, as the attribution grants a placed surface.
inline double instance_ray_padding(double condition) {
    return std::min(condition * 0x1p-18, bvh_padding);
}

// κ as an instance's record holds it, its norms rounded up: what its box and its item are padded by.
inline double condition_of(const scene::TransformNorms<float>& norms) {
    return static_cast<double>(norms.stretch) * static_cast<double>(norms.shrink);
}

// The share an instance's item in the scene's BVH is padded by: 2⁻²⁰ more than its box in the world, so that the BVH's
// box holds that box whatever float rounded in making it, and the BVH meets every instance brute force meets.
inline double instance_item_padding(double condition) {
    return instance_box_padding(condition) + 0x1p-20;
}

// The instance `record`'s box in the world: its shape's box carried out (|L|·half extent about L·centre + t) and
// padded by instance_box_padding of its largest |coordinate|.
InstanceBox instance_box(const CompiledScene& scene, std::uint32_t record);

}  // namespace twinray::sse
