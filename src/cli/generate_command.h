#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace twinray::cli {

// Adds `twinray generate FAMILY [--size N] [--seed S] -o FILE`: writes a large scene of a generated
// family (generate_scene.h); when it is the chosen subcommand, `run` is set to the command's body.
void add_generate_command(CLI::App& app, std::function<int()>& run);

}  // namespace twinray::cli
