// Recording the ray tree (twinray probe) of lane 0, where the per-ray API runs its one ray, through the
// same RayTree calls as the reference. The tracing code calls these only when it has a tree (one null
// test); they are cold, out of the packets' way. Points are recorded in world coordinates: the compiled
// scene's origin added in double (`origin`).
#pragma once

#include "render/ray_tree.h"
#include "scene/depth_control.h"
#include "sse/nearest_hit.h"

namespace twinray::sse {

inline Vec3d lane0(const Vec3x4& v) {
    return recorded(lane(v, 0));
}

inline Vec3d lane0_in_world(const Vec3x4& point, const scene::Vec3& origin) {
    return origin + lane0(point);
}

// The node of lane 0's ray, or -1 when lane 0 is not active (then nothing below it is recorded).
[[gnu::cold]] inline int record_ray(RayTree& tree, RayKind kind, int depth, int parent, const RayPacket& rays,
                                    const Hit4& hit, const scene::Vec3& origin) {
    if ((movemask(rays.active) & 1) == 0) {
        return -1;
    }
    int index = tree.add(kind, depth, parent, lane0_in_world(rays.origin, origin), lane0(rays.direction));
    if (movemask(hit.hit) & 1) {
        alignas(16) std::int32_t leaf[4], triangle[4], part[4];
        hit.leaf.store(leaf);
        hit.triangle.store(triangle);
        hit.part.store(part);
        tree.set_hit(index, leaf[0], triangle[0], part[0], static_cast<double>(hit.t.lane(0)),
                     lane0_in_world(hit.point, origin), lane0(hit.normal), (movemask(hit.entering) & 1) != 0);
    }
    return index;
}

// Lane 0's light: facing away (not in `lit`: no shadow ray), else its shadow ray and transmittance.
template <typename P>
[[gnu::cold]] void record_light(RayTree& tree, int node, vfloat4 lambert, vbool4 lit, const Vec3x4& shadow_origin,
                                Vec3 light_position, vfloat4 transmittance, const scene::Vec3& origin) {
    if (node < 0) {
        return;
    }
    double n_dot_l = static_cast<double>(lambert.lane(0));
    if ((movemask(lit) & 1) == 0) {
        tree.add_light_facing_away(node, n_dot_l);
        return;
    }
    tree.add_light(node, n_dot_l, static_cast<double>(transmittance.lane(0)), lane0_in_world(shadow_origin, origin),
                   lane0(normalize<P>(broadcast(light_position) - shadow_origin)));
}

[[gnu::cold]] inline void record_light_facing_away(RayTree& tree, int node, vfloat4 lambert) {
    if (node >= 0) {
        tree.add_light_facing_away(node, static_cast<double>(lambert.lane(0)));
    }
}

[[gnu::cold]] inline void record_local_color(RayTree& tree, int node, const Vec3x4& color) {
    if (node >= 0) {
        tree.set_local_color(node, lane0(color));
    }
}

[[gnu::cold]] inline void record_total_color(RayTree& tree, int node, const Vec3x4& color) {
    if (node >= 0) {
        tree.set_total_color(node, lane0(color));
    }
}

[[gnu::cold]] inline void record_dropped(RayTree& tree, int parent, RayKind kind, int depth,
                                         const scene::RayShare& share, const scene::DepthControl& control,
                                         bool for_budget) {
    tree.add_dropped(parent, kind, depth, share.weight, share.weight * control.radiance_bound(depth), for_budget);
}

}  // namespace twinray::sse
