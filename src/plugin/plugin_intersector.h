// A plug-in as the reference's external intersector (reference/external.h): `twinray render --tracer plugin:PATH`
// shades in double with twinray's own shading, asking the plug-in for every ray, one ray per call.
#pragma once

#include "plugin/plugin.h"
#include "reference/external.h"

#include <limits>
#include <optional>
#include <vector>

namespace twinray::plugin {

class PluginIntersector final : public reference::ExternalIntersector<double> {
public:
    explicit PluginIntersector(const BuiltScene& built) : built_(built) {}

    double unit_roundoff() const override { return built_.plugin().unit_roundoff(); }

    std::optional<reference::ExternalCrossing<double>> nearest(const reference::Ray<double>& ray) const override {
        const Hit hit = built_.nearest(ray.origin, ray.direction, 0, std::numeric_limits<double>::infinity());
        if (!hit.hit) {
            return std::nullopt;
        }
        return crossing(hit);
    }

    std::vector<reference::ExternalCrossing<double>> crossings(const reference::Ray<double>& ray,
                                                               double distance) const override {
        std::vector<reference::ExternalCrossing<double>> all;
        for (const Hit& hit : built_.hits_along(ray.origin, ray.direction, 0, distance)) {
            all.push_back(crossing(hit));
        }
        return all;
    }

private:
    static reference::ExternalCrossing<double> crossing(const Hit& hit) {
        return {hit.t, hit.leaf, hit.triangle, hit.normal, hit.entering};
    }

    const BuiltScene& built_;
};

}  // namespace twinray::plugin
