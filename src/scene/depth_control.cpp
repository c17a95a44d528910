#include "scene/depth_control.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace twinray::scene {
namespace {

// The derivation is in docs/reference-tracer.md ("Adaptive depth control"). A ray returns the background,
// or one hit's local shading plus its children weighted by reflection and transmission. Per material m,
// L_m bounds the local shading in every channel: every light at full strength (N·L ≤ 1, the Phong power
// ≤ 1) times the largest shadow transmittance.
double local_radiance_bound(const Scene& scene, const Material& m, double shadow) {
    double largest = 0;
    for (int c = 0; c < 3; ++c) {
        double lights = 0;
        for (const Light& light : scene.lights) {
            lights += (m.diffuse * m.color[c] + m.phong) * light.color[c];
        }
        // shadow may be +∞; a material no light reaches must not turn that into ∞·0 = NaN.
        double lit = lights > 0 ? shadow * lights : 0;
        largest = std::max(largest, m.ambient * m.color[c] * scene.ambient_light[c] + lit);
    }
    return largest;
}

}  // namespace

DepthControl::DepthControl(const Scene& scene)
    : radiance_bound_(static_cast<std::size_t>(scene.max_depth) + 2, 0.0),
      min_weight_(scene.min_weight),
      max_depth_(scene.max_depth) {
    for (const Material& m : scene.materials) {
        coefficients_.push_back({m.reflection, m.transmission});
    }
    // Only the materials of some primitive can be hit.
    std::vector<bool> used(scene.materials.size(), false);
    for (int material : scene.leaf_materials) {
        used[static_cast<std::size_t>(material)] = true;
    }
    double largest_transmission = 0;
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        if (used[i]) {
            largest_transmission = std::max(largest_transmission, scene.materials[i].transmission);
        }
    }
    // A shadow ray multiplies the transmission of every surface it crosses: a primitive is crossed at most
    // twice (it is convex; a plane once), a mesh's triangle once. Transmissions above 1 are legal, so the
    // product may grow with every crossing; it is only bounded by 1 when none exceeds 1.
    double most_crossings = 2.0 * static_cast<double>(scene.leaf_materials.size() - scene.meshes.size());
    for (const Mesh& mesh : scene.meshes) {
        most_crossings += static_cast<double>(mesh.data->triangles.size());  // an instance's: its shape's
    }
    double shadow = largest_transmission > 1 ? std::pow(largest_transmission, most_crossings) : 1.0;
    struct Bounded {
        double local, children;  // L_m, and reflection + transmission (which total internal reflection keeps)
    };
    std::vector<Bounded> hit;
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        if (used[i]) {
            const Material& m = scene.materials[i];
            hit.push_back({local_radiance_bound(scene, m, shadow), m.reflection + m.transmission});
        }
    }
    double background = std::max({scene.background.x, scene.background.y, scene.background.z});
    // B(d) = max(background, max over m of L_m + s_m·B(d + 1)), B(max_depth + 1) = 0: the most a ray at depth
    // d returns. The tracers compute in float or double what this bounds exactly: a relative margin of 2⁻¹⁰
    // covers their rounding (at most a few hundred roundings of 2⁻²⁴ each along a 64-deep path).
    constexpr double rounding_margin = 1.0 + 1.0 / 1024;
    double below = 0;
    for (int depth = scene.max_depth; depth >= 1; --depth) {
        double most = background;
        for (const Bounded& m : hit) {
            most = std::max(most, m.local + (m.children > 0 ? m.children * below : 0.0));  // no 0·∞ = NaN
        }
        below = most;
        radiance_bound_[static_cast<std::size_t>(depth)] = below * rounding_margin;
    }
    // One level past max_depth, which the tracers never trace: bounded as the last level (local shading
    // only), so a ray asked about there reads a sound bound, not past the table.
    radiance_bound_.back() = radiance_bound_[static_cast<std::size_t>(scene.max_depth)];
}

RayShare DepthControl::refracted(const RayShare& parent, int material) const {
    const SecondaryCoefficients& k = coefficients_[static_cast<std::size_t>(material)];
    int rays_left = parent.allowance - 1;
    int allowance = k.reflection > 0 ? static_cast<int>(std::floor(static_cast<double>(rays_left) * k.transmission /
                                                                   (k.transmission + k.reflection)))
                                     : rays_left;
    return {parent.weight * k.transmission, allowance};
}

RayShare DepthControl::reflected(const RayShare& parent, int material, bool total_internal,
                                 std::uint32_t used_by_refracted) const {
    const SecondaryCoefficients& k = coefficients_[static_cast<std::size_t>(material)];
    double coefficient = total_internal ? k.reflection + k.transmission : k.reflection;
    return {parent.weight * coefficient, parent.allowance - 1 - static_cast<int>(used_by_refracted)};
}

DropReason DepthControl::decide(const RayShare& share, int depth, PixelLedger& ledger) const {
    double bound = share.weight * radiance_bound(depth);
    DropReason reason = DropReason::traced;
    if (min_weight_ ? share.weight < *min_weight_ : ledger.dropped_bound + bound <= pixel_tolerance) {
        reason = DropReason::cutoff;
    } else if (share.allowance < 1) {
        reason = DropReason::budget;
        ledger.over_budget = true;
    }
    if (reason != DropReason::traced) {
        ++ledger.dropped;
        ledger.dropped_bound += bound;
    }
    return reason;
}

double DepthControl::bailout_weight() const {
    if (min_weight_) {
        return *min_weight_;
    }
    // The first secondary rays (depth 2) have the largest bound; a ray that cannot matter there cannot
    // matter deeper.
    if (max_depth_ < 2 || !std::isfinite(radiance_bound(2)) || radiance_bound(2) <= 0) {
        return 0;
    }
    return pixel_tolerance / radiance_bound(2);
}

}  // namespace twinray::scene
