// twinray: two ray tracers, one scene format, and the tools to hold them against each other.
#include "cli/bench_command.h"
#include "cli/compare_command.h"
#include "cli/conform_command.h"
#include "cli/diff_command.h"
#include "cli/exit_codes.h"
#include "cli/generate_command.h"
#include "cli/golden_command.h"
#include "cli/numerics_command.h"
#include "cli/pov_command.h"
#include "cli/probe_command.h"
#include "cli/render_command.h"
#include "cli/watertight_command.h"

#include <CLI/CLI.hpp>

#include <exception>
#include <functional>
#include <iostream>

int main(int argc, char** argv) {
    using namespace twinray::cli;
    CLI::App app{
        "twinray: a double-precision reference ray tracer and a fast SSE4.1 tracer, held against each other.\n"
        "Exit status: 0 success, 1 usage error, 2 invalid scene, 3 output not writable, 4 unreadable or\n"
        "mismatched input image, 5 the CPU lacks SSE4.1 (use --tracer reference), 6 watertight: a leak or a double "
        "hit,\n"
        "70 internal error.\n"
        "compare and diff: 0 pass, 1 warn, 2 fail (see their --help)."};
    app.require_subcommand(1);
    std::function<int()> run;
    add_render_command(app, run);
    add_bench_command(app, run);
    add_pov_command(app, run);
    add_compare_command(app, run);
    add_diff_command(app, run);
    add_golden_command(app, run);
    add_probe_command(app, run);
    add_numerics_command(app, run);
    add_generate_command(app, run);
    add_watertight_command(app, run);
    add_conform_command(app, run);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& error) {
        return app.exit(error) == 0 ? exit_success : exit_usage;
    }
    try {
        return run();
    } catch (const std::exception& error) {
        std::cerr << "twinray: internal error: " << error.what() << "\n";
        return exit_internal_error;
    }
}
