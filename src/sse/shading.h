// Whitted shading of four rays at once: materials, lights and shadows, Phong, reflection and Snell's
// refraction, secondary rays continuing as packets under a mask of the lanes that spawn them. Only the SSE
// tracer's own translation units (built with -msse4.1) include this.
#pragma once

#include "sse/mutation.h"
#include "sse/nearest_hit.h"
#include "sse/ray_tree_recording.h"
#include "sse/shadow.h"

#include <array>
#include <cmath>

namespace twinray::sse {

// The material of each lane's hit, gathered once per hit.
struct Material4 {
    Vec3x4 color;
    vfloat4 ambient, diffuse, phong, phong_size, reflection, transmission, ior;
    std::array<int, 4> index;  // in CompiledScene::materials; 0 where a lane has no hit
};

using LaneShares = std::array<scene::RayShare, 4>;

// The trees of a packet's four pixels as they are traced: rays counted, what the depth control left out of
// each lane's tree, the recording of lane 0's.
struct PacketWalk {
    std::uint64_t rays = 0;
    std::array<scene::PixelLedger, 4> ledgers;
    RayTree* tree = nullptr;
};

// Four primary rays' shares: each lane is a pixel with the whole budget.
inline LaneShares primary_shares() {
    LaneShares shares;
    shares.fill(scene::DepthControl::primary());
    return shares;
}

inline vfloat4 from_lanes(const float lanes[4]) {
    return vfloat4(_mm_setr_ps(lanes[0], lanes[1], lanes[2], lanes[3]));
}

// The reference's rule (docs/reference-tracer.md): start off the surface on the side the ray leaves to,
// by the hit's spawn_offset (SurfaceAnchor).
inline Vec3x4 spawn_origin(const Hit4& hit, const Vec3x4& direction) {
    vfloat4 side = select(dot<ExactPrecision>(direction, hit.normal) >= vfloat4(0.0f), vfloat4(1.0f), vfloat4(-1.0f));
    return hit.point + (side * hit.spawn_offset) * hit.normal;
}

template <typename P>
class PacketTracer {
public:
    explicit PacketTracer(const CompiledScene& scene) : scene_(scene), nearest_hit_(scene), shadow_(scene) {}

    Hit4 intersect(RayPacket& rays, const PrimitiveLists& candidates) const {
        return nearest_hit_.intersect(rays, candidates);
    }
    Hit4 intersect(RayPacket& rays) const { return intersect(rays, scene_.flat()); }

    // `walk.tree`, if given, records lane 0's ray as a `kind` child of node `parent`, and all it spawns.
    Vec3x4 trace(RayPacket& rays, int depth, const LaneShares& shares, PacketWalk& walk,
                 RayKind kind = RayKind::primary, int parent = -1) const {
        return trace(rays, scene_.flat(), depth, shares, walk, kind, parent);
    }

    Vec3x4 trace(RayPacket& rays, const PrimitiveLists& candidates, int depth, const LaneShares& shares,
                 PacketWalk& walk, RayKind kind = RayKind::primary, int parent = -1) const {
        walk.rays += lane_count(rays.active);
        int active = movemask(rays.active);
        for (int lane = 0; lane < 4; ++lane) {
            walk.ledgers[static_cast<std::size_t>(lane)].traced += static_cast<std::uint32_t>((active >> lane) & 1);
        }
        Hit4 hit = intersect(rays, candidates);
        RayTree* tree = walk.tree;
        int node = tree != nullptr ? record_ray(*tree, kind, depth, parent, rays, hit, scene_.origin) : -1;
        Vec3x4 background = broadcast(scene_.background);
        if (none(hit.hit)) {
            if (tree != nullptr) {
                record_total_color(*tree, node, background);
            }
            return background;
        }
        Vec3x4 color = select(hit.hit, shade(rays, hit, depth, shares, walk, node), background);
        if (tree != nullptr) {
            record_total_color(*tree, node, color);
        }
        return color;
    }

private:
    Material4 gather_material(const Hit4& hit) const {
        alignas(16) std::int32_t material[4];
        hit.material.store(material);
        int lanes = movemask(hit.hit);
        float values[10][4] = {};
        std::array<int, 4> index{};
        for (int lane = 0; lane < 4; ++lane) {
            if (((lanes >> lane) & 1) == 0) {
                continue;
            }
            index[static_cast<std::size_t>(lane)] = material[lane];
            const Material& m = scene_.materials[static_cast<std::size_t>(material[lane])];
            const float fields[10] = {m.color.x, m.color.y,    m.color.z,    m.ambient,      m.diffuse,
                                      m.phong,   m.phong_size, m.reflection, m.transmission, m.ior};
            for (int field = 0; field < 10; ++field) {
                values[field][lane] = fields[field];
            }
        }
        return {{from_lanes(values[0]), from_lanes(values[1]), from_lanes(values[2])},
                from_lanes(values[3]),
                from_lanes(values[4]),
                from_lanes(values[5]),
                from_lanes(values[6]),
                from_lanes(values[7]),
                from_lanes(values[8]),
                from_lanes(values[9]),
                index};
    }

    // max(0, R·L)^phong_size per lane; the power is scalar (SSE has none), computed only where needed.
    static vfloat4 phong_power(vfloat4 cosine, vfloat4 exponent, vbool4 lanes) {
        alignas(16) float base[4], power[4], result[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        max(vfloat4(0.0f), cosine).store(base);
        exponent.store(power);
        int mask = movemask(lanes);
        for (int lane = 0; lane < 4; ++lane) {
            if ((mask >> lane) & 1) {
                result[lane] = std::pow(base[lane], power[lane] + (mutated<Mutant::phong_exponent_off_by_one> ? 1 : 0));
            }
        }
        return vfloat4::load(result);
    }

    // I = ambient·C·ambient_light + Σ_lights shadow·(diffuse·C·Lc·(N·L) + phong·Lc·max(0, R·L)^phong_size)
    //   + reflection·I(reflected) + transmission·I(refracted)          (docs/scene-format.md, "Shading")
    // `node`: lane 0's ray in walk.tree, if recording.
    Vec3x4 shade(const RayPacket& rays, const Hit4& hit, int depth, const LaneShares& shares, PacketWalk& walk,
                 int node) const {
        RayTree* tree = walk.tree;
        Material4 m = gather_material(hit);
        vfloat4 zero(0.0f);
        const Vec3x4& direction = rays.direction;
        Vec3x4 color = m.ambient * (m.color * broadcast(scene_.ambient_light));
        const Vec3x4& shading = hit.shading_normal;
        Vec3x4 mirror = direction - (vfloat4(2.0f) * dot<P>(direction, shading)) * shading;
        vbool4 has_phong = hit.hit & (m.phong > zero);
        for (const Light& light : scene_.lights) {
            Vec3x4 to_light = normalize<P>(broadcast(light.position) - hit.point);
            vfloat4 lambert = dot<P>(shading, to_light);
            vbool4 lit = hit.hit & (lambert > zero);
            if (none(lit)) {
                if (tree != nullptr) {
                    record_light_facing_away(*tree, node, lambert);
                }
                continue;
            }
            walk.rays += lane_count(lit);
            vfloat4 shadow = shadow_(spawn_origin(hit, to_light), light.position, lit);
            if (tree != nullptr) {
                record_light<P>(*tree, node, lambert, lit, spawn_origin(hit, to_light), light.position, shadow,
                                scene_.origin);
            }
            vbool4 reached = lit & (shadow > zero);
            if (none(reached)) {
                continue;
            }
            Vec3x4 light_color = broadcast(light.color);
            Vec3x4 diffuse = (m.diffuse * lambert) * (m.color * light_color);
            vfloat4 highlight = zero;
            if (any(has_phong & reached)) {
                highlight = m.phong * phong_power(dot<P>(mirror, to_light), m.phong_size, has_phong & reached);
            }
            color = select(reached, color + shadow * (diffuse + highlight * light_color), color);
        }
        if (tree != nullptr) {
            record_local_color(*tree, node, color);
        }
        if (mutated<Mutant::depth_limit_off_by_one> ? depth > scene_.max_depth : depth >= scene_.max_depth) {
            return color;
        }
        // Each lane's children are traced only if the depth control admits them (scene/depth_control.h).
        const scene::DepthControl& control = scene_.depth_control;
        std::array<std::uint32_t, 4> traced_before_children;
        for (std::size_t lane = 0; lane < 4; ++lane) {
            traced_before_children[lane] = walk.ledgers[lane].traced;
        }
        vfloat4 reflection = select(hit.hit, m.reflection, zero);
        vbool4 transparent = hit.hit & (m.transmission > zero);
        vbool4 total_internal = none_true();
        if (scene_.any_transparency && any(transparent)) {
            vfloat4 eta = mutated<Mutant::snell_ratio_inverted> ? select(hit.entering, m.ior, reciprocal<P>(m.ior))
                                                                : select(hit.entering, reciprocal<P>(m.ior), m.ior);
            vfloat4 cos_incident = -dot<P>(direction, shading);
            vfloat4 sin2_transmitted = eta * eta * (vfloat4(1.0f) - cos_incident * cos_incident);
            total_internal = transparent & (sin2_transmitted > vfloat4(1.0f));
            if constexpr (!mutated<Mutant::total_internal_reflection_lost>) {
                reflection = reflection + select(total_internal, m.transmission, zero);
            }
            LaneShares children;
            vbool4 refracting = admit(
                transparent & !total_internal,
                [&](std::size_t lane) { return control.refracted(shares[lane], m.index[lane]); }, depth + 1, walk,
                RayKind::refracted, node, children);
            if (any(refracting)) {
                vfloat4 cos_transmitted = sqrt(max(vfloat4(1.0f) - sin2_transmitted, zero));
                Vec3x4 refracted = normalize<P>(eta * direction + (eta * cos_incident - cos_transmitted) * shading);
                color = color + select(refracting, m.transmission, zero) * trace_secondary(hit, refracted, refracting,
                                                                                           children, depth, walk,
                                                                                           RayKind::refracted, node);
            }
        }
        int total_internal_lanes = movemask(total_internal);
        LaneShares children;
        vbool4 reflecting = admit(
            reflection > zero,
            [&](std::size_t lane) {
                return control.reflected(shares[lane], m.index[lane], ((total_internal_lanes >> lane) & 1) != 0,
                                         walk.ledgers[lane].traced - traced_before_children[lane]);
            },
            depth + 1, walk, RayKind::reflected, node, children);
        if (any(reflecting)) {
            color =
                color + select(reflecting, reflection, zero) *
                            trace_secondary(hit, mirror, reflecting, children, depth, walk, RayKind::reflected, node);
        }
        return color;
    }

    // The lanes of `lanes` whose child ray the depth control traces, with their shares in `children`
    // (share_of(lane)); each other lane's ledger is charged with its ray, recorded for lane 0.
    template <typename ShareOf>
    vbool4 admit(vbool4 lanes, ShareOf&& share_of, int depth, PacketWalk& walk, RayKind kind, int parent,
                 LaneShares& children) const {
        int candidates = movemask(lanes);
        std::int32_t admitted[4] = {0, 0, 0, 0};
        for (std::size_t lane = 0; lane < 4; ++lane) {
            if (((candidates >> lane) & 1) == 0) {
                continue;
            }
            children[lane] = share_of(lane);
            scene::DropReason reason = scene_.depth_control.decide(children[lane], depth, walk.ledgers[lane]);
            if (reason == scene::DropReason::traced) {
                admitted[lane] = -1;
            } else if (lane == 0 && walk.tree != nullptr && parent >= 0) {
                record_dropped(*walk.tree, parent, kind, depth, children[lane], scene_.depth_control,
                               reason == scene::DropReason::budget);
            }
        }
        return lanes_from(admitted);
    }

    Vec3x4 trace_secondary(const Hit4& hit, const Vec3x4& direction, vbool4 lanes, const LaneShares& shares, int depth,
                           PacketWalk& walk, RayKind kind, int parent) const {
        Vec3x4 origin = spawn_origin(hit, direction);
        RayPacket rays(origin, direction, lanes);
        Vec3x4 color = trace(rays, depth + 1, shares, walk, kind, parent);
        return select(lanes, color, Vec3x4{});
    }

    const CompiledScene& scene_;
    NearestHit<P> nearest_hit_;
    ShadowTransmittance<P> shadow_;
};

}  // namespace twinray::sse
