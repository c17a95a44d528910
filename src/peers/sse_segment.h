// The tracer ABI's two queries over twinray's SSE tracer, for a ray with a range t_min < t < t_max: what its plug-in
// (peers/sse_tracer.cpp) answers and the judges' direct path (plugin/direct_sse.cpp) asks, one code for both.
#pragma once

#include "sse/tracer.h"

#include <algorithm>
#include <optional>
#include <vector>

namespace twinray::peers {

// A ray in double as the SSE tracer takes it: the direction rounded to float.
inline sse::Ray sse_ray(const scene::Vec3& origin, const scene::Vec3& direction) {
    return {origin, sse::Vec3(direction)};
}

// The crossings up to t_max rounded to float, which are exactly those below t_max, past t_min.
inline std::vector<sse::Hit> crossings_within(const sse::Tracer& tracer, const sse::Ray& ray, double t_min,
                                              double t_max) {
    std::vector<sse::Hit> all = tracer.hits_along(ray, static_cast<float>(t_max));
    all.erase(std::remove_if(all.begin(), all.end(), [&](const sse::Hit& hit) { return !(hit.t > t_min); }), all.end());
    return all;
}

// From t = 0 the tracer's own nearest hit; from a later t_min, the first crossing past it.
inline std::optional<sse::Hit> nearest_within(const sse::Tracer& tracer, const sse::Ray& ray, double t_min,
                                              double t_max) {
    std::optional<sse::Hit> nearest;
    if (t_min <= 0) {
        nearest = tracer.intersect(ray);
    } else if (std::vector<sse::Hit> along = crossings_within(tracer, ray, t_min, t_max); !along.empty()) {
        nearest = along.front();
    }
    return nearest && nearest->t < t_max ? nearest : std::nullopt;
}

}  // namespace twinray::peers
