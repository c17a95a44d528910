// `twinray probe`'s tracing: the target traced by each tracer into a ray tree, and where the trees part.
#pragma once

#include "accuracy/attribution.h"
#include "cli/probe_arguments.h"
#include "render/ray_tree.h"
#include "scene/scene.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace twinray::cli::probe {

// One tracer's tree of the probed ray.
struct TracedTree {
    std::string label;  // the tracer, for people
    RayTree tree;
};

// Both trees and their divergences. Without SSE4.1 only the reference traces; sse_note says why.
struct Findings {
    TracedTree reference;
    std::optional<TracedTree> sse;
    std::string sse_note;
    DivergenceThresholds limits;
    std::vector<Divergence> divergences;  // in tracing order; empty without sse
    accuracy::PixelCause cause;           // why the trees differ (accuracy/attribution.h); only with sse
};

Findings trace_target(const scene::Scene& scene, const Target& target, Accel accel = Accel::automatic);

// Naming what a tree holds, for the text and the JSON alike.
std::string object_name(const scene::Scene& scene, int leaf);
// For a hit on a mesh's triangle, its vertices' weights at the hit point (scene::barycentrics); else none.
std::optional<std::array<double, 3>> barycentrics(const scene::Scene& scene, const RayNode& node);
std::string material_name(const scene::Scene& scene, int leaf);
// The node at `index`, or nullptr where the tree is absent or the index is -1 (a ray the tracer did not trace).
const RayNode* node_at(const RayTree* tree, int index);

}  // namespace twinray::cli::probe
