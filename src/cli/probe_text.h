// `twinray probe`'s report for people: the two ray trees side by side, one row per field, the first
// divergence marked and explained (docs/probe.md).
#pragma once

#include "cli/probe_arguments.h"
#include "cli/probe_tracing.h"
#include "scene/scene.h"

#include <string>

namespace twinray::cli::probe {

// Prints to stdout.
void print_text(const scene::Scene& scene, const std::string& scene_path, const Target& target,
                const Findings& findings);

}  // namespace twinray::cli::probe
