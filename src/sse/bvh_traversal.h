// Four rays (a packet) down the BVH (bvh.h): one test of the four rays against each of a node's four boxes,
// nearest child first, a child entered if any lane still needing it meets its box. Only the SSE tracer's own
// translation units (built with -msse4.1) include this.
//
// Why the answers stay those of brute force (docs/sse-tracer.md, "The BVH"): a kernel's hit point lies
// within a few float ulps of its primitive, every box is padded by bvh_padding of its coordinates and every
// ray's origin by bvh_padding of its own, far more (by less what needs less: a shape's triangles, shape_ray_padding;
// instances, whose own boxes both ways test, instance_box_padding); so a ray's box test passes at any t where its
// kernel could report a crossing, and a leaf is skipped only if none of its items could change the lane's answer.
#pragma once

#include "sse/compiled_scene.h"

#include <algorithm>
#include <optional>
#include <utility>

namespace twinray::sse {

// A packet's rays as its box tests need them: 1/d as an IEEE division (whatever the precision knobs), and the
// origin moved by δ = padding·|o|∞ (per lane; the top level's CompiledScene::top_ray_padding, or a shape's
// shape_ray_padding) towards each face, which pads every box by δ for this ray at no cost per node: the low faces'
// t is (low − δ − o)/d, the high faces' (high + δ − o)/d.
struct BvhRays {
    Vec3x4 low_face_origin;   // o + δ
    Vec3x4 high_face_origin;  // o − δ
    Vec3x4 inverse_direction;

    TWINRAY_KERNEL BvhRays(const RayPacket& rays, float padding) {
        vfloat4 delta = vfloat4(padding) * max_abs_component(rays.origin) + vfloat4(1e-30f);
        for (int axis = 0; axis < 3; ++axis) {
            low_face_origin[axis] = rays.origin[axis] + delta;
            high_face_origin[axis] = rays.origin[axis] - delta;
            inverse_direction[axis] = vfloat4(1.0f) / rays.direction[axis];
        }
    }
};

// The top level's: the scene's rays padded by CompiledScene::top_ray_padding, with or without a BVH alike.
inline BvhRays top_level_rays(const CompiledScene& scene, const RayPacket& rays) {
    return BvhRays(rays, scene.top_ray_padding);
}

struct NodeTest {
    vfloat4 near;  // where each lane enters the box (0 if it starts inside); +∞ for lanes that miss it
    vbool4 hit;    // lanes of `lanes` that meet the box within [0, t_max]
};

// A box against the packet: slabs, each face's coordinate in all four lanes. A lane parallel to an axis gets ±∞
// from both faces, or NaN where its origin lies exactly on a padded face: min/max then return the other face's t,
// which is ±∞ and drops the lane, rightly (it is δ outside).
inline NodeTest test_box(const Vec3x4& low, const Vec3x4& high, const BvhRays& rays, vfloat4 t_max, vbool4 lanes) {
    vfloat4 near(0.0f);
    vfloat4 far = t_max;
    for (int axis = 0; axis < 3; ++axis) {
        vfloat4 t_low = (low[axis] - rays.low_face_origin[axis]) * rays.inverse_direction[axis];
        vfloat4 t_high = (high[axis] - rays.high_face_origin[axis]) * rays.inverse_direction[axis];
        near = max(near, min(t_low, t_high));
        far = min(far, max(t_low, t_high));
    }
    vbool4 hit = lanes & (near <= far);
    return {select(hit, near, vfloat4(infinity)), hit};
}

// Child c's box against the packet.
inline NodeTest test_child(const BvhNode& node, int c, const BvhRays& rays, vfloat4 t_max, vbool4 lanes) {
    return test_box({vfloat4(node.low[0][c]), vfloat4(node.low[1][c]), vfloat4(node.low[2][c])},
                    {vfloat4(node.high[0][c]), vfloat4(node.high[1][c]), vfloat4(node.high[2][c])}, rays, t_max, lanes);
}

// One lane's ray against a node's four boxes at once (the same slab arithmetic as test_child, lane by lane, so
// the same boxes pass): where each child is entered, and which children it meets before t_max.
struct LaneRay {
    Vec3x4 low_face_origin, high_face_origin, inverse_direction;  // the lane's, in all four lanes

    LaneRay(const BvhRays& rays, int lane) {
        for (int axis = 0; axis < 3; ++axis) {
            low_face_origin[axis] = vfloat4(rays.low_face_origin[axis].lane(lane));
            high_face_origin[axis] = vfloat4(rays.high_face_origin[axis].lane(lane));
            inverse_direction[axis] = vfloat4(rays.inverse_direction[axis].lane(lane));
        }
    }

    int children_met(const BvhNode& node, float t_max, vfloat4& near) const {
        near = vfloat4(0.0f);
        vfloat4 far(t_max);
        for (int axis = 0; axis < 3; ++axis) {
            vfloat4 t_low = (vfloat4::load(node.low[axis]) - low_face_origin[axis]) * inverse_direction[axis];
            vfloat4 t_high = (vfloat4::load(node.high[axis]) - high_face_origin[axis]) * inverse_direction[axis];
            near = max(near, min(t_low, t_high));
            far = min(far, max(t_low, t_high));
        }
        vbool4 present = !(vint4::load(reinterpret_cast<const std::int32_t*>(node.count)) ==
                           vint4(static_cast<std::int32_t>(BvhNode::empty_child)));
        return movemask(present & (near <= far));
    }
};

// Entries of a walk's stack: a node (count 0, nodes[first]) or a leaf (items[first, first + count)), with
// where the ray enters it: one float or, for a packet, four (__m128: trivial, so that a stack of entries is
// not zeroed on every walk, which vfloat4's constructor would do, 6 KB a walk), and then the least of them,
// which orders siblings.
struct LanePending {
    float near;
    std::uint32_t first;
    std::uint32_t count;
};

struct PacketPending {
    __m128 near;
    std::uint32_t first;
    std::uint32_t count;
    float least_near;
};

inline float order_of(const LanePending& entry) {
    return entry.near;
}
inline float order_of(const PacketPending& entry) {
    return entry.least_near;
}

// A child the walk will visit: its node's two cache lines, or the first bytes of its leaf's records (`leaf_records`:
// the BVH's items, or a shape's triangles, which its leaves read at their places), fetched while the walk tests its
// siblings and pops their subtrees (at a million primitives each is a miss).
template <typename Record>
void prefetch_child(const Bvh& bvh, const LargeArray<Record>& leaf_records, std::uint32_t first, std::uint32_t count) {
    const char* bytes = count == 0 ? reinterpret_cast<const char*>(&bvh.nodes[first])
                                   : reinterpret_cast<const char*>(&leaf_records[first]);
    _mm_prefetch(bytes, _MM_HINT_T0);
    _mm_prefetch(bytes + 64, _MM_HINT_T0);
}

// Pushes one sibling onto the run of its siblings (from `base`), kept farthest first, so that the nearest is
// popped first.
template <typename Entry>
TWINRAY_KERNEL void push_in_order(Entry* stack, int base, int& size, const Entry& entry) {
    int at = size++;
    while (at > base && order_of(stack[at - 1]) < order_of(entry)) {
        stack[at] = stack[at - 1];
        --at;
    }
    stack[at] = entry;
}

// Lane `lane` alone down the subtree at nodes[root], four boxes a test: where a packet has diverged to one
// ray, testing four boxes for it at once costs a quarter of testing one box for all four lanes, three of them
// idle. at_leaf still runs the packet's kernels (any crossing it keeps for another lane is a true one).
template <typename Record, typename AtLeaf>
void walk_one_lane(const Bvh& bvh, const LargeArray<Record>& leaf_records, const BvhRays& rays, int lane,
                   std::uint32_t root, vbool4& lanes, const vfloat4& t_max, AtLeaf& at_leaf) {
    const LaneRay ray(rays, lane);
    const int lane_bit = 1 << lane;
    LanePending stack[bvh_stack_size];
    int size = 0;
    stack[size++] = {0.0f, root, 0};
    float limit = t_max.lane(lane);
    while (size > 0) {
        LanePending pending = stack[--size];
        if (!(pending.near <= limit)) {
            continue;
        }
        // Down to a leaf: of the children met, the nearest (the last of equals, which the stack would give first) is
        // entered at once and the rest pushed farthest first; an only child is not prefetched (inside a small shape,
        // most nodes), several all are. Pushing the nearest too and popping it back read stack entries just written,
        // in other widths than they were written: a store forwarding stalled on every node of several children.
        while (pending.count == 0) {
            const BvhNode& node = bvh.nodes[pending.first];
            vfloat4 near;
            int met = ray.children_met(node, limit, near);
            if (met == 0) {
                break;
            }
            alignas(16) float entries[4];
            near.store(entries);
            int nearest = __builtin_ctz(static_cast<unsigned>(met));
            for (int rest = met & (met - 1); rest != 0; rest &= rest - 1) {
                const int c = __builtin_ctz(static_cast<unsigned>(rest));
                nearest = entries[c] <= entries[nearest] ? c : nearest;
            }
            if (met != 1 << nearest) {
                const int base = size;
                for (; met != 0; met &= met - 1) {
                    const int c = __builtin_ctz(static_cast<unsigned>(met));
                    prefetch_child(bvh, leaf_records, node.first[c], node.count[c]);
                    if (c != nearest) {
                        push_in_order(stack, base, size, LanePending{entries[c], node.first[c], node.count[c]});
                    }
                }
            }
            pending = {entries[nearest], node.first[nearest], node.count[nearest]};
        }
        if (pending.count == 0) {
            continue;  // a node whose children the ray all misses
        }
        at_leaf(BvhLeaf{pending.first, pending.count, lane});
        if ((movemask(lanes) & lane_bit) == 0) {
            return;
        }
        limit = t_max.lane(lane);
    }
}

// Calls at_leaf(BvhLeaf) for every leaf whose box some lane of `lanes` meets before its `t_max`. at_leaf may
// lower t_max and clear lanes (rays that are done); both are read again at every node, and the walk stops
// when no lane is left. A node's children met are visited nearest first (by the least entry of any lane).
// Below a node that at most `lanes_alone` lanes still meet, each of them walks on alone (walk_one_lane), one after
// the other: past one, a leaf may be visited once for each, and at_leaf, told its walking lane, must keep only that
// lane's crossings. The stack holds at most three pending siblings a level: bvh_stack_size bounds it.
// `leaf_records`: what a leaf reads first (prefetch_child).
template <int lanes_alone = 1, typename Record, typename AtLeaf>
void for_each_leaf_met(const Bvh& bvh, const LargeArray<Record>& leaf_records, const BvhRays& rays, vbool4& lanes,
                       const vfloat4& t_max, AtLeaf&& at_leaf) {
    PacketPending stack[bvh_stack_size];
    int size = 0;
    stack[size++] = {select(lanes, vfloat4(0.0f), vfloat4(infinity)).m, 0, 0, 0.0f};
    while (size > 0) {
        PacketPending pending = stack[--size];
        vbool4 meeting = lanes & (vfloat4(pending.near) <= t_max);
        int meeting_bits = movemask(meeting);
        if (meeting_bits == 0) {
            continue;
        }
        if (pending.count > 0) {
            at_leaf(BvhLeaf{pending.first, pending.count});
            if (none(lanes)) {
                return;
            }
            continue;
        }
        if (lane_count(meeting) <= static_cast<std::uint64_t>(lanes_alone)) {
            for (int bits = meeting_bits; bits != 0; bits &= bits - 1) {
                const int lane = __builtin_ctz(static_cast<unsigned>(bits));
                if ((movemask(lanes) >> lane) & 1) {
                    walk_one_lane(bvh, leaf_records, rays, lane, pending.first, lanes, t_max, at_leaf);
                }
            }
            if (none(lanes)) {
                return;
            }
            continue;
        }
        const BvhNode& node = bvh.nodes[pending.first];
        const int base = size;
        for (int c = 0; c < 4 && node.count[c] != BvhNode::empty_child; ++c) {
            NodeTest child = test_child(node, c, rays, t_max, meeting);
            if (any(child.hit)) {
                prefetch_child(bvh, leaf_records, node.first[c], node.count[c]);
                push_in_order(stack, base, size,
                              PacketPending{child.near.m, node.first[c], node.count[c], horizontal_min(child.near)});
            }
        }
    }
}

// The CSG objects a packet may meet, folded in ascending index: the order brute force folds them in, so
// each sees the same limit and the answer is the same. Without a walk of the BVH (no BVH), every object. Past
// `capacity` candidates (no heap allocation per ray) the smallest indices are held, and the rest are met again by
// another walk once those are folded (for_each's rounds): at 20 000 glass CSG instances a shadow ray passes by
// more than `capacity` boxes, and testing every object's bound instead made renders five times slower.
class CsgCandidates {
public:
    static constexpr int capacity = 64;

    // From now on, only the objects add()ed (and the unbounded ones) are candidates.
    void collect() { collecting_ = true; }
    void add(std::uint32_t index) {
        if (index < next_round_from_) {
            return;  // folded in an earlier round
        }
        if (count_ < capacity) {
            indices_[count_++] = index;
            return;
        }
        more_ = true;
        std::uint32_t* largest = std::max_element(indices_, indices_ + count_);
        *largest = std::min(*largest, index);
    }
    // Whether for_each needed more than one round (a walk again).
    bool walked_again() const { return rounds_ > 1; }
    // Whether a leaf's items might not all fit: a walk whose answer does not depend on the order the objects are
    // folded in (the least (t, leaf) of a nearest hit, an opaque shadow ray's blocking) folds those held now
    // (fold_held), so that for_each needs no round but its first.
    bool nearly_full() const { return count_ > capacity - static_cast<int>(primitive_bvh_costs.max_leaf_items); }
    // visit(object) for the objects added so far, in ascending index, which are then forgotten; the unbounded ones
    // are for for_each. Objects dropped before it (a leaf of more than `capacity` objects whose centroids coincide,
    // which no split separates) are met again by for_each's rounds, from the first index on.
    template <typename Visit>
    void fold_held(const CompiledScene& scene, Visit&& visit) {
        std::sort(indices_, indices_ + count_);
        for (int i = 0; i < count_; ++i) {
            visit(scene.csg_objects[indices_[i]]);
        }
        count_ = 0;
        again_from_start_ = again_from_start_ || more_;
        more_ = false;
    }

    // visit(object) for every candidate, the unbounded ones among them, in ascending index, in rounds of at most
    // `capacity`: after a round that could not hold them all, walk_again() meets the objects again and add()s them,
    // and only those above the round's last are kept. An object visited twice (one fold_held visited, met again)
    // changes no order-independent answer, and only such callers call fold_held.
    template <typename WalkAgain, typename Visit>
    void for_each(const CompiledScene& scene, WalkAgain&& walk_again, Visit&& visit) {
        if (!collecting_) {
            for (const CsgObject& object : scene.csg_objects) {
                visit(object);
            }
            return;
        }
        for (;;) {
            for (std::int32_t index : scene.unbounded_csg) {
                add(static_cast<std::uint32_t>(index));
            }
            std::sort(indices_, indices_ + count_);
            for (int i = 0; i < count_; ++i) {
                visit(scene.csg_objects[indices_[i]]);
            }
            if (again_from_start_) {
                next_round_from_ = 0;
                again_from_start_ = false;
            } else if (more_) {
                next_round_from_ = indices_[count_ - 1] + 1;
            } else {
                return;
            }
            count_ = 0;
            more_ = false;
            ++rounds_;
            walk_again();
        }
    }

private:
    std::uint32_t indices_[capacity];
    int count_ = 0;
    bool collecting_ = false;
    bool more_ = false;                  // more candidates met than held
    std::uint32_t next_round_from_ = 0;  // the least index a round still takes
    bool again_from_start_ = false;      // fold_held folded while objects had been dropped
    int rounds_ = 1;
};

// Calls visit(crossing, place) for every triangle of the list some ray meets, in place order.
template <typename P, typename Visit>
void for_each_triangle_crossing(const TriangleList& triangles, const ShearedRays& rays, Visit&& visit) {
    for (std::size_t i = 0; i < triangles.items.size(); ++i) {
        TriangleHit4 crossing = triangle_crossing<P>(triangles.items[i], rays);
        if (any(crossing.valid)) {
            visit(crossing, static_cast<std::uint32_t>(i));
        }
    }
}

// The packet carried into an instance's space as transformed.h carries it, o' = L⁻¹·(o − t), d' = L⁻¹·d, but d'
// left as it is: the triangle test takes any direction, and along o' + t·d' the object rays meet a triangle at the
// world rays' own t, so limits and hits need no scaling.
inline RayPacket object_rays(const InstanceRecord& instance, const RayPacket& rays) {
    const math::Transform<float>& m = instance.to_world;
    math::Matrix3<vfloat4> inverse;
    for (int i = 0; i < 3; ++i) {
        inverse.row[i] = broadcast(m.inverse.row[i]);
    }
    Vec3x4 origin = mutated<Mutant::transform_order_swapped> ? inverse * rays.origin - broadcast(m.translation)
                                                             : inverse * (rays.origin - broadcast(m.translation));
    return RayPacket(origin, inverse * rays.direction, rays.active);
}

// The packet against an instance's box in the world (instance_box). A BVH leaf holds several instances and does not
// keep their boxes: without this test each of them costs the trip into its space and its shape's root test, and a
// packet of primary rays through a forest of 1 000 trees entered 5.4 instances where 1.2 pass it
// (docs/performance.md).
inline NodeTest test_instance_box(const InstanceBox& box, const BvhRays& world, vbool4 lanes, const vfloat4& t_max) {
    // Each load's fourth lane is the record's next float, unused.
    return test_box(spread_xyz(_mm_loadu_ps(box.low)), spread_xyz(_mm_loadu_ps(box.high)), world, t_max, lanes);
}

// The lane that alone reached a leaf of a shape, walking on its own or the only one of `lanes`; else -1.
inline int lane_alone_at(const BvhLeaf& leaf, vbool4 lanes) {
    const int bits = movemask(lanes);
    return leaf.walking_lane >= 0                  ? leaf.walking_lane
           : bits != 0 && (bits & (bits - 1)) == 0 ? __builtin_ctz(static_cast<unsigned>(bits))
                                                   : -1;
}

// A leaf's triangles against one lane's ray, four at a time (crossing_of_four): where the packet's lanes have parted
// between trees, a lane alone paid a four-lane test per triangle, three lanes idle; at 100 000 instances 57 % of the
// instances entered served one lane (docs/performance.md). Each crossing found is visited as the packet's kernel
// would give it for that lane. The other lanes' crossings, which the packet's kernel finds too, are not looked for:
// a lane that needs one meets this leaf itself, as the BVH's boxes are conservative.
template <typename P, typename Visit>
void for_each_crossing_of_lane(const CompiledShape& shape, const BvhLeaf& leaf, const ShearedRays& alone, int lane,
                               Visit&& visit) {
    const std::uint32_t end = leaf.first + leaf.count;
    for (std::uint32_t i = leaf.first; i < end; i += 4) {  // leaf.first is a multiple of 4 (CompiledShape::blocks)
        const TriangleHit4 crossings = crossing_of_four<P>(shape.blocks[i / 4], alone);
        // Past the leaf's end, its last triangle repeated: not visited.
        int valid = movemask(crossings.valid) & ((1 << std::min<std::uint32_t>(4, end - i)) - 1);
        const int front = movemask(crossings.front);
        for (; valid != 0; valid &= valid - 1) {
            const int k = __builtin_ctz(static_cast<unsigned>(valid));
            TriangleHit4 crossing;
            crossing.valid = lanes_of(1 << lane);
            crossing.t = vfloat4(crossings.t.lane(k));
            crossing.front = ((front >> k) & 1) != 0 ? all_true() : none_true();
            visit(crossing, i + static_cast<std::uint32_t>(k));
        }
    }
}

// Inside a shape, a node that three lanes or fewer meet is walked by each of them alone: four boxes a test and four
// triangles a test for one ray cost about what one box or one triangle costs for four lanes, so up to three lanes
// apart cost less than the packet, whose idle lanes ride along (first hits on forests of 4 000 and 10 000 trees 2–4 %
// faster, of 1 000 and 100 000 within noise; docs/performance.md). The scene's walk keeps one: there a leaf's
// kernels run for every lane.
constexpr int shape_lanes_alone = 3;

// Calls visit(crossing, place) for every triangle of the instance's shape (`place` in its triangle list) that some
// lane of `lanes` meets before its t_max, through the shape's BVH where it has one; visit may lower t_max and clear
// lanes (a shadow ray blocked), both read again at every node, as for_each_leaf_met reads them. The caller has
// tested the instance's box (test_instance_box).
template <typename P, typename Visit>
void for_each_crossing_inside(const CompiledScene& scene, const InstanceRecord& instance, const RayPacket& rays,
                              vbool4& lanes, const vfloat4& t_max, Visit&& visit) {
    const CompiledShape& shape = scene.shapes[instance.shape];
    const RayPacket object = object_rays(instance, rays);
    const ShearedRays sheared = ShearedRays::of<P>(object);
    if (shape.bvh.empty()) {
        for_each_triangle_crossing<P>(shape.triangles, sheared, visit);
        return;
    }
    ShearedRays alone_frame;  // lane `framed`'s, made when a leaf first needs it
    int framed = -1;
    // The leaf by reference: by value, the lone lane's walk packed its two places into one register through the
    // stack, a stalled store forwarding at every leaf (3 % of a first hit at 100 000 instances).
    const BvhRays box_rays(object, shape_ray_padding<P>());
    for_each_leaf_met<shape_lanes_alone>(
        shape.bvh, shape.triangles.items, box_rays, lanes, t_max, [&](const BvhLeaf& leaf) {
            const int alone = lane_alone_at(leaf, lanes);
            if constexpr (!P::moller_trumbore) {
                if (alone >= 0) {
                    if (alone != framed) {
                        alone_frame = sheared.lane_alone(alone);
                        framed = alone;
                    }
                    for_each_crossing_of_lane<P>(shape, leaf, alone_frame, alone, visit);
                    return;
                }
            }
            // Here with a walking lane only under Möller–Trumbore: the packet's other lanes walk this leaf too, and
            // their crossings here are theirs to find.
            const vbool4 finding = leaf.walking_lane >= 0 ? lanes_of(1 << leaf.walking_lane) : all_true();
            for (std::uint32_t place = leaf.first; place < leaf.first + leaf.count; ++place) {
                TriangleHit4 crossing = triangle_crossing<P>(shape.triangles.items[place], sheared);
                if constexpr (P::moller_trumbore) {
                    crossing.valid = crossing.valid & finding;
                }
                if (any(crossing.valid)) {
                    visit(crossing, place);
                }
            }
        });
}

// for_each_crossing_inside behind the instance's box. `world`: the packet's own BvhRays.
template <typename P, typename Visit>
void for_each_instance_crossing(const CompiledScene& scene, const InstanceBox& box, const RayPacket& rays,
                                const BvhRays& world, vbool4& lanes, const vfloat4& t_max, Visit&& visit) {
    if (any(test_instance_box(box, world, lanes, t_max).hit)) {
        for_each_crossing_inside<P>(scene, scene.instances[box.record], rays, lanes, t_max, std::forward<Visit>(visit));
    }
}

// A BVH leaf's instances whose boxes a packet met, entered nearest box first, each only if a lane still meets its box
// before that lane's t_max: a nearer tree's hit then culls the trees behind it. For nearest hits, whose answer does
// not depend on the order crossings are met in (keep_nearest); a shadow multiplies its factors in list order and
// keeps the leaf's. Past `capacity` (the BVH's most items a leaf, bvh.cpp, save a leaf of items whose centroids
// coincide, which no split separates) the rest are entered at once, unordered.
class InstancesByDistance {
public:
    static constexpr int capacity = 8;

    // False where full: then the caller enters this one now.
    bool add(std::uint32_t index, const NodeTest& box) {
        if (count_ == capacity) {
            return false;
        }
        Met met{box.near.m, box.hit.m, horizontal_min(box.near), index};
        int at = count_++;
        while (at > 0 && met_[at - 1].least_near > met.least_near) {
            met_[at] = met_[at - 1];
            --at;
        }
        met_[at] = met;
        return true;
    }

    bool empty() const { return count_ == 0; }

    // enter(index, lanes) for each, nearest first, with the lanes that still meet its box before t_max; then none is
    // left, for the next leaf.
    template <typename Enter>
    void enter_nearest_first(const vfloat4& t_max, Enter&& enter) {
        for (int i = 0; i < count_; ++i) {
            vbool4 lanes = vbool4{met_[i].hit} & (vfloat4(met_[i].near) <= t_max);
            if (any(lanes)) {
                enter(met_[i].index, lanes);
            }
        }
        count_ = 0;
    }

private:
    struct Met {
        __m128 near, hit;  // trivial, as PacketPending's: no zeroing of the array on every leaf
        float least_near;
        std::uint32_t index;
    };
    Met met_[capacity];
    int count_ = 0;
};

// Calls visit(span, id, transmission, list) for every primitive of a BVH leaf that some ray of the packet meets
// (as for_each_span), visit_triangle(crossing, place) for every triangle (its place in scene.triangles) and
// visit_instance(box) for every instance (its place in scene.instance_boxes), and adds the leaf's CSG objects to `csg`.
// `sheared` is the packet's frame for triangles (made, and read, only where the scene has some).
template <typename P, typename Visit, typename VisitTriangle, typename VisitInstance>
void for_each_span_in_leaf(const CompiledScene& scene, BvhLeaf leaf, const RayPacket& rays,
                           const std::optional<ShearedRays>& sheared, CsgCandidates& csg, Visit&& visit,
                           VisitTriangle&& visit_triangle, VisitInstance&& visit_instance) {
    for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
        const BvhItem& item = scene.bvh.items[i];
        if (item.list == csg_list) {
            csg.add(item.index);
            continue;
        }
        if (item.list == instance_list) {
            visit_instance(item.index);
            continue;
        }
        if (item.list == triangle_list) {
            TriangleHit4 crossing = triangle_crossing<P>(scene.triangles.items[item.index], *sheared);
            if (any(crossing.valid)) {
                visit_triangle(crossing, item.index);
            }
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

// A walk again for CsgCandidates::for_each's next round: the CSG objects of every leaf some lane of `lanes` meets
// before its t_max, add()ed to `csg`, as for_each_span_in_leaf adds them.
inline void collect_csg_again(const CompiledScene& scene, const RayPacket& rays, vbool4 lanes, const vfloat4& t_max,
                              CsgCandidates& csg) {
    const BvhRays box_rays = top_level_rays(scene, rays);
    for_each_leaf_met(scene.bvh, scene.bvh.items, box_rays, lanes, t_max, [&](const BvhLeaf& leaf) {
        for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
            if (scene.bvh.items[i].list == csg_list) {
                csg.add(scene.bvh.items[i].index);
            }
        }
    });
}

}  // namespace twinray::sse
