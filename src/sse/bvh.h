// A bounding volume hierarchy over the bounded top-level items of the compiled scene (each primitive by its
// box, each CSG object by its bound); planes and anything else unbounded stay in flat lists. Four children a
// node, as wide as SSE: built binary by binned SAH on one thread, then collapsed. Deterministic: the same scene
// gives the same node array on any machine and for any thread count (IEEE float arithmetic only, no unordered
// containers, our own partition, ties to the lower axis, bin and input index). The build uses SSE2 only (the
// x86-64 baseline, no -msse4.1); the traversal is in bvh_traversal.h.
#pragma once

#include "render/large_array.h"
#include "scene/geometry.h"

#include <cstdint>
#include <vector>

namespace twinray::sse {

// Which top-level item a leaf holds: `list` is a type's position in scene::PrimitiveTypes (its list in
// PrimitiveLists) or `csg_list` for a CSG object; `index` is its place in that list (CompiledScene keeps its
// primitive lists in leaf order, so a leaf's items are consecutive records).
struct BvhItem {
    std::uint32_t list;
    std::uint32_t index;
    bool operator==(const BvhItem&) const = default;
};

// 128 bytes, two cache lines: the boxes of up to four children, structure of arrays (low[axis][child]), so
// that one child's face is one broadcast and one ray's four slabs are one __m128. Child c is an inner node
// (count[c] == 0, nodes[first[c]]), a leaf (items[first[c], first[c] + count[c])) or, past the last child,
// empty (count[c] == empty_child). Leaves live in their parent: a walk loads no node to learn it has reached one.
struct alignas(64) BvhNode {
    static constexpr std::uint32_t empty_child = ~std::uint32_t{0};

    float low[3][4];
    float high[3][4];
    std::uint32_t first[4];
    std::uint32_t count[4];
    bool operator==(const BvhNode&) const = default;
};

// A leaf's items: items[first, first + count). `walking_lane`: the one lane that reached it, where a packet's walk
// went on for one lane alone (walk_one_lane); else -1.
struct BvhLeaf {
    std::uint32_t first;
    std::uint32_t count;
    int walking_lane = -1;
};

// A leaf is at most this many nodes below the root, whatever the scene: the binary build switches from SAH to
// halving splits where the depth left runs short, and collapsing only shortens paths. A walk keeps at most
// three pending siblings a level, so bvh_stack_size entries never overflow.
constexpr int bvh_max_depth = 64;
constexpr int bvh_stack_size = 3 * bvh_max_depth + 1;

// Box tests stay conservative against the float kernels (docs/sse-tracer.md, "The BVH"): every box is padded
// outward by this share of its largest |coordinate| before it is rounded outward to float, and every ray's
// origin by the same share of its own (bvh_traversal.h). 2⁻¹³ is 2048 float ulps, far beyond any kernel's
// rounding of a hit point (a few ulps of the distances involved).
constexpr double bvh_padding = 1.0 / 8192.0;

// One item as the build takes it and moves it: its bounds in the compiled scene's coordinates (double, finite)
// padded by `padding` (bvh_padding, or an instance's instance_item_padding) of their largest |coordinate| and rounded
// outward to float, and its item, packed. 32 bytes, so that partitioning moves whole cache-line halves, and the build
// sorts the very array it is given: at a million items, no second copy of them (32 MB) and no double bounds (56 MB)
// beside the binary tree.
struct alignas(16) BvhInput {
    static constexpr std::uint32_t index_bits = 28;  // BvhItem::list in the 4 bits above
    static constexpr std::uint32_t list_count = std::uint32_t{1} << (32 - index_bits);

    BvhInput(const scene::Bounds& bounds, BvhItem item, double padding = bvh_padding);
    BvhItem item() const { return {packed_item >> index_bits, packed_item & ((std::uint32_t{1} << index_bits) - 1)}; }

    float low[3];
    std::uint32_t place;  // among the inputs, for ties: set by the build
    float high[3];
    std::uint32_t packed_item;
};

struct Bvh {
    LargeArray<BvhNode> nodes;  // nodes[0] is the root; empty: no BVH
    LargeArray<BvhItem> items;  // leaves' items, in leaf order
    // Filled by compile(), which moves the primitive lists into leaf order: for each list in turn (as
    // PrimitiveLists::for_each), the places of its primitives in file order, the order brute force multiplies
    // shadow rays' transmissions in.
    LargeArray<std::uint32_t> file_order;

    bool empty() const { return nodes.empty(); }
};

// A shape's BVH holds triangles alone and is walked in the shape's own space, where a ray from far away has a large
// |o'| against small boxes: a tree of the forest of 100 000 (2.8 units tall) lies 390 to 2 100 of its units from the
// camera, and 2⁻¹³ of that padded each of its leaves' boxes by 0.05 to 0.25 (docs/performance.md). The watertight test
// needs far less: its t is a combination, with weights U, V, W of one sign, of the three vertices carried into the
// ray's frame, each off by a few ulps of |v − o| there (v − o, the shear), so the point it names lies within those ulps
// of its triangle's box, whose own padding covers |v|. 2⁻¹⁸ of |o|∞ (64 ulps) holds every crossing of
// ShapeRayPaddingHoldsEveryWatertightCrossingFarFromItsTriangle (tests/bvh_test.cpp) with the margin it prints: the
// farthest lies 1.6 ulps out. Not a triangle thin in the ray's frame (a sliver, a grazing ray), whose det is near 0 and
// whose point can lie past any fixed padding, bvh_padding's too (docs/sse-tracer.md, "The BVH"). The Möller–Trumbore
// knob keeps bvh_padding.
constexpr double watertight_shape_ray_padding = 1.0 / 262144.0;

template <typename P>
constexpr float shape_ray_padding() {
    return static_cast<float>(P::moller_trumbore ? bvh_padding : watertight_shape_ray_padding);
}

// What the SAH weighs: a node's price in item tests, and the most items a leaf may hold.
struct BvhCosts {
    float node;
    std::uint32_t max_leaf_items;
};

// The top level's items: a node of the collapsed tree is four box tests of a packet and two cache lines. Measured
// against (cost 2, 4 items): the same first-hit and render times from 100 to a million primitives, and half the bytes
// (docs/performance.md, "The BVH").
constexpr BvhCosts primitive_bvh_costs{4.0f, 8};
// A mesh's triangles: a lone lane tests a leaf's four at once (crossing_of_four), and a node costs it a chain of
// dependent steps, so a node is worth about two such blocks. Measured against the top level's (4, 8): the forest of
// 100 000 instances 5–8 % faster, of 10 000 about 4 %, meshes without instances the same (docs/performance.md,
// "Larger leaves in a mesh's BVH").
constexpr BvhCosts triangle_bvh_costs{8.0f, 16};

// `inputs` in the order the leaves' items should keep among equals (the compiled lists' order); taken, and released
// before the tree is collapsed.
Bvh build_bvh(LargeArray<BvhInput> inputs, const BvhCosts& costs);

// Bytes of nodes, items and file order.
std::size_t bvh_bytes(const Bvh& bvh);

}  // namespace twinray::sse
