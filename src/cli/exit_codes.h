// The exit statuses of every twinray command (documented in the README).
#pragma once

namespace twinray::cli {

enum ExitCode : int {
    exit_success = 0,
    exit_usage = 1,             // bad command line (unknown option, value out of range, unsupported -o format)
    exit_invalid_scene = 2,     // the scene file is missing, unreadable or breaks the scene contract
    exit_output_error = 3,      // an output file cannot be written
    exit_unreadable_image = 4,  // compare/diff: an input image cannot be read, or two images differ in size
    exit_internal_error = 70,   // a bug: an unexpected exception (please report it)
    exit_cpu_unsupported = 5,   // the chosen tracer needs a CPU feature this machine lacks (SSE4.1)
    exit_not_watertight = 6,    // watertight: some tracer missed or double-hit a ray at a shared edge or vertex
    exit_plugin_unusable =
        7,  // a plug-in that does not load, lacks the entry point, speaks another ABI, or fails to build
    exit_plugin_lacks_kind = 8,    // the scene holds a kind of primitive the plug-in does not intersect
    exit_plugin_fault = 9,         // a plug-in answered against the tracer ABI's contract (NaN, t out of range, ...)
    exit_conformance_failed = 10,  // conform: some case of the plug-in's failed
    exit_interrupted = 130,  // render: stopped by Ctrl-C (SIGINT) before writing; 128 + SIGINT, as a shell reports it
};

}  // namespace twinray::cli
