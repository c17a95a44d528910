#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace twinray::cli {

// Adds `twinray watertight [--rays N] [--csv FILE]`: the watertightness suite (accuracy/watertight.h) at full
// size, every family at every distance and size, for the oracle and every SSE tracer built: misses and
// double hits, a row per tracer and distance.
void add_watertight_command(CLI::App& app, std::function<int()>& run);

}  // namespace twinray::cli
