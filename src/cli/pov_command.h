#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace twinray::cli {

// Adds `twinray pov`; when it is the chosen subcommand, `run` is set to the command's body.
void add_pov_command(CLI::App& app, std::function<int()>& run);

}  // namespace twinray::cli
