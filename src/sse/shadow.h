// Shadow rays of four lanes at once: the share of a light that reaches each lane's surface point. Only
// the SSE tracer's own translation units (built with -msse4.1) include this.
#pragma once

#include "sse/mutation.h"
#include "sse/nearest_hit.h"

#include <algorithm>
#include <limits>

namespace twinray::sse {

// The crossings of a packet's shadow rays through primitives and triangles found in any order (through the
// BVH), to be multiplied in brute force's order, (type list, id), triangles last by their mesh's leaf: float
// multiplication is not associative, and this keeps the product the same bit for bit. The triangles of one mesh
// need no order among them: each multiplies a lane by the mesh's one transmission or by exactly 1. A primitive
// no lane crosses would multiply by exactly 1, so it is left out. Past `capacity` crossings (no heap allocation
// per ray) those of the smallest keys are held, and the rest are met again by another walk once those are
// multiplied (for_each_in_rounds): a shadow ray along a row of a field of glass spheres crosses hundreds, and brute
// force over every primitive took three quarters of such a render's time.
class TransmissionFactors {
public:
    static constexpr int capacity = 128;
    struct Factor {
        std::uint32_t list;
        std::int32_t id;  // increasing in file order within its list; a triangle's mesh's leaf
        vbool4 enter_between, exit_between;
        float transmission;
    };

    void add(const Factor& factor) {
        if (earlier(factor, next_round_from_)) {
            return;  // multiplied in an earlier round
        }
        if (count_ < capacity) {
            factors_[count_++] = factor;
            return;
        }
        more_ = true;
        Factor* largest = std::max_element(factors_, factors_ + count_, earlier);
        if (earlier(factor, *largest)) {
            *largest = factor;
        }
    }
    // Whether for_each_in_rounds needed more than one round (a walk again).
    bool walked_again() const { return rounds_ > 1; }

    // visit(factor) for every factor in list order, in rounds: after a round that could not hold them all, the factors
    // of the largest key held wait (some of that key may have been dropped) and walk_again() meets every crossing
    // again, of which only those from that key on are kept. Every key below the largest held is whole: a factor is
    // dropped only where its key is at least the largest held, which only falls. False, having visited nothing
    // more, where a round holds one key alone (a mesh crossed at more than `capacity` triangles): then the caller
    // multiplies by brute force, and must not have multiplied what was visited.
    template <typename WalkAgain, typename Visit>
    bool for_each_in_rounds(WalkAgain&& walk_again, Visit&& visit) {
        for (;;) {
            std::sort(factors_, factors_ + count_, earlier);
            if (!more_) {
                std::for_each(factors_, factors_ + count_, visit);
                return true;
            }
            const Factor waiting = factors_[count_ - 1];
            const Factor* whole_end = std::lower_bound(factors_, factors_ + count_, waiting, earlier);
            if (whole_end == factors_) {
                return false;
            }
            std::for_each(static_cast<const Factor*>(factors_), whole_end, visit);
            next_round_from_ = waiting;
            count_ = 0;
            more_ = false;
            ++rounds_;
            walk_again();
        }
    }

private:
    static bool earlier(const Factor& a, const Factor& b) {
        return a.list < b.list || (a.list == b.list && a.id < b.id);
    }

    Factor factors_[capacity];
    int count_ = 0;
    bool more_ = false;  // more crossings met than held
    Factor next_round_from_{0, std::numeric_limits<std::int32_t>::min(), none_true(), none_true(), 0.0f};
    int rounds_ = 1;
};

// for_each_span over scene.primitives in file order, the order brute force multiplies shadow rays'
// transmissions in: the lists' own without a BVH, through bvh.file_order with one (the lists are then in
// leaf order).
template <typename P, typename Visit>
void for_each_span_in_file_order(const CompiledScene& scene, const RayPacket& rays, Visit&& visit) {
    if (scene.bvh.empty()) {
        for_each_span<P>(scene.primitives, rays, visit);
        return;
    }
    for_each_span_in_order<P>(
        scene.primitives, rays, [&](std::size_t first, std::size_t i) { return scene.bvh.file_order[first + i]; },
        visit);
}

// for_each_triangle_crossing in file order: the list's own without a BVH, through triangles.file_order with one.
template <typename P, typename Visit>
void for_each_triangle_crossing_in_file_order(const TriangleList& triangles, const ShearedRays& rays, Visit&& visit) {
    if (triangles.file_order.empty()) {
        for_each_triangle_crossing<P>(triangles, rays, visit);
        return;
    }
    for (std::uint32_t place : triangles.file_order) {
        TriangleHit4 crossing = triangle_crossing<P>(triangles.items[place], rays);
        if (any(crossing.valid)) {
            visit(crossing, place);
        }
    }
}

// Model only what the scene requires: without transparent materials a shadow ray stops at its first
// blocker (any crossing at all closes the lane); with them, transmissions multiply along the ray.
template <typename P>
class ShadowTransmittance {
public:
    explicit ShadowTransmittance(const CompiledScene& scene) : scene_(scene) {}

    // Per lane, the product of the transmission of every surface crossed strictly between origin and
    // light; lanes outside `lanes` get 0. `fallbacks`, if given, records which brute-force fallbacks ran.
    vfloat4 operator()(const Vec3x4& origin, Vec3 light_position, vbool4 lanes, Fallbacks* fallbacks = nullptr) const {
        Vec3x4 to_light = broadcast(light_position) - origin;
        vfloat4 squared_distance = dot<P>(to_light, to_light);
        vfloat4 inverse_distance = inverse_sqrt<P>(squared_distance);
        vfloat4 distance = P::fast_rsqrt ? squared_distance * inverse_distance : sqrt(squared_distance);
        Vec3x4 direction = inverse_distance * to_light;
        RayPacket rays(origin, direction, lanes);
        if (scene_.any_inverse_direction) {
            rays.template compute_inverse_direction<P>();
        }
        vfloat4 zero(0.0f), one(1.0f);
        vfloat4 transmittance = select(lanes, one, zero);
        vbool4 open = lanes;  // lanes not yet fully blocked
        auto crossings_between = [&](const Span4& span, vbool4& enter_between, vbool4& exit_between) {
            enter_between = span.valid & (span.enter > zero) & (span.enter < distance);
            exit_between = span.valid & (span.exit > zero) & (span.exit < distance);
        };
        const std::optional<ShearedRays> sheared = sheared_for<P>(scene_, rays);
        // A triangle is crossed once, at t > 0 (crossing_of): it counts where that is before the light.
        auto triangle_between = [&](const TriangleHit4& crossing) { return crossing.valid & (crossing.t < distance); };
        CsgCandidates csg;
        if (!scene_.any_transparency) {
            auto block = [&](const Span4& span, std::int32_t, float, std::uint32_t) {
                if (none(open)) {
                    return;
                }
                vbool4 enter_between, exit_between;
                crossings_between(span, enter_between, exit_between);
                open = open & !(enter_between | exit_between);
            };
            auto block_triangle = [&](const TriangleHit4& crossing, std::uint32_t) {
                open = open & !triangle_between(crossing);
            };
            auto block_instance = [&](const BvhRays& box_rays, std::uint32_t box_place) {
                if (any(open)) {
                    for_each_instance_crossing<P>(scene_, scene_.instance_boxes[box_place], rays, box_rays, open,
                                                  distance, block_triangle);
                }
            };
            for_each_span<P>(scene_.flat(), rays, block);
            if (!scene_.bvh.empty() && any(open)) {
                csg.collect();
                const BvhRays box_rays = top_level_rays(scene_, rays);
                for_each_leaf_met(scene_.bvh, scene_.bvh.items, box_rays, open, distance, [&](BvhLeaf leaf) {
                    for_each_span_in_leaf<P>(scene_, leaf, rays, sheared, csg, block, block_triangle,
                                             [&](std::uint32_t box_place) { block_instance(box_rays, box_place); });
                    if (csg.nearly_full()) [[unlikely]] {
                        fold_held_csg(rays, distance, open, csg);
                    }
                });
            } else if (scene_.bvh.empty()) {
                if (sheared && any(open)) {
                    for_each_triangle_crossing<P>(scene_.triangles, *sheared, block_triangle);
                }
                if (!scene_.instances.empty()) {
                    const BvhRays box_rays = top_level_rays(scene_, rays);
                    for (std::uint32_t i = 0; i < scene_.instance_boxes.size(); ++i) {
                        block_instance(box_rays, i);
                    }
                }
            }
        } else {
            auto multiply = [&](vbool4 enter_between, vbool4 exit_between, float transmission) {
                vfloat4 surface(mutated<Mutant::shadow_transmission_ignored> ? 1.0f : transmission);
                transmittance =
                    transmittance * select(enter_between, surface, one) * select(exit_between, surface, one);
            };
            bool multiplied = false;
            if (!scene_.bvh.empty()) {
                TransmissionFactors factors;
                auto record = [&](const Span4& span, std::int32_t id, float transmission, std::uint32_t list) {
                    vbool4 enter_between, exit_between;
                    crossings_between(span, enter_between, exit_between);
                    if (any(enter_between | exit_between)) {
                        factors.add({list, id, enter_between, exit_between, transmission});
                    }
                };
                auto record_triangle = [&](const TriangleHit4& crossing, std::uint32_t place) {
                    vbool4 between = triangle_between(crossing);
                    if (any(between)) {
                        std::int32_t leaf = scene_.triangles.items[place].leaf;
                        factors.add({triangle_list, leaf, between, none_true(), material_transmission(leaf)});
                    }
                };
                const BvhRays box_rays = top_level_rays(scene_, rays);
                auto record_instance = [&](std::uint32_t box_place) {
                    const InstanceBox& box = scene_.instance_boxes[box_place];
                    const InstanceRecord& instance = scene_.instances[box.record];
                    for_each_instance_crossing<P>(
                        scene_, box, rays, box_rays, lanes, distance, [&](const TriangleHit4& crossing, std::uint32_t) {
                            vbool4 between = triangle_between(crossing);
                            if (any(between)) {
                                factors.add(
                                    {instance_list, instance.leaf, between, none_true(), transmission_of(instance)});
                            }
                        });
                };
                // Every crossing recorded, and the leaves' CSG objects added to `met_csg`: `csg` the first time, a
                // collector thrown away on a walk again, whose CSG objects are already held.
                auto walk = [&](CsgCandidates& met_csg) {
                    for_each_span<P>(scene_.flat(), rays, record);
                    vbool4 all_lanes = lanes;
                    for_each_leaf_met(scene_.bvh, scene_.bvh.items, box_rays, all_lanes, distance, [&](BvhLeaf leaf) {
                        for_each_span_in_leaf<P>(scene_, leaf, rays, sheared, met_csg, record, record_triangle,
                                                 record_instance);
                    });
                };
                csg.collect();
                walk(csg);
                multiplied = factors.for_each_in_rounds(
                    [&] {
                        CsgCandidates thrown_away;
                        walk(thrown_away);
                    },
                    [&](const TransmissionFactors::Factor& factor) {
                        multiply(factor.enter_between, factor.exit_between, factor.transmission);
                    });
                if (!multiplied) {
                    transmittance = select(lanes, one, zero);
                }
                if (fallbacks != nullptr && (factors.walked_again() || !multiplied)) {
                    fallbacks->transmission_factors = true;
                }
            }
            if (!multiplied) {
                for_each_span_in_file_order<P>(scene_, rays,
                                               [&](const Span4& span, std::int32_t, float transmission, std::uint32_t) {
                                                   vbool4 enter_between, exit_between;
                                                   crossings_between(span, enter_between, exit_between);
                                                   multiply(enter_between, exit_between, transmission);
                                               });
                if (sheared) {
                    for_each_triangle_crossing_in_file_order<P>(
                        scene_.triangles, *sheared, [&](const TriangleHit4& crossing, std::uint32_t place) {
                            multiply(triangle_between(crossing), none_true(),
                                     material_transmission(scene_.triangles.items[place].leaf));
                        });
                }
                if (!scene_.instances.empty()) {
                    const BvhRays box_rays = top_level_rays(scene_, rays);
                    // In file order, the records' own, whatever order the boxes are in.
                    for (std::uint32_t record = 0; record < scene_.instances.size(); ++record) {
                        const float transmission = transmission_of(scene_.instances[record]);
                        for_each_instance_crossing<P>(scene_, instance_box(scene_, record), rays, box_rays, lanes,
                                                      distance, [&](const TriangleHit4& crossing, std::uint32_t) {
                                                          multiply(triangle_between(crossing), none_true(),
                                                                   transmission);
                                                      });
                    }
                }
            }
            open = open & (transmittance > zero);
        }
        transmittance = select(open, transmittance, zero);
        if (scene_.csg_objects.empty() || none(open)) {
            return transmittance;
        }
        alignas(16) float product[4];
        transmittance.store(product);
        multiply_csg(rays, distance, open, product, [&](auto&& visit) {
            csg.for_each(
                scene_, [&] { collect_csg_again(scene_, rays, lanes, distance, csg); }, visit);
        });
        if (fallbacks != nullptr && csg.walked_again()) {
            fallbacks->csg_candidates = true;
        }
        return vfloat4::load(product);
    }

private:
    // Closes the `open` lanes that cross a CSG object held: opaque, whichever object a ray crosses first closes its
    // lane, in any order. Out of line, as NearestHit::fold_held_csg: a scene without CSG objects never calls it.
    [[gnu::noinline]] void fold_held_csg(const RayPacket& rays, vfloat4 distance, vbool4& open,
                                         CsgCandidates& csg) const {
        alignas(16) float product[4];
        select(open, vfloat4(1.0f), vfloat4(0.0f)).store(product);
        multiply_csg(rays, distance, open, product, [&](auto&& visit) { csg.fold_held(scene_, visit); });
        open = open & (vfloat4::load(product) > vfloat4(0.0f));
    }

    // Multiplies product[lane] by the transmission of each surface of the CSG objects `for_each_candidate(visit)`
    // visits that an `open` lane's ray crosses before `distance`, object after object in the order visited.
    template <typename ForEachCandidate>
    void multiply_csg(const RayPacket& rays, vfloat4 distance, vbool4 open, float product[4],
                      ForEachCandidate&& for_each_candidate) const {
        for_each_candidate([&](const CsgObject& object) {
            int met = lanes_meeting_bound<P>(object, rays, distance) & movemask(open);
            if (met == 0) {
                return;
            }
            CsgEvaluation<P> evaluation(scene_, object, rays);
            alignas(16) float limit[4];
            distance.store(limit);
            for (int lane = 0; lane < 4; ++lane) {
                if (((met >> lane) & 1) == 0 || product[lane] == 0.0f) {
                    continue;
                }
                SpanArray spans;
                evaluation.evaluate(lane, spans);
                for (int i = 0; i < spans.count; ++i) {
                    for (const Crossing* crossing : {&spans.enter[i], &spans.exit[i]}) {
                        if (crossing->leaf >= 0 && crossing->t > 0.0f && crossing->t < limit[lane]) {
                            product[lane] *= object.instance < 0 ? material_transmission(crossing->leaf)
                                                                 : part_transmission(object.instance, crossing->leaf);
                        }
                    }
                }
            }
        });
    }

    float material_transmission(std::int32_t leaf) const {
        const Leaf& info = scene_.leaves[static_cast<std::size_t>(leaf)];
        return scene_.materials[static_cast<std::size_t>(info.material)].transmission;
    }
    float part_transmission(std::int32_t instance, std::int32_t part) const {
        return scene_.materials[static_cast<std::size_t>(scene_.part_material(instance, part))].transmission;
    }
    float transmission_of(const InstanceRecord& instance) const {
        return scene_.materials[static_cast<std::size_t>(instance.material)].transmission;
    }

    const CompiledScene& scene_;
};

}  // namespace twinray::sse
