// `twinray probe --json`: both trees, the first hits and the divergences as one JSON object for scripts
// (its fields: docs/probe.md).
#pragma once

#include "cli/probe_arguments.h"
#include "cli/probe_tracing.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <string>

namespace twinray::cli::probe {

// Ordered: the keys print in the order docs/probe.md lists them.
using Json = nlohmann::ordered_json;

Json report_json(const scene::Scene& scene, const std::string& scene_path, const Target& target,
                 const Findings& findings);

}  // namespace twinray::cli::probe
