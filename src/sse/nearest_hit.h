// The nearest hit of four rays: every primitive's span (per type, in the order of the list), CSG objects
// folded per lane, and the hit's normal and re-projection onto its surface. Only the SSE tracer's own
// translation units (built with -msse4.1) include this.
#pragma once

#include "sse/bvh_traversal.h"
#include "sse/compiled_scene.h"
#include "sse/mutation.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace twinray::sse {

// Tag bits of a nearest hit: the crossing's tag (face, flipped) plus whether the ray enters there.
constexpr std::int32_t tag_entering = 0x20;

// Whether a packet's walk outgrew a fixed capacity: CSG candidates then folded in rounds, each after a walk again
// (CsgCandidates in bvh_traversal.h), transmission factors multiplied in rounds too, or by brute force where one
// mesh's crossings fill a round (TransmissionFactors in shadow.h). The answer is the same either way; tests read this
// to prove that the fallbacks run (bvh_test.cpp).
struct Fallbacks {
    bool csg_candidates = false;
    bool transmission_factors = false;
};

// The nearest crossing so far, per lane (per ray).
struct Nearest4 {
    vfloat4 t{infinity};
    vint4 leaf{-1};
    vint4 tag{0};
    // A mesh's hit (else stale, unread): the triangle's place in CompiledScene::triangles (an instance's: in its
    // shape's), and its index in its mesh, which breaks ties within the mesh.
    vint4 place{-1};
    vint4 triangle{-1};
    // An instance's hit: its index in CompiledScene::instances; -1 for a mesh's triangle, and left stale where a
    // primitive's crossing (keep_nearest, which spends nothing on it) replaced it: the record's leaf tells. On an
    // instance of a solid shape (part >= 0), its index in CompiledScene::solid_instances.
    vint4 instance{-1};
    // On an instance of a solid shape, the part hit. Set only by the CSG objects' fold and left stale where a later
    // crossing of a primitive replaced it: the solid instance record's leaf tells, as for `instance`.
    vint4 part{-1};
};

// A primitive's first crossing after t = 0 is its enter if that lies ahead, else its exit. Smaller t
// wins; at equal t the smaller leaf, i.e. the object earlier in the file.
TWINRAY_KERNEL void keep_nearest(Nearest4& nearest, const Span4& span, std::int32_t leaf_id) {
    vfloat4 zero(0.0f);
    vint4 leaf(leaf_id);
    vbool4 entering = span.enter > zero;
    vfloat4 t = select(entering, span.enter, span.exit);
    vint4 tag = select(entering, span.enter_face | vint4(tag_entering), span.exit_face);
    vbool4 earlier = mutated<Mutant::ties_to_later_object> ? nearest.leaf < leaf : leaf < nearest.leaf;
    vbool4 nearer = span.valid & (t > zero) & ((t < nearest.t) | ((t == nearest.t) & earlier));
    nearest.t = select(nearer, t, nearest.t);
    nearest.leaf = select(nearer, leaf, nearest.leaf);
    nearest.tag = select(nearer, tag, nearest.tag);
}

// A triangle's crossing, kept as keep_nearest keeps a primitive's: smaller t wins; at equal t the smaller
// leaf, and within one mesh the smaller triangle index. `instance`: the index of the instance whose shape's
// triangle it is (its leaf `leaf_id`), or -1 for a mesh's (`leaf_id` the record's).
TWINRAY_KERNEL void keep_nearest_triangle(Nearest4& nearest, const TriangleHit4& crossing, std::int32_t leaf_id,
                                          std::uint32_t triangle_index, std::uint32_t place, std::int32_t instance) {
    vint4 leaf(leaf_id);
    vint4 triangle(static_cast<std::int32_t>(triangle_index));
    vbool4 same_leaf = leaf == nearest.leaf;
    vbool4 earlier_leaf = mutated<Mutant::ties_to_later_object> ? nearest.leaf < leaf : leaf < nearest.leaf;
    vbool4 earlier = earlier_leaf | (same_leaf & (triangle < nearest.triangle));
    vbool4 nearer = crossing.valid & ((crossing.t < nearest.t) | ((crossing.t == nearest.t) & earlier));
    nearest.t = select(nearer, crossing.t, nearest.t);
    nearest.leaf = select(nearer, leaf, nearest.leaf);
    nearest.tag = select(nearer, select(crossing.front, vint4(tag_entering), vint4(0)), nearest.tag);
    nearest.triangle = select(nearer, triangle, nearest.triangle);
    nearest.place = select(nearer, vint4(static_cast<std::int32_t>(place)), nearest.place);
    nearest.instance = select(nearer, vint4(instance), nearest.instance);
}

// The packet's frame for triangles, made only where the scene has some: model only what the scene requires
// (a frame made for every packet of a scene without triangles cost spheres.json 6% more instructions).
template <typename P>
std::optional<ShearedRays> sheared_for(const CompiledScene& scene, const RayPacket& rays) {
    if (scene.triangles.items.empty()) {
        return std::nullopt;
    }
    return ShearedRays::of<P>(rays);
}

// Calls visit(span, id, transmission, list) for every primitive of every type present that some ray meets
// (`list`: its type's position in scene::PrimitiveTypes), list after list, each list's i-th primitive at
// place place_of(first, i) in it, `first` counting the primitives of the lists before. Primitives that no ray
// of the packet meets are skipped before any use of their span: in a coherent packet that is most of them.
template <typename P, typename PlaceOf, typename Visit>
void for_each_span_in_order(const PrimitiveLists& lists, const RayPacket& rays, PlaceOf&& place_of, Visit&& visit) {
    std::uint32_t list_index = 0;
    std::size_t first = 0;
    lists.for_each([&](const auto& list) {
        for (std::size_t i = 0; i < list.items.size(); ++i) {
            std::size_t place = place_of(first, i);
            Span4 span = span_of<P>(list.items[place], rays);
            if (any(span.valid)) {
                visit(span, list.ids[place], list.transmission[place], list_index);
            }
        }
        first += list.items.size();
        ++list_index;
    });
}

// for_each_span_in_order in the lists' own order.
template <typename P, typename Visit>
void for_each_span(const PrimitiveLists& lists, const RayPacket& rays, Visit&& visit) {
    for_each_span_in_order<P>(
        lists, rays, [](std::size_t, std::size_t i) { return i; }, visit);
}

// A CSG object's span list for one lane of a packet: every leaf's span computed for the whole packet
// (four rays per instruction), then the tree folded bottom-up per ray in stack arrays. An instance of a solid shape
// folds its shape's tree along the rays carried into the shape's space (unit_object_rays), t brought back; its spans'
// crossings name parts (named()).
template <typename P>
class CsgEvaluation {
public:
    CsgEvaluation(const CompiledScene& scene, const CsgObject& object, const RayPacket& rays) : tree_(*object.tree) {
        std::fill(valid_, valid_ + tree_.slot_leaf.size(), 0);  // leaves no ray meets are not visited
        if (object.instance < 0) {
            add_spans(rays, nullptr);
            return;
        }
        const InstanceRecord& record = scene.solid_instances[static_cast<std::size_t>(object.instance)];
        instance_leaf_ = record.leaf;
        math::Matrix3<vfloat4> inverse;
        for (int i = 0; i < 3; ++i) {
            inverse.row[i] = broadcast(record.to_world.inverse.row[i]);
        }
        UnitObjectRays object_rays = unit_object_rays<P>(inverse, broadcast(record.to_world.translation), rays);
        if (tree_.uses_inverse_direction) {
            object_rays.rays.template compute_inverse_direction<P>();
        }
        add_spans(object_rays.rays, &object_rays.shrink);
    }

    void evaluate(int lane, SpanArray& out) const { evaluate(lane, 0, out); }

    // What a crossing of the spans names: a leaf, or on an instance of a solid shape the instance's leaf and the part.
    struct Named {
        std::int32_t leaf, part;
    };
    Named named(const Crossing& crossing) const {
        return instance_leaf_ < 0 ? Named{crossing.leaf, -1} : Named{instance_leaf_, crossing.leaf};
    }

private:
    // `shrink`, for rays carried into a shape's space, brings each t back to the world's.
    void add_spans(const RayPacket& rays, const vfloat4* shrink) {
        for_each_span<P>(tree_.leaves, rays, [&](const Span4& span, std::int32_t slot, float, std::uint32_t) {
            (shrink != nullptr ? span.enter * *shrink : span.enter).store(enter_[slot]);
            (shrink != nullptr ? span.exit * *shrink : span.exit).store(exit_[slot]);
            span.enter_face.store(enter_face_[slot]);
            span.exit_face.store(exit_face_[slot]);
            valid_[slot] = movemask(span.valid);
        });
    }

    void evaluate(int lane, int node_index, SpanArray& out) const {
        const CsgNode& node = tree_.nodes[static_cast<std::size_t>(node_index)];
        if (node.slot >= 0) {
            out.clear();
            int slot = node.slot;
            if ((valid_[slot] >> lane) & 1) {
                std::int32_t leaf = tree_.slot_leaf[static_cast<std::size_t>(slot)];
                float enter = enter_[slot][lane];
                float exit = exit_[slot][lane];
                out.push({enter, std::isinf(enter) ? -1 : leaf, enter_face_[slot][lane]},
                         {exit, std::isinf(exit) ? -1 : leaf, exit_face_[slot][lane]});
            }
            return;
        }
        const int* children = &tree_.children_of[static_cast<std::size_t>(node.first_child)];
        SpanArray operand, scratch, other;
        SpanArray* accumulated = &out;
        SpanArray* combined = &other;
        evaluate(lane, children[0], *accumulated);
        for (int i = 1; i < node.child_count; ++i) {
            evaluate(lane, children[i], operand);
            csg_combine(node.op, *accumulated, operand, scratch, *combined);
            std::swap(accumulated, combined);
        }
        if (accumulated != &out) {
            out.assign(*accumulated);
        }
    }

    const CsgTree& tree_;
    std::int32_t instance_leaf_ = -1;
    alignas(16) float enter_[scene::max_csg_leaves][4];
    alignas(16) float exit_[scene::max_csg_leaves][4];
    alignas(16) std::int32_t enter_face_[scene::max_csg_leaves][4];
    alignas(16) std::int32_t exit_face_[scene::max_csg_leaves][4];
    int valid_[scene::max_csg_leaves];
};

// The lanes whose ray meets the object's bound somewhere in (0, limit).
template <typename P>
inline int lanes_meeting_bound(const CsgObject& object, const RayPacket& rays, vfloat4 limit) {
    Span4 span = span_of<P>(object.bound, rays);
    return movemask(rays.active & span.valid & (span.exit > vfloat4(0.0f)) & (span.enter < limit));
}

struct Hit4 {
    vbool4 hit;  // active lanes whose ray met a surface
    vfloat4 t;
    Vec3x4 point;   // re-projected onto the primitive's surface
    Vec3x4 normal;  // unit, facing the ray: the geometric normal, which decides sides and spawn offsets
    vint4 leaf;
    vint4 triangle;  // on a mesh, the triangle's index in it; else -1
    vint4 part;      // on an instance of a solid shape, the part hit; else -1
    vint4 material;  // index into CompiledScene::materials
    vbool4 entering;
    vfloat4 spawn_offset;  // how far off the surface secondary rays start
    // What shading uses: `normal`, or on a smooth mesh the interpolated normal turned to its side.
    Vec3x4 shading_normal;
};

template <typename P>
class NearestHit {
public:
    explicit NearestHit(const CompiledScene& scene) : scene_(scene) {}

    // `candidates` are the top-level primitives tested one by one: scene.flat(), or for primary rays the ones
    // of it a tile can see (TileCulling); with a BVH the rest are found through it. The nearest crossing is
    // the least (t, leaf) over the primitives met, whatever the order they are met in (keep_nearest).
    // `fallbacks`, if given, records whether the CSG objects were folded by brute force past capacity.
    Hit4 intersect(RayPacket& rays, const PrimitiveLists& candidates, Fallbacks* fallbacks = nullptr) const {
        if (scene_.any_inverse_direction) {
            rays.template compute_inverse_direction<P>();
        }
        Nearest4 nearest;
        auto keep = [&](const Span4& span, std::int32_t leaf, float, std::uint32_t) {
            keep_nearest(nearest, span, leaf);
        };
        for_each_span<P>(candidates, rays, keep);
        const std::optional<ShearedRays> sheared = sheared_for<P>(scene_, rays);
        auto keep_triangle = [&](const TriangleHit4& crossing, std::uint32_t place) {
            const TriangleRecord& record = scene_.triangles.items[place];
            keep_nearest_triangle(nearest, crossing, record.leaf, record.triangle, place, -1);
        };
        CsgCandidates csg;
        if (!scene_.bvh.empty()) {
            auto keep_and_fetch = [&](const Span4& span, std::int32_t leaf, float transmission, std::uint32_t list) {
                keep(span, leaf, transmission, list);
                prefetch_leaf(leaf);
            };
            csg.collect();
            vbool4 lanes = rays.active;
            const BvhRays box_rays = top_level_rays(scene_, rays);
            InstancesByDistance instances;
            for_each_leaf_met(scene_.bvh, scene_.bvh.items, box_rays, lanes, nearest.t, [&](BvhLeaf leaf) {
                for_each_span_in_leaf<P>(
                    scene_, leaf, rays, sheared, csg, keep_and_fetch, keep_triangle,
                    [&](std::uint32_t box_place) { meet_instance(rays, box_rays, box_place, nearest, &instances); });
                if (!instances.empty()) {
                    enter_nearest_first(rays, nearest, instances);
                }
                if (csg.nearly_full()) [[unlikely]] {
                    fold_held_csg(rays, nearest, csg);
                }
            });
        } else {
            if (sheared) {
                for_each_triangle_crossing<P>(scene_.triangles, *sheared, keep_triangle);
            }
            if (!scene_.instances.empty()) {
                const BvhRays box_rays = top_level_rays(scene_, rays);
                for (std::uint32_t i = 0; i < scene_.instance_boxes.size(); ++i) {
                    meet_instance(rays, box_rays, i, nearest, nullptr);
                }
            }
        }
        if (!scene_.csg_objects.empty()) {
            nearest_csg_crossings(rays, nearest, [&](auto&& visit) {
                csg.for_each(
                    scene_, [&] { collect_csg_again(scene_, rays, rays.active, nearest.t, csg); }, visit);
            });
            if (fallbacks != nullptr && csg.walked_again()) {
                fallbacks->csg_candidates = true;
            }
        }
        return finish(rays, nearest);
    }

    // Every crossing of lane 0's ray with t in (0, distance) by increasing (t, leaf, triangle), each completed as
    // intersect completes its nearest (re-projection, normal, spawn offset): what the tracer ABI's hits_along and
    // the watertightness suite read. The walk is intersect's, bounded by `distance`; a correctness tool, it
    // collects the crossings on the heap.
    template <typename Visit>
    void for_each_crossing(RayPacket& rays, float distance, Visit&& visit) const {
        if (scene_.any_inverse_direction) {
            rays.template compute_inverse_direction<P>();
        }
        struct Crossed {
            float t;
            std::int32_t leaf, tag, place, triangle, instance, part = -1;
        };
        std::vector<Crossed> crossed;
        auto ahead = [distance](float t) { return t > 0.0f && t < distance; };
        auto add_span = [&](const Span4& span, std::int32_t leaf, float, std::uint32_t) {
            if ((movemask(span.valid) & 1) == 0) {
                return;
            }
            alignas(16) std::int32_t enter_face[4], exit_face[4];
            span.enter_face.store(enter_face);
            span.exit_face.store(exit_face);
            if (const float enter = span.enter.lane(0); ahead(enter)) {
                crossed.push_back({enter, leaf, enter_face[0] | tag_entering, -1, -1, -1});
            }
            if (const float exit = span.exit.lane(0); ahead(exit)) {
                crossed.push_back({exit, leaf, exit_face[0], -1, -1, -1});
            }
        };
        auto add_triangle = [&](const TriangleHit4& crossing, std::int32_t leaf, std::uint32_t triangle,
                                std::uint32_t place, std::int32_t instance, bool mirrors) {
            if ((movemask(crossing.valid) & 1) == 0 || !ahead(crossing.t.lane(0))) {
                return;
            }
            const bool front = ((movemask(crossing.front) & 1) != 0) != mirrors;
            crossed.push_back({crossing.t.lane(0), leaf, front ? tag_entering : 0, static_cast<std::int32_t>(place),
                               static_cast<std::int32_t>(triangle), instance});
        };
        auto add_mesh_triangle = [&](const TriangleHit4& crossing, std::uint32_t place) {
            const TriangleRecord& record = scene_.triangles.items[place];
            add_triangle(crossing, record.leaf, record.triangle, place, -1, false);
        };
        auto add_instance = [&](const BvhRays& box_rays, std::uint32_t box_place) {
            const InstanceBox& box = scene_.instance_boxes[box_place];
            const InstanceRecord& instance = scene_.instances[box.record];
            const TriangleList& triangles = scene_.shapes[instance.shape].triangles;
            vbool4 lanes = rays.active;
            for_each_instance_crossing<P>(scene_, box, rays, box_rays, lanes, vfloat4(distance),
                                          [&](const TriangleHit4& crossing, std::uint32_t place) {
                                              add_triangle(crossing, instance.leaf, triangles.items[place].triangle,
                                                           place, static_cast<std::int32_t>(box.record),
                                                           instance.mirrors);
                                          });
        };
        for_each_span<P>(scene_.flat(), rays, add_span);
        const std::optional<ShearedRays> sheared = sheared_for<P>(scene_, rays);
        CsgCandidates csg;
        if (!scene_.bvh.empty()) {
            csg.collect();
            vbool4 lanes = rays.active;
            const BvhRays box_rays = top_level_rays(scene_, rays);
            for_each_leaf_met(scene_.bvh, scene_.bvh.items, box_rays, lanes, vfloat4(distance), [&](BvhLeaf leaf) {
                for_each_span_in_leaf<P>(scene_, leaf, rays, sheared, csg, add_span, add_mesh_triangle,
                                         [&](std::uint32_t box_place) { add_instance(box_rays, box_place); });
            });
        } else {
            if (sheared) {
                for_each_triangle_crossing<P>(scene_.triangles, *sheared, add_mesh_triangle);
            }
            if (!scene_.instances.empty()) {
                const BvhRays box_rays = top_level_rays(scene_, rays);
                for (std::uint32_t i = 0; i < scene_.instance_boxes.size(); ++i) {
                    add_instance(box_rays, i);
                }
            }
        }
        const vfloat4 limit(distance);
        auto walk_again = [&] { collect_csg_again(scene_, rays, rays.active, limit, csg); };
        csg.for_each(scene_, walk_again, [&](const CsgObject& object) {
            SpanArray spans;
            const CsgEvaluation<P> evaluation(scene_, object, rays);
            evaluation.evaluate(0, spans);
            auto add_end = [&](const Crossing& end, std::int32_t entering) {
                if (end.leaf >= 0 && ahead(end.t)) {
                    const auto named = evaluation.named(end);
                    crossed.push_back({end.t, named.leaf, end.tag | entering, -1, -1, object.instance, named.part});
                }
            };
            for (int i = 0; i < spans.count; ++i) {
                add_end(spans.enter[i], tag_entering);
                add_end(spans.exit[i], 0);
            }
        });
        std::stable_sort(crossed.begin(), crossed.end(), [](const Crossed& a, const Crossed& b) {
            return a.t < b.t ||
                   (a.t == b.t &&
                    (a.leaf < b.leaf ||
                     (a.leaf == b.leaf && (a.triangle < b.triangle || (a.triangle == b.triangle && a.part < b.part)))));
        });
        for (const Crossed& crossing : crossed) {
            Nearest4 one;
            one.t = vfloat4(crossing.t);
            one.leaf = vint4(crossing.leaf);
            one.tag = vint4(crossing.tag);
            one.place = vint4(crossing.place);
            one.triangle = vint4(crossing.triangle);
            one.instance = vint4(crossing.instance);
            one.part = vint4(crossing.part);
            visit(finish(rays, one));
        }
    }

private:
    // The instance whose box is at `box_place` in scene.instance_boxes, behind its box: entered now, or added to
    // `deferred` (a BVH leaf's instances, entered nearest first once the leaf's other items are tested). Out of line,
    // as is the entering: inlined, they made intersect() and its leaf loop larger for every scene, and scenes without
    // instances paid for it.
    __attribute__((noinline)) void meet_instance(const RayPacket& rays, const BvhRays& box_rays,
                                                 std::uint32_t box_place, Nearest4& nearest,
                                                 InstancesByDistance* deferred) const {
        const InstanceBox& box = scene_.instance_boxes[box_place];
        NodeTest met = test_instance_box(box, box_rays, rays.active, nearest.t);
        if (none(met.hit)) {
            return;
        }
        // The record (its 116 bytes over two or three cache lines) is read next, mostly once the leaf's other
        // items are tested: fetched from here, as at 100 000 instances it is a miss (3 % of the first hits' time).
        const char* record = reinterpret_cast<const char*>(&scene_.instances[box.record]);
        _mm_prefetch(record, _MM_HINT_T0);
        _mm_prefetch(record + 64, _MM_HINT_T0);
        _mm_prefetch(record + sizeof(InstanceRecord) - 1, _MM_HINT_T0);
        if (deferred == nullptr || !deferred->add(box.record, met)) {
            keep_crossings_inside(rays, box.record, met.hit, nearest);
        }
    }

    __attribute__((noinline)) void enter_nearest_first(const RayPacket& rays, Nearest4& nearest,
                                                       InstancesByDistance& instances) const {
        instances.enter_nearest_first(
            nearest.t, [&](std::uint32_t index, vbool4 lanes) { keep_crossings_inside(rays, index, lanes, nearest); });
    }

    // The crossings of the instance at `index` for `lanes`, which meet its box. They enter where the placed
    // triangle's front faces the ray: its shape's front, unless the transform mirrors.
    void keep_crossings_inside(const RayPacket& rays, std::uint32_t index, vbool4 lanes, Nearest4& nearest) const {
        const InstanceRecord& instance = scene_.instances[index];
        const TriangleList& triangles = scene_.shapes[instance.shape].triangles;
        for_each_crossing_inside<P>(
            scene_, instance, rays, lanes, nearest.t, [&](TriangleHit4 crossing, std::uint32_t place) {
                crossing.front = instance.mirrors ? !crossing.front : crossing.front;
                keep_nearest_triangle(nearest, crossing, instance.leaf, triangles.items[place].triangle, place,
                                      static_cast<std::int32_t>(index));
            });
    }

    // finish() reads the Leaf of each lane's nearest hit, which is in file order while a BVH's walk visits
    // primitives in leaf order: at a million primitives a cache miss per lane, a fifth of the first hits'
    // time, unless it is fetched while the walk goes on. Every primitive a ray meets may end up its nearest.
    // Without a BVH the primitives are tested in file order, the leaves' own: nothing to fetch ahead.
    void prefetch_leaf(std::int32_t leaf) const {
        const char* bytes = reinterpret_cast<const char*>(&scene_.leaves[static_cast<std::size_t>(leaf)]);
        _mm_prefetch(bytes, _MM_HINT_T0);
        _mm_prefetch(bytes + sizeof(Leaf) - 1, _MM_HINT_T0);
    }

    // Out of line, as a scene without CSG objects never calls it: inside the walk's leaf visit it grew the walk's code
    // and the instructions of a scene of spheres.
    [[gnu::noinline]] void fold_held_csg(const RayPacket& rays, Nearest4& nearest, CsgCandidates& csg) const {
        nearest_csg_crossings(rays, nearest, [&](auto&& visit) { csg.fold_held(scene_, visit); });
    }

    // Per lane: CSG objects whose bound the ray meets before its nearest hit so far. With a BVH, the
    // candidates are the objects whose box some lane met before its nearest primitive: a superset of those
    // whose bound passes the test below, so the same objects change the answer. `for_each_candidate(visit)` visits
    // them (all at once, or those held so far): the least (t, leaf) does not depend on the order.
    template <typename ForEachCandidate>
    void nearest_csg_crossings(const RayPacket& rays, Nearest4& nearest, ForEachCandidate&& for_each_candidate) const {
        alignas(16) float t[4];
        alignas(16) std::int32_t leaf[4], tag[4], instance[4], part[4];
        nearest.t.store(t);
        nearest.leaf.store(leaf);
        nearest.tag.store(tag);
        nearest.instance.store(instance);
        nearest.part.store(part);
        for_each_candidate([&](const CsgObject& object) {
            int lanes = lanes_meeting_bound<P>(object, rays, vfloat4::load(t));
            if (lanes == 0) {
                return;
            }
            CsgEvaluation<P> evaluation(scene_, object, rays);
            for (int lane = 0; lane < 4; ++lane) {
                if (((lanes >> lane) & 1) == 0) {
                    continue;
                }
                SpanArray spans;
                evaluation.evaluate(lane, spans);
                for (int i = 0; i < spans.count; ++i) {
                    bool entering = spans.enter[i].t > 0.0f;
                    const Crossing& crossing = entering ? spans.enter[i] : spans.exit[i];
                    if (!(crossing.t > 0.0f)) {
                        continue;
                    }
                    const auto named = evaluation.named(crossing);
                    if (crossing.leaf >= 0 &&
                        (crossing.t < t[lane] || (crossing.t == t[lane] && named.leaf < leaf[lane]))) {
                        t[lane] = crossing.t;
                        leaf[lane] = named.leaf;
                        tag[lane] = crossing.tag | (entering ? tag_entering : 0);
                        instance[lane] = object.instance;
                        part[lane] = named.part;
                    }
                    break;
                }
            }
        });
        nearest.t = vfloat4::load(t);
        nearest.leaf = vint4::load(leaf);
        nearest.tag = vint4::load(tag);
        nearest.instance = vint4::load(instance);
        nearest.part = vint4::load(part);
    }

    // The surface of each lane's hit from its primitive's header (outward_normal, surface_anchor): the
    // normal's direction, whether it still needs normalising, and where the point re-projects to.
    struct LaneSurface {
        Vec3 outward{0.0f, 0.0f, 1.0f};
        bool needs_normalizing = false;
        SurfaceAnchor anchor;
    };

    // The surface of a lane's hit on `leaf`, as `surface_of` presents its primitive's surface.
    template <typename SurfaceOf>
    static LaneSurface lane_surface_from(const Leaf& leaf, std::int32_t tag, Vec3 point, SurfaceOf&& surface_of) {
        LaneSurface out;
        std::int32_t face = tag & tag_face_mask;
        bool flipped = (tag & tag_flipped) != 0;
        std::visit(
            [&](const auto& primitive) {
                if constexpr (!std::is_same_v<std::decay_t<decltype(primitive)>, MeshSurface>) {
                    const auto& surface = surface_of(primitive);
                    out.outward = outward_normal(surface, face, point, out.needs_normalizing);
                    out.anchor = surface_anchor(surface, face, flipped ? -1.0f : 1.0f, point);
                }
            },
            leaf.surface);
        if (flipped) {
            out.outward = -out.outward;
        }
        return out;
    }

    static LaneSurface lane_surface(const Leaf& leaf, std::int32_t tag, Vec3 point) {
        return lane_surface_from(
            leaf, tag, point, [](const auto& surface) -> const auto& { return surface; });
    }

    // A part of the solid shape that `placed` places: its surface in the shape's space, under the instance's
    // transform. Out of line, so that finish() keeps lane_surface inline: one function for both, with a branch on
    // `placed`, was called out of line and cost a scene of spheres 7% more instructions.
    [[gnu::noinline]] static LaneSurface part_surface(const Leaf& part, std::int32_t tag, Vec3 point,
                                                      const InstanceRecord& placed) {
        return lane_surface_from(part, tag, point, [&placed](const auto& surface) {
            return PlacedPartSurface<std::decay_t<decltype(surface)>>(surface, placed.to_world, placed.norms);
        });
    }

    // The surfaces of the triangles the lanes of `lanes` hit (at places `place`), four at once: the unit normal
    // of the side each ray met (its front where `front`) and its plane's projection (reference/triangle.h's
    // surface_point, in float). The textbook operations of the scalar code lane by lane (three divisions,
    // IEEE square roots), so each lane rounds as one triangle alone would; lanes outside `lanes` repeat a hit
    // lane's triangle and are not read.
    struct TriangleSurfaces4 {
        Vec3x4 outward, anchor;
        vfloat4 own_rounding, size_bound, point_factor;
    };

    TriangleSurfaces4 triangle_surfaces(const std::int32_t place[4], int lanes, vbool4 front,
                                        const Vec3x4& point) const {
        const TriangleRecord* record[4];
        const int first = __builtin_ctz(static_cast<unsigned>(lanes));
        for (int lane = 0; lane < 4; ++lane) {
            int from = ((lanes >> lane) & 1) != 0 ? lane : first;
            record[lane] = &scene_.triangles.items[static_cast<std::size_t>(place[from])];
        }
        Vec3x4 a = vertex_of_four(record, &TriangleRecord::a), b = vertex_of_four(record, &TriangleRecord::b),
               c = vertex_of_four(record, &TriangleRecord::c);
        auto length = [](const Vec3x4& v) { return sqrt(math::dot(v, v)); };
        Vec3x4 n = math::cross(b - a, c - a);
        Vec3x4 normal = n / length(n);
        vfloat4 longest = max(length(b - a), max(length(c - b), length(a - c)));
        math::SurfaceBounds<float> bounds = scene::surface_bounds_of_triangle(1.0f);
        TriangleSurfaces4 out;
        out.outward = select(front, normal, -normal);
        out.anchor = point + math::dot(a - point, normal) * normal;
        out.own_rounding = vfloat4(bounds.own_rounding.size) * longest +
                           vfloat4(bounds.own_rounding.point_factor) * max_abs_component(point);
        out.size_bound = vfloat4(bounds.spawn_offset.size) * longest;
        out.point_factor = vfloat4(bounds.spawn_offset.point_factor);
        return out;
    }

    // The hits of the lanes of `lanes` on instances (lane i on instance[i], the triangle at place[i] in its shape),
    // four at once: triangle_surfaces' rule in object space, carried through each lane's own transform as
    // transformed.h's surface_anchor carries a primitive's: the normal of the side the ray met through the inverse
    // transpose (not yet unit), the point re-projected in object space and carried back as the anchor itself (radius
    // 0, no own rounding), the spawn offset carried through both trips (scene::transformed_spawn_offset). The scalar
    // rule's operations lane by lane, so each lane rounds as one hit alone would. Lanes outside `lanes` repeat a hit
    // lane's instance and are not read.
    struct InstanceSurfaces4 {
        Vec3x4 outward, anchor;
        vfloat4 spawn_offset;
    };

    InstanceSurfaces4 instance_surfaces(const std::int32_t instance[4], const std::int32_t place[4], int lanes,
                                        vbool4 entering, const Vec3x4& point) const {
        const InstanceRecord* record[4];
        const float *frame[4], *vertex[4];
        int mirrors = 0;
        const int first = __builtin_ctz(static_cast<unsigned>(lanes));
        for (int lane = 0; lane < 4; ++lane) {
            const int from = ((lanes >> lane) & 1) != 0 ? lane : first;
            record[lane] = &scene_.instances[static_cast<std::size_t>(instance[from])];
            const CompiledShape& shape = scene_.shapes[record[lane]->shape];
            const auto at = static_cast<std::size_t>(place[from]);
            frame[lane] = &shape.frames[at].normal.x;
            vertex[lane] = &shape.triangles.items[at].a.x;
            mirrors |= record[lane]->mirrors ? 1 << lane : 0;
        }
        // Each record's L, L⁻¹, t and norms are its first 26 floats: read four at a time into lanes.
        static_assert(sizeof(math::Transform<float>) == 21 * sizeof(float) &&
                      offsetof(InstanceRecord, norms) == sizeof(math::Transform<float>) &&
                      sizeof(scene::TransformNorms<float>) == 5 * sizeof(float) && sizeof(InstanceRecord) >= 28 * 4);
        vfloat4 column[28];
        for (int block = 0; block < 7; ++block) {
            const float* at[4];
            for (int lane = 0; lane < 4; ++lane) {
                at[lane] = reinterpret_cast<const float*>(record[lane]) + 4 * block;
            }
            const Transposed4 columns = load_transposed(at);
            for (int k = 0; k < 4; ++k) {
                column[4 * block + k] = columns.column[k];
            }
        }
        math::Transform<vfloat4> m;
        for (int row = 0; row < 3; ++row) {
            m.linear.row[row] = {column[3 * row], column[3 * row + 1], column[3 * row + 2]};
            m.inverse.row[row] = {column[9 + 3 * row], column[10 + 3 * row], column[11 + 3 * row]};
        }
        m.translation = {column[18], column[19], column[20]};
        const scene::TransformNorms<vfloat4> norms{column[21], column[22], column[23], column[24], column[25]};
        const Transposed4 frames = load_transposed(frame), vertices = load_transposed(vertex);
        const Vec3x4 normal{frames.column[0], frames.column[1], frames.column[2]};
        const vfloat4 longest = frames.column[3];
        const Vec3x4 a{vertices.column[0], vertices.column[1], vertices.column[2]};

        const math::SurfaceBounds<float> bounds = scene::surface_bounds_of_triangle(1.0f);
        const Vec3x4 object_point = m.point_to_object(point);
        const Vec3x4 anchor = object_point + math::dot(a - object_point, normal) * normal;
        const vfloat4 own_rounding = vfloat4(bounds.own_rounding.size) * longest +
                                     vfloat4(bounds.own_rounding.point_factor) * max_abs_component(object_point);
        const Vec3x4 projected =
            select(abs(math::dot(normal, object_point - anchor)) > own_rounding, anchor, object_point);
        const vbool4 unmoved =
            (projected.x == object_point.x) & (projected.y == object_point.y) & (projected.z == object_point.z);
        const Vec3x4 world = select(unmoved, point, m.point_to_world(projected));
        const vfloat4 extent = max_abs_component(projected);
        const vfloat4 object_offset =
            vfloat4(bounds.spawn_offset.size) * longest + vfloat4(bounds.spawn_offset.point_factor) * extent;
        const vbool4 mirrored = lanes_of(mirrors);
        const vbool4 front = select_mask(mirrored, !entering, entering);
        const Vec3x4 side = select(front, normal, -normal);
        InstanceSurfaces4 out;
        out.outward = mutated<Mutant::transformed_normal_through_matrix> ? m.linear * side : m.normal_to_world(side);
        out.anchor = world;
        out.spawn_offset =
            scene::transformed_spawn_offset<vfloat4, float>(norms, object_offset, extent, max_abs_component(world));
        return out;
    }

    // reference/triangle.h's shading_normal for an instance: the shape's at the point's object-space image, through
    // the inverse transpose, unit, and turned to `facing` in the world.
    Vec3 smooth_normal(const InstanceRecord& instance, std::uint32_t place, Vec3 point, Vec3 facing) const {
        const math::Transform<float>& m = instance.to_world;
        const CompiledShape& shape = scene_.shapes[instance.shape];
        const TriangleRecord& t = shape.triangles.items[place];
        Vec3 object_front = math::normalize(math::cross(t.b - t.a, t.c - t.a));
        Vec3 unit = math::normalize(m.normal_to_world(
            smooth_normal(shape.mesh, shape.triangles, place, m.point_to_object(point), object_front)));
        return math::dot(unit, facing) < 0.0f ? -unit : unit;
    }

    // reference/triangle.h's shading_normal, in float: the vertex normals weighted by the sub-triangles' areas
    // at `point`, turned to `facing`; `facing` where they cancel. The triangle at `place` in `triangles`.
    static Vec3 smooth_normal(const CompiledMesh& mesh, const TriangleList& triangles, std::uint32_t place, Vec3 point,
                              Vec3 facing) {
        const TriangleRecord& t = triangles.items[place];
        const std::array<std::uint32_t, 3>& corners = triangles.corners[place];
        Vec3 n = math::cross(t.b - t.a, t.c - t.a);
        float area = math::dot(n, n);
        float weight_a = math::dot(n, math::cross(t.c - t.b, point - t.b)) / area;
        float weight_b = math::dot(n, math::cross(t.a - t.c, point - t.c)) / area;
        float weight_c = 1.0f - weight_a - weight_b;
        Vec3 interpolated = weight_a * mesh.normals[corners[0]] + weight_b * mesh.normals[corners[1]] +
                            weight_c * mesh.normals[corners[2]];
        if (!(math::dot(interpolated, interpolated) > 0.0f)) {
            return facing;
        }
        Vec3 unit = math::normalize(interpolated);
        return math::dot(unit, facing) < 0.0f ? -unit : unit;
    }

    // Whether records[index] is the instance whose leaf a lane's nearest hit names: Nearest4's instance and part are
    // left stale where a primitive's crossing replaced an instance's (and an index may be a mesh instance's or a
    // solid one's), but leaves are unique.
    static bool names(const LargeArray<InstanceRecord>& records, std::int32_t index, std::int32_t leaf) {
        return index >= 0 && static_cast<std::size_t>(index) < records.size() &&
               records[static_cast<std::size_t>(index)].leaf == leaf;
    }

    Hit4 finish(const RayPacket& rays, const Nearest4& nearest) const {
        Hit4 hit;
        hit.hit = rays.active & !(nearest.leaf == vint4(-1));
        if (none(hit.hit)) {
            return hit;
        }
        hit.t = nearest.t;
        const Vec3x4& direction = rays.direction;
        hit.point = rays.origin + hit.t * direction;
        hit.leaf = nearest.leaf;
        hit.entering = {
            _mm_castsi128_ps(_mm_cmpeq_epi32((nearest.tag & vint4(tag_entering)).m, vint4(tag_entering).m))};
        alignas(16) float point[3][4], normal[3][4], anchor[3][4], radius[4], own_rounding[4], size_bound[4],
            point_factor[4];
        alignas(16) std::int32_t leaf[4], tag[4], curved[4], place[4], triangle[4] = {-1, -1, -1, -1}, material[4] = {};
        for (int axis = 0; axis < 3; ++axis) {
            hit.point[axis].store(point[axis]);
        }
        nearest.leaf.store(leaf);
        nearest.tag.store(tag);
        nearest.place.store(place);
        alignas(16) std::int32_t instance[4], part[4], part_hit[4] = {-1, -1, -1, -1};
        nearest.instance.store(instance);
        nearest.part.store(part);
        int lanes = movemask(hit.hit);
        const CompiledMesh* smooth[4] = {};
        const InstanceRecord* smooth_instance[4] = {};
        int triangle_lanes = 0, instance_lanes = 0;
        for (int lane = 0; lane < 4; ++lane) {
            LaneSurface surface;
            if ((lanes >> lane) & 1) {
                Vec3 lane_point{point[0][lane], point[1][lane], point[2][lane]};
                if (part[lane] >= 0 && names(scene_.solid_instances, instance[lane], leaf[lane])) {
                    const InstanceRecord& record = scene_.solid_instances[static_cast<std::size_t>(instance[lane])];
                    const Leaf& info = scene_.solids[record.shape].parts[static_cast<std::size_t>(part[lane])];
                    material[lane] = scene_.part_material(instance[lane], part[lane]);
                    surface = part_surface(info, tag[lane], lane_point, record);
                    part_hit[lane] = part[lane];
                } else if (names(scene_.instances, instance[lane], leaf[lane])) {
                    const InstanceRecord& record = scene_.instances[static_cast<std::size_t>(instance[lane])];
                    const auto at = static_cast<std::uint32_t>(place[lane]);
                    const CompiledShape& shape = scene_.shapes[record.shape];
                    instance_lanes |= 1 << lane;
                    triangle[lane] = static_cast<std::int32_t>(shape.triangles.items[at].triangle);
                    material[lane] = record.material;
                    smooth_instance[lane] = shape.mesh.normals.empty() ? nullptr : &record;
                } else {
                    const Leaf& info = scene_.leaves[static_cast<std::size_t>(leaf[lane])];
                    material[lane] = info.material;
                    if (const auto* mesh = std::get_if<MeshSurface>(&info.surface)) {
                        triangle_lanes |= 1 << lane;
                        triangle[lane] = static_cast<std::int32_t>(
                            scene_.triangles.items[static_cast<std::size_t>(place[lane])].triangle);
                        const CompiledMesh& compiled = scene_.meshes[mesh->mesh];
                        smooth[lane] = compiled.normals.empty() ? nullptr : &compiled;
                    } else {
                        surface = lane_surface(info, tag[lane], lane_point);
                    }
                }
            }
            for (int axis = 0; axis < 3; ++axis) {
                normal[axis][lane] = surface.outward[axis];
                anchor[axis][lane] = surface.anchor.anchor[axis];
            }
            curved[lane] = surface.needs_normalizing ? -1 : 0;
            radius[lane] = surface.anchor.radius;
            own_rounding[lane] = surface.anchor.own_rounding;
            size_bound[lane] = surface.anchor.spawn_offset.size;
            point_factor[lane] = surface.anchor.spawn_offset.point_factor;
        }
        Vec3x4 outward{vfloat4::load(normal[0]), vfloat4::load(normal[1]), vfloat4::load(normal[2])};
        Vec3x4 anchors{vfloat4::load(anchor[0]), vfloat4::load(anchor[1]), vfloat4::load(anchor[2])};
        vfloat4 radii = vfloat4::load(radius);
        vfloat4 own_roundings = vfloat4::load(own_rounding), size_bounds = vfloat4::load(size_bound),
                point_factors = vfloat4::load(point_factor);
        if (triangle_lanes != 0) {
            TriangleSurfaces4 triangles = triangle_surfaces(place, triangle_lanes, hit.entering, hit.point);
            vbool4 on_triangle = lanes_of(triangle_lanes);
            outward = select(on_triangle, triangles.outward, outward);
            anchors = select(on_triangle, triangles.anchor, anchors);
            radii = select(on_triangle, vfloat4(0.0f), radii);
            own_roundings = select(on_triangle, triangles.own_rounding, own_roundings);
            size_bounds = select(on_triangle, triangles.size_bound, size_bounds);
            point_factors = select(on_triangle, triangles.point_factor, point_factors);
        }
        if (instance_lanes != 0) {
            InstanceSurfaces4 instances = instance_surfaces(instance, place, instance_lanes, hit.entering, hit.point);
            vbool4 on_instance = lanes_of(instance_lanes);
            outward = select(on_instance, instances.outward, outward);
            anchors = select(on_instance, instances.anchor, anchors);
            radii = select(on_instance, vfloat4(0.0f), radii);
            own_roundings = select(on_instance, vfloat4(0.0f), own_roundings);
            size_bounds = select(on_instance, instances.spawn_offset, size_bounds);
            point_factors = select(on_instance, vfloat4(0.0f), point_factors);
        }
        vbool4 normalize_lanes = vbool4{_mm_castsi128_ps(vint4::load(curved).m)} | lanes_of(instance_lanes);
        if (any(normalize_lanes)) {
            // As the reference's radial_normal: a radial vector of exactly zero (a primitive smaller than
            // the ulp where it stands) has no direction; the ray's reverse stands in for it, not a NaN.
            vbool4 degenerate = dot<P>(outward, outward) == vfloat4(0.0f);
            outward = select(normalize_lanes, normalize<P>(select(degenerate, -direction, outward)), outward);
        }
        // Re-projected onto the surface where measurably off it: p is |n̂·(p − anchor)| from the anchor
        // along n̂ and p' is |radius| (0 on flat faces, whose anchor is p' itself).
        vfloat4 off_surface = abs(abs(dot<P>(outward, hit.point - anchors)) - abs(radii));
        if constexpr (!mutated<Mutant::no_reprojection>) {
            hit.point = select(off_surface > own_roundings, anchors + radii * outward, hit.point);
        }
        hit.spawn_offset = size_bounds + point_factors * max_abs_component(hit.point);
        if constexpr (mutated<Mutant::spawn_offset_too_small>) {
            hit.spawn_offset = hit.spawn_offset * vfloat4(0x1p-20f);
        }
        vbool4 facing_away = dot<P>(outward, direction) > vfloat4(0.0f);
        hit.normal = select(mutated<Mutant::normal_faces_away> ? !facing_away : facing_away, -outward, outward);
        hit.triangle = vint4::load(triangle);
        hit.part = vint4::load(part_hit);
        hit.material = vint4::load(material);
        hit.shading_normal = hit.normal;
        if (smooth[0] != nullptr || smooth[1] != nullptr || smooth[2] != nullptr || smooth[3] != nullptr ||
            smooth_instance[0] != nullptr || smooth_instance[1] != nullptr || smooth_instance[2] != nullptr ||
            smooth_instance[3] != nullptr) {
            alignas(16) float shading[3][4];
            for (int axis = 0; axis < 3; ++axis) {
                hit.normal[axis].store(shading[axis]);
                hit.point[axis].store(point[axis]);
            }
            for (int lane = 0; lane < 4; ++lane) {
                if (smooth[lane] == nullptr && smooth_instance[lane] == nullptr) {
                    continue;
                }
                const auto at = static_cast<std::uint32_t>(place[lane]);
                const Vec3 lane_point{point[0][lane], point[1][lane], point[2][lane]};
                const Vec3 facing{shading[0][lane], shading[1][lane], shading[2][lane]};
                Vec3 turned = smooth[lane] != nullptr
                                  ? smooth_normal(*smooth[lane], scene_.triangles, at, lane_point, facing)
                                  : smooth_normal(*smooth_instance[lane], at, lane_point, facing);
                for (int axis = 0; axis < 3; ++axis) {
                    shading[axis][lane] = turned[axis];
                }
            }
            hit.shading_normal = {vfloat4::load(shading[0]), vfloat4::load(shading[1]), vfloat4::load(shading[2])};
        }
        return hit;
    }

    const CompiledScene& scene_;
};

}  // namespace twinray::sse
