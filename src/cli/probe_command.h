#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace twinray::cli {

// Adds `twinray probe`: the ray tree of one pixel (or one ray) from both tracers side by side, and the
// first place they part (docs/probe.md); when it is the chosen subcommand, `run` is set to its body.
void add_probe_command(CLI::App& app, std::function<int()>& run);

}  // namespace twinray::cli
