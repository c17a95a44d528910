// Four rays (a packet) down the BVH (bvh.h): one test of the four rays against a node's box at a time, nearer
// child first, a node entered if any lane still needing it meets its box. Only the SSE tracer's own
// translation units (built with -msse4.1) include this.
//
// Why the answers stay those of brute force (docs/sse-tracer.md, "The BVH"): a kernel's hit point lies
// within a few float ulps of its primitive, every box is padded by bvh_padding of its coordinates and every
// ray's origin by bvh_padding of its own, far more; so a ray's box test passes at any t where its kernel
// could report a crossing, and a leaf is skipped only if none of its items could change the lane's answer.
#pragma once

#include "sse/compiled_scene.h"

#include <algorithm>

namespace twinray::sse {

// A packet's rays as its box tests need them: 1/d as an IEEE division (whatever the precision knobs), and the
// origin moved by δ = bvh_padding·|o|∞ (per lane) towards each face, which pads every box by δ for this ray
// at no cost per node: the low faces' t is (low − δ − o)/d, the high faces' (high + δ − o)/d.
struct BvhRays {
    Vec3x4 low_face_origin;   // o + δ
    Vec3x4 high_face_origin;  // o − δ
    Vec3x4 inverse_direction;

    explicit BvhRays(const RayPacket& rays) {
        vfloat4 delta = vfloat4(static_cast<float>(bvh_padding)) * max_abs_component(rays.origin) + vfloat4(1e-30f);
        for (int axis = 0; axis < 3; ++axis) {
            low_face_origin[axis] = rays.origin[axis] + delta;
            high_face_origin[axis] = rays.origin[axis] - delta;
            inverse_direction[axis] = vfloat4(1.0f) / rays.direction[axis];
        }
    }
};

struct NodeTest {
    vfloat4 near;  // where each lane enters the box (0 if it starts inside); +∞ for lanes that miss it
    vbool4 hit;    // lanes of `lanes` that meet the box within [0, t_max]
};

// Slabs. A lane parallel to an axis gets ±∞ from both faces, or NaN where its origin lies exactly on a padded
// face: min/max then return the other face's t, which is ±∞ and drops the lane, rightly (it is δ outside).
inline NodeTest test_node(const BvhNode& node, const BvhRays& rays, vfloat4 t_max, vbool4 lanes) {
    vfloat4 near(0.0f);
    vfloat4 far = t_max;
    for (int axis = 0; axis < 3; ++axis) {
        vfloat4 t_low = (vfloat4(node.low[axis]) - rays.low_face_origin[axis]) * rays.inverse_direction[axis];
        vfloat4 t_high = (vfloat4(node.high[axis]) - rays.high_face_origin[axis]) * rays.inverse_direction[axis];
        near = max(near, min(t_low, t_high));
        far = min(far, max(t_low, t_high));
    }
    vbool4 hit = lanes & (near <= far);
    return {select(hit, near, vfloat4(infinity)), hit};
}

// Calls at_leaf(node) for every leaf whose box some lane of `lanes` meets before its `t_max`. at_leaf may
// lower t_max and clear lanes (rays that are done); both are read again at every node, and the walk stops
// when no lane is left. The stack holds at most one pending sibling per level: bvh_max_depth bounds it.
template <typename AtLeaf>
void for_each_leaf_met(const Bvh& bvh, const BvhRays& rays, vbool4& lanes, const vfloat4& t_max, AtLeaf&& at_leaf) {
    struct Pending {
        vfloat4 near;
        std::uint32_t node;
    };
    Pending stack[bvh_max_depth + 2];
    int size = 0;
    NodeTest root = test_node(bvh.nodes[0], rays, t_max, lanes);
    if (any(root.hit)) {
        stack[size++] = {root.near, 0};
    }
    while (size > 0) {
        Pending pending = stack[--size];
        vbool4 meeting = lanes & (pending.near <= t_max);
        if (none(meeting)) {
            continue;
        }
        const BvhNode& node = bvh.nodes[pending.node];
        if (node.count > 0) {
            at_leaf(node);
            if (none(lanes)) {
                return;
            }
            continue;
        }
        NodeTest left = test_node(bvh.nodes[node.first], rays, t_max, meeting);
        NodeTest right = test_node(bvh.nodes[node.first + 1], rays, t_max, meeting);
        bool enter_left = any(left.hit);
        bool enter_right = any(right.hit);
        if (enter_left && enter_right) {
            // Nearer first (pushed last) for most of the lanes that meet both.
            vbool4 both = left.hit & right.hit;
            bool left_first = 2 * lane_count(both & (left.near <= right.near)) >= lane_count(both);
            const Pending first{left_first ? left.near : right.near, left_first ? node.first : node.first + 1};
            const Pending second{left_first ? right.near : left.near, left_first ? node.first + 1 : node.first};
            stack[size++] = second;
            stack[size++] = first;
        } else if (enter_left) {
            stack[size++] = {left.near, node.first};
        } else if (enter_right) {
            stack[size++] = {right.near, node.first + 1};
        }
    }
}

// The CSG objects a packet may meet, folded in ascending index: the order brute force folds them in, so
// each sees the same limit and the answer is the same. Without a walk of the BVH (no BVH), or past `capacity`
// candidates (no heap allocation per ray), every object.
class CsgCandidates {
public:
    static constexpr int capacity = 64;

    // From now on, only the objects add()ed (and the unbounded ones) are candidates.
    void collect() { collecting_ = true; }
    void add(std::uint32_t index) {
        if (count_ < capacity) {
            indices_[count_++] = index;
        } else {
            overflowed_ = true;
        }
    }
    bool overflowed() const { return overflowed_; }

    template <typename Visit>
    void for_each(const CompiledScene& scene, Visit&& visit) {
        for (std::int32_t index : scene.unbounded_csg) {
            add(static_cast<std::uint32_t>(index));
        }
        if (!collecting_ || overflowed_) {
            for (const CsgObject& object : scene.csg_objects) {
                visit(object);
            }
            return;
        }
        std::sort(indices_, indices_ + count_);
        for (int i = 0; i < count_; ++i) {
            visit(scene.csg_objects[indices_[i]]);
        }
    }

private:
    std::uint32_t indices_[capacity];
    int count_ = 0;
    bool collecting_ = false;
    bool overflowed_ = false;
};

// Calls visit(span, id, transmission, list) for every primitive of a BVH leaf that some ray of the packet meets
// (as for_each_span), and adds the leaf's CSG objects to `csg`.
template <typename P, typename Visit>
void for_each_span_in_leaf(const CompiledScene& scene, const BvhNode& leaf, const RayPacket& rays, CsgCandidates& csg,
                           Visit&& visit) {
    for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
        const BvhItem& item = scene.bvh.items[i];
        if (item.list == csg_list) {
            csg.add(item.index);
            continue;
        }
        scene.primitives.visit_list(item.list, [&](const auto& list) {
            Span4 span = span_of<P>(list.items[item.index], rays);
            if (any(span.valid)) {
                visit(span, list.ids[item.index], list.transmission[item.index], item.list);
            }
        });
    }
}

}  // namespace twinray::sse
