#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace twinray::cli {

// Adds `twinray golden --update [SCENE...]`: regenerates the stored reference images, on purpose only.
void add_golden_command(CLI::App& app, std::function<int()>& run);

}  // namespace twinray::cli
