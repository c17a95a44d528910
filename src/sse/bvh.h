// A bounding volume hierarchy over the bounded top-level items of the compiled scene (each primitive by its
// box, each CSG object by its bound); planes and anything else unbounded stay in flat lists. Binary, built by
// binned SAH on one thread, deterministic: the same scene gives the same node array on any machine and for
// any thread count (IEEE float arithmetic only, no unordered containers, our own partition, ties to the lower
// axis, bin and input index). The build uses SSE2 only (the x86-64 baseline, no -msse4.1); the traversal is in
// bvh_traversal.h.
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

// 32 bytes, 16-byte aligned, so that each half loads as one __m128. An inner node (count 0) has its two
// children at `first` and `first + 1`, `first` even: the array starts on a cache line, so two siblings, tested
// together, share one 64-byte line. A leaf holds items[first, first + count).
struct alignas(16) BvhNode {
    float low[3];
    std::uint32_t first;
    float high[3];
    std::uint32_t count;
    bool operator==(const BvhNode&) const = default;
};

// A leaf is at most this deep (the root is depth 0), so a traversal stack of bvh_max_depth + 1 entries never
// overflows, whatever the scene: the build switches from SAH to halving splits where the depth left runs short.
constexpr int bvh_max_depth = 64;

// What the build needs of one item: its bounds in the compiled scene's coordinates (double, finite).
struct BvhInput {
    scene::Bounds bounds;
    BvhItem item;
};

struct Bvh {
    LargeArray<BvhNode> nodes;  // nodes[0] is the root, nodes[1] unused (siblings from 2); empty: no BVH
    LargeArray<BvhItem> items;  // leaves' items, in leaf order
    // Filled by compile(), which moves the primitive lists into leaf order: for each list in turn (as
    // PrimitiveLists::for_each), the places of its primitives in file order, the order brute force multiplies
    // shadow rays' transmissions in.
    LargeArray<std::uint32_t> file_order;

    bool empty() const { return nodes.empty(); }
};

// Box tests stay conservative against the float kernels (docs/sse-tracer.md, "The BVH"): every box is padded
// outward by this share of its largest |coordinate| before it is rounded outward to float, and every ray's
// origin by the same share of its own (bvh_traversal.h). 2⁻¹³ is 2048 float ulps, far beyond any kernel's
// rounding of a hit point (a few ulps of the distances involved).
constexpr double bvh_padding = 1.0 / 8192.0;

// `inputs` in the order the leaves' items should keep among equals (the compiled lists' order).
Bvh build_bvh(const std::vector<BvhInput>& inputs);

// Bytes of nodes, items and file order.
std::size_t bvh_bytes(const Bvh& bvh);

}  // namespace twinray::sse
