// What the per-ray judges (plugin/conformance.h) ask of a tracer, whichever it is: a plug-in behind the tracer ABI
// (plugin/plugin.h) or twinray's SSE tracer called directly (plugin/direct_sse.h). A judge never knows which it
// holds, so that the same judges give the SSE tracer's verdicts both ways and the two can be held equal.
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "twinray/tracer.h"

namespace twinray::plugin {

// A tracer's hit in twinray's terms: `leaf` the scene's, `triangle` -1 off a mesh, `instance` the index among the
// scene's instances (the meshes with a placement, in order) or -1. `normal`: unit, outward (a triangle's front).
struct Hit {
    bool hit = false;
    int leaf = -1;
    int triangle = -1;
    int instance = -1;
    double t = 0;
    scene::Vec3 normal{};
    double u = 0, v = 0;
    bool entering = false;
};

// A ray as the ABI passes it, and back.
inline twinray_ray abi_ray(const scene::Vec3& origin, const scene::Vec3& direction, double t_min, double t_max) {
    return {{origin.x, origin.y, origin.z}, {direction.x, direction.y, direction.z}, t_min, t_max};
}
inline scene::Vec3 origin_of(const twinray_ray& ray) {
    return {ray.origin[0], ray.origin[1], ray.origin[2]};
}
inline scene::Vec3 direction_of(const twinray_ray& ray) {
    return {ray.direction[0], ray.direction[1], ray.direction[2]};
}

// A tracer's structure for one scene.
class JudgedScene {
public:
    virtual ~JudgedScene() = default;
    // The nearest hit of each ray (hits.size() == rays.size()) with t in the ray's range.
    virtual void intersect(std::span<const twinray_ray> rays, std::span<Hit> hits) const = 0;
    // Every hit with t_min < t < t_max, by increasing t.
    virtual std::vector<Hit> hits_along(const scene::Vec3& origin, const scene::Vec3& direction, double t_min,
                                        double t_max) const = 0;
};

class JudgedTracer {
public:
    virtual ~JudgedTracer() = default;
    // One line: name, version, what it intersects, its unit roundoff, whether it is thread-safe.
    virtual std::string description() const = 0;
    virtual double unit_roundoff() const = 0;
    // The kinds `scene` holds that the tracer does not intersect ("csg", "instances", ...): a case over such a
    // scene is skipped.
    virtual std::vector<std::string> missing_kinds(const scene::Scene& scene) const = 0;
    virtual std::unique_ptr<JudgedScene> build(const scene::Scene& scene) const = 0;
};

}  // namespace twinray::plugin
