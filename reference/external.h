// An intersector other than the reference's own: a tracer behind the tracer ABI (plugin/plugin_intersector.h). Given
// one, the reference asks it for every ray it traces — primary, shadow, reflected, refracted — and shades, shadows,
// spawns and controls depth from its answers as from its own, so that an image's difference from the oracle's
// belongs to the intersector alone.
#pragma once

#include "reference/ray.h"

#include <optional>
#include <vector>

namespace twinray::reference {

template <typename T>
struct ExternalCrossing {
    T t{};
    int leaf = -1;
    int triangle = -1;       // on a mesh, the triangle's index in it (its shape's, for an instance)
    Vec3<T> outward_normal;  // unit; a triangle's front
    bool entering = false;
};

template <typename T>
class ExternalIntersector {
public:
    virtual ~ExternalIntersector() = default;
    // Of the arithmetic its crossings are found in: the reference widens its spawn offsets by its ratio to T's.
    virtual T unit_roundoff() const = 0;
    // The nearest crossing with t > 0, ties to the smaller leaf.
    virtual std::optional<ExternalCrossing<T>> nearest(const Ray<T>& ray) const = 0;
    // Every crossing with 0 < t < distance, by increasing t.
    virtual std::vector<ExternalCrossing<T>> crossings(const Ray<T>& ray, T distance) const = 0;
};

}  // namespace twinray::reference
