#include "accuracy/ray_accuracy.h"

#include "math/camera.h"
#include "scene/geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <variant>

namespace twinray::accuracy {
namespace {

template <typename V>
RefVec to_double(const V& v) {
    return {static_cast<double>(v[0]), static_cast<double>(v[1]), static_cast<double>(v[2])};
}

template <typename H>
FirstHit first_hit(const H& hit) {
    return {hit.leaf, static_cast<double>(hit.t), to_double(hit.point), to_double(hit.normal), hit.entering, hit.part};
}

template <typename T>
FirstHitOf reference_first_hits(const reference::Tracer<T>& tracer, int width, int height) {
    return [&tracer, width, height](int x, int y) -> std::optional<FirstHit> {
        auto hit = tracer.intersect(tracer.primary_ray(x, y, width, height));
        return hit ? std::optional<FirstHit>(first_hit(*hit)) : std::nullopt;
    };
}

// The value at share q of the sorted values (nearest rank).
double quantile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) {
        return 0;
    }
    auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
    return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}

bool same_answer(const std::optional<RefHit>& a, const std::optional<RefHit>& b) {
    if (a.has_value() != b.has_value())
        return false;
    if (!a)
        return true;
    return a->leaf == b->leaf && a->part == b->part && angle_between(a->normal, b->normal) <= normal_bound_radians;
}

}  // namespace

FirstHitOf first_hits_of(const reference::Tracer<double>& tracer, int width, int height) {
    return reference_first_hits(tracer, width, height);
}

FirstHitOf first_hits_of(const reference::Tracer<float>& tracer, int width, int height) {
    return reference_first_hits(tracer, width, height);
}

FirstHitOf first_hits_of(const sse::Tracer& tracer, int width, int height) {
    return [&tracer, width, height](int x, int y) -> std::optional<FirstHit> {
        auto hit = tracer.intersect(tracer.primary_ray(x, y, width, height));
        return hit ? std::optional<FirstHit>(first_hit(*hit)) : std::nullopt;
    };
}

FirstHitOf first_hits_of(const tracing::AnyTracer& tracer, int width, int height) {
    return [&tracer, width, height](int x, int y) -> std::optional<FirstHit> {
        const tracing::FirstHit hit = tracer.primary_hit(x, y, width, height);
        return hit.hit
                   ? std::optional<FirstHit>({hit.leaf, hit.t, RefVec{hit.point.x, hit.point.y, hit.point.z},
                                              RefVec{hit.normal.x, hit.normal.y, hit.normal.z}, hit.entering, hit.part})
                   : std::nullopt;
    };
}

std::vector<std::optional<FirstHit>> all_first_hits(const FirstHitOf& tracer, int width, int height) {
    std::vector<std::optional<FirstHit>> hits;
    hits.reserve(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            hits.push_back(tracer(x, y));
        }
    }
    return hits;
}

double angle_between(RefVec a, RefVec b) {
    return std::atan2(reference::length(reference::cross(a, b)), reference::dot(a, b));
}

double largest_coordinate(const scene::Scene& scene) {
    double largest =
        std::max(scene::largest_coordinate(scene.camera.eye), scene::largest_coordinate(scene.camera.look_at));
    for (const scene::Object& object : scene.objects) {
        largest = std::max(largest, scene::largest_coordinate(object));
    }
    return largest;
}

RefRay reference_ray_at(const scene::Scene& scene, double px, double py, int width, int height) {
    using reference::Vec3;
    math::CameraBasis<double> camera = math::camera_basis(
        Vec3<double>(scene.camera.eye), Vec3<double>(scene.camera.look_at), Vec3<double>(scene.camera.up),
        scene.camera.fov_deg, [](Vec3<double> v) { return reference::normalize(v); });
    double half_height = camera.half_width * height / width;
    double u = (2.0 * px / width - 1.0) * camera.half_width;
    double v = (1.0 - 2.0 * py / height) * half_height;
    return {camera.eye, reference::normalize(camera.forward + u * camera.right + v * camera.up)};
}

namespace {

// Whether `differs` holds for the reference's answer to any of the four rays shifted by band_pixels from
// pixel (x, y)'s centre on the image plane: the one walk both bands take.
template <typename Differs>
bool any_shifted_ray(const reference::Tracer<double>& reference, const scene::Scene& scene, int x, int y, int width,
                     int height, Differs&& differs) {
    const double shifts[4][2] = {{band_pixels, 0}, {-band_pixels, 0}, {0, band_pixels}, {0, -band_pixels}};
    for (const auto& shift : shifts) {
        if (differs(
                reference.intersect(reference_ray_at(scene, x + 0.5 + shift[0], y + 0.5 + shift[1], width, height)))) {
            return true;
        }
    }
    return false;
}

}  // namespace

bool in_silhouette_band(const reference::Tracer<double>& reference, const scene::Scene& scene, int x, int y, int width,
                        int height, const std::optional<RefHit>& centre) {
    return any_shifted_ray(reference, scene, x, y, width, height,
                           [&](const std::optional<RefHit>& shifted) { return !same_answer(centre, shifted); });
}

bool in_triangle_band(const reference::Tracer<double>& reference, const scene::Scene& scene, int x, int y, int width,
                      int height, const RefHit& centre) {
    return any_shifted_ray(reference, scene, x, y, width, height, [&](const std::optional<RefHit>& shifted) {
        return !shifted || shifted->leaf != centre.leaf || shifted->triangle != centre.triangle;
    });
}

RayAccuracy measure_rays(const std::vector<std::optional<FirstHit>>& expected, const FirstHitOf& actual, int width,
                         int height) {
    RayAccuracy accuracy;
    std::vector<double> t_relative;
    double max_angle = 0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::optional<FirstHit>& want =
                expected[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)];
            std::optional<FirstHit> got = actual(x, y);
            ++accuracy.rays;
            if (want.has_value() != got.has_value()) {
                ++accuracy.hit_miss_disagreements;
            } else if (want && (want->leaf != got->leaf || want->part != got->part)) {
                ++accuracy.other_object;
            } else if (want) {
                t_relative.push_back(std::fabs(got->t - want->t) / want->t);
                max_angle = std::max(max_angle, angle_between(got->normal, want->normal));
            }
        }
    }
    std::sort(t_relative.begin(), t_relative.end());
    accuracy.t_relative_p50 = quantile(t_relative, 0.5);
    accuracy.t_relative_p999 = quantile(t_relative, 0.999);
    accuracy.t_relative_max = t_relative.empty() ? 0 : t_relative.back();
    accuracy.normal_angle_max_degrees = max_angle * 180.0 / std::numbers::pi;
    return accuracy;
}

}  // namespace twinray::accuracy
