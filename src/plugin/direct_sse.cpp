#include "plugin/direct_sse.h"

#include "peers/sse_segment.h"
#include "sse/cpu.h"

#include <stdexcept>

namespace twinray::plugin {
namespace {

class DirectSseScene final : public JudgedScene {
public:
    explicit DirectSseScene(const scene::Scene& scene)
        : tracer_(scene), instance_of_leaf_(scene.leaf_paths.size(), -1) {
        int instance = 0;
        for (const scene::Mesh& mesh : scene.meshes) {
            if (mesh.placement) {
                instance_of_leaf_[static_cast<std::size_t>(mesh.leaf)] = instance++;
            }
        }
    }

    void intersect(std::span<const twinray_ray> rays, std::span<Hit> hits) const override {
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const twinray_ray& ray = rays[i];
            const std::optional<sse::Hit> nearest =
                peers::nearest_within(tracer_, peers::sse_ray(origin_of(ray), direction_of(ray)), ray.t_min, ray.t_max);
            hits[i] = nearest ? judged(*nearest) : Hit{};
        }
    }

    std::vector<Hit> hits_along(const scene::Vec3& origin, const scene::Vec3& direction, double t_min,
                                double t_max) const override {
        std::vector<Hit> all;
        for (const sse::Hit& hit : peers::crossings_within(tracer_, peers::sse_ray(origin, direction), t_min, t_max)) {
            all.push_back(judged(hit));
        }
        return all;
    }

private:
    // As the plug-in gives it: the tracer's normal faces the ray, the outward one is it where the ray enters.
    // Barycentrics are the plug-in's own work and no judge reads them.
    Hit judged(const sse::Hit& hit) const {
        const float side = hit.entering ? 1.0f : -1.0f;
        const sse::Vec3 outward = side * hit.normal;
        return {true,
                hit.leaf,
                hit.triangle,
                instance_of_leaf_[static_cast<std::size_t>(hit.leaf)],
                hit.t,
                scene::Vec3(outward),
                0,
                0,
                hit.entering};
    }

    sse::Tracer tracer_;
    std::vector<int> instance_of_leaf_;
};

}  // namespace

DirectSse::DirectSse() {
    if (!sse::cpu_supports_sse41()) {
        throw std::runtime_error(sse::missing_sse41_message());
    }
}

std::string DirectSse::description() const {
    return "twinray sse, called directly (every kind, CSG included; unit roundoff 5.96e-08; thread-safe)";
}

std::unique_ptr<JudgedScene> DirectSse::build(const scene::Scene& scene) const {
    return std::make_unique<DirectSseScene>(scene);
}

}  // namespace twinray::plugin
