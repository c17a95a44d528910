#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace twinray::cli {

// Adds `twinray bench`: Mrays/s of every tracer on each scene, side by side, with the ratios.
void add_bench_command(CLI::App& app, std::function<int()>& run);

}  // namespace twinray::cli
