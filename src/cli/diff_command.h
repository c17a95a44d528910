#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace twinray::cli {

// Adds `twinray diff SCENE... -o DIR`: both tracers per scene, error maps and an HTML report.
void add_diff_command(CLI::App& app, std::function<int()>& run);

}  // namespace twinray::cli
