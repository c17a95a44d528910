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
    std::string name = "reference";  // short, for node indices: "reference", "sse", "plugin"
    double unit_roundoff = 0x1p-53;  // of the arithmetic the tree's hits were found in
};

// The reference's tree beside the judged tracer's, and their divergences. Where the judged tracer cannot run
// here (the SSE tracer without SSE4.1) only the reference traces; judged_note says why.
struct Findings {
    TracedTree reference;
    std::optional<TracedTree> judged;
    std::string judged_note;
    DivergenceThresholds limits;
    std::vector<Divergence> divergences;  // in tracing order; empty without a judged tree
    accuracy::PixelCause cause;           // why the trees differ (accuracy/attribution.h); only with a judged tree
};

// `tracer` names the judged tracer as --tracer does (tracing::make_tracer); a plug-in's errors are thrown as
// plugin::PluginError.
Findings trace_target(const scene::Scene& scene, const Target& target, Accel accel = Accel::automatic,
                      const std::string& tracer = "sse");

// Naming what a tree holds, for the text and the JSON alike.
std::string object_name(const scene::Scene& scene, const RayNode& node);
// For a hit on a mesh's triangle, its vertices' weights at the hit point (scene::barycentrics); else none.
std::optional<std::array<double, 3>> barycentrics(const scene::Scene& scene, const RayNode& node);
std::string material_name(const scene::Scene& scene, const RayNode& node);
// The node at `index`, or nullptr where the tree is absent or the index is -1 (a ray the tracer did not trace).
const RayNode* node_at(const RayTree* tree, int index);

}  // namespace twinray::cli::probe
