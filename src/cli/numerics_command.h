#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace twinray::cli {

// Adds `twinray numerics`: hit-point error against scale and distance, self-hits ("acne") and leaks per
// tracer, as CSV; or, with --footprint, where float's error outgrows a pixel (docs/numerics.md).
void add_numerics_command(CLI::App& app, std::function<int()>& run);

}  // namespace twinray::cli
