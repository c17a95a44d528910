#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace twinray::cli {

// Adds `twinray conform PLUGIN [SCENES...]`: the per-ray suites of plugin/conformance.h against a tracer behind
// the tracer ABI, each case in a child process with a time limit, a verdict per case and suite (and JUnit XML).
void add_conform_command(CLI::App& app, std::function<int()>& run);

}  // namespace twinray::cli
