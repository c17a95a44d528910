#include "cli/probe_tracing.h"

#include "reference/tracer.h"
#include "scene/geometry.h"
#include "tracing/any_tracer.h"

#include <cstddef>

namespace twinray::cli::probe {
namespace {

TracedTree trace_reference(const reference::Tracer<double>& tracer, const Target& target) {
    using R = reference::Ray<double>;
    R ray = target.is_pixel ? tracer.primary_ray(target.x, target.y, target.width, target.height)
                            : R{{target.origin[0], target.origin[1], target.origin[2]},
                                {target.direction[0], target.direction[1], target.direction[2]}};
    TracedTree traced{"reference<double>", {}, "reference", 0x1p-53};
    tracer.trace(ray, 1, nullptr, &traced.tree);
    return traced;
}

// The ray given by hand reaches a float tracer with its origin in double (the SSE tracer re-bases it on its own
// origin before rounding to float) and its direction, normalised in double, rounded to float.
TracedTree trace_judged(const tracing::AnyTracer& tracer, const std::string& name, const Target& target) {
    TracedTree traced{tracer.description(), {}, tracing::is_plugin(name) ? "plugin" : name, tracer.unit_roundoff()};
    if (target.is_pixel) {
        tracer.trace_primary(target.x, target.y, target.width, target.height, traced.tree);
    } else {
        tracer.trace_ray(target.origin, target.direction, traced.tree);
    }
    return traced;
}

}  // namespace

Findings trace_target(const scene::Scene& scene, const Target& target, Accel accel, const std::string& tracer) {
    // One reference tracer traces the tree and, for the attribution, replays the judged tracer's rays.
    reference::Tracer<double> reference(scene, accel);
    Findings findings{trace_reference(reference, target), std::nullopt, "", {}, {}, {}};
    if (std::string reason = tracing::tracer_unavailable_reason(tracer); !reason.empty()) {
        findings.judged_note = tracer + " not run: " + reason;
        return findings;
    }
    findings.judged = trace_judged(*tracing::make_tracer(tracer, scene, {}, accel), tracer, target);
    findings.divergences = find_divergences(findings.reference.tree, findings.judged->tree, findings.limits);
    findings.cause = accuracy::attribute(scene, reference, findings.reference.tree, findings.judged->tree);
    return findings;
}

std::string object_name(const scene::Scene& scene, const RayNode& node) {
    if (node.leaf < 0 || static_cast<std::size_t>(node.leaf) >= scene.leaf_paths.size()) {
        return "leaf " + std::to_string(node.leaf) + " (unknown)";
    }
    return scene.leaf_name(node.leaf, node.part);
}

std::optional<std::array<double, 3>> barycentrics(const scene::Scene& scene, const RayNode& node) {
    if (!node.hit || node.triangle < 0) {
        return std::nullopt;
    }
    const scene::Mesh* mesh = scene.mesh_of_leaf(node.leaf);
    if (mesh == nullptr) {
        return std::nullopt;
    }
    // An instance's triangle is its shape's, in the shape's own space.
    const scene::Vec3 point = mesh->placement ? mesh->placement->transform().point_to_object(node.point) : node.point;
    return scene::barycentrics(*mesh->data, static_cast<std::uint32_t>(node.triangle), point);
}

std::string material_name(const scene::Scene& scene, const RayNode& node) {
    if (node.leaf < 0 || static_cast<std::size_t>(node.leaf) >= scene.leaf_materials.size()) {
        return "?";
    }
    return scene.material_names[static_cast<std::size_t>(scene.material_of(node.leaf, node.part))];
}

const RayNode* node_at(const RayTree* tree, int index) {
    return tree != nullptr && index >= 0 ? &tree->nodes[static_cast<std::size_t>(index)] : nullptr;
}

}  // namespace twinray::cli::probe
