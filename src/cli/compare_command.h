#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace twinray::cli {

// Adds `twinray compare A B`: idiff-style image comparison (exit 0 pass, 1 warn, 2 fail, 4 unreadable).
void add_compare_command(CLI::App& app, std::function<int()>& run);

}  // namespace twinray::cli
