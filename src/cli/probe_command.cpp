// `twinray probe`, stage by stage: the arguments (probe_arguments), the reference's and the judged tracer's trees
// (probe_tracing), then the table (probe_text) or the JSON (probe_json).
#include "cli/probe_command.h"

#include "cli/exit_codes.h"
#include "cli/probe_arguments.h"
#include "cli/probe_json.h"
#include "cli/probe_text.h"
#include "cli/probe_tracing.h"
#include "cli/tracers.h"
#include "scene/loader.h"

#include <iostream>
#include <memory>

namespace twinray::cli {
namespace {

int run_probe(const probe::Arguments& arguments) {
    probe::Target target;
    try {
        target = probe::parse_target(arguments);
    } catch (const probe::UsageError& error) {
        std::cerr << "twinray probe: " << error.what() << "\n";
        return exit_usage;
    }
    scene::Scene scene;
    try {
        scene = scene::load_scene(arguments.scene_path);
    } catch (const scene::SceneError& error) {
        std::cerr << "twinray probe: invalid scene: " << error.what() << "\n";
        return exit_invalid_scene;
    }
    if (target.is_pixel) {
        try {
            probe::place_pixel(scene, arguments, target);
        } catch (const probe::UsageError& error) {
            std::cerr << "twinray probe: " << error.what() << "\n";
            return exit_usage;
        }
    }
    probe::Findings findings;
    try {
        findings = probe::trace_target(scene, target, arguments.accel, arguments.tracer);
    } catch (const plugin::PluginError& error) {
        std::cerr << "twinray probe: " << error.what() << "\n";
        return plugin_exit_status(error);
    }
    if (arguments.json) {
        std::cout << probe::report_json(scene, arguments.scene_path, target, findings).dump(2) << "\n";
    } else {
        probe::print_text(scene, arguments.scene_path, target, findings);
    }
    return exit_success;
}

}  // namespace

void add_probe_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<probe::Arguments>();
    CLI::App* command = app.add_subcommand(
        "probe",
        "Trace one pixel (or ray) with the reference and the SSE tracer (or --tracer's) and print the two ray trees "
        "side by side, marking where they first diverge");
    probe::add_options(*command, *arguments);
    add_accel_option(*command, arguments->accel);
    add_tracer_option(*command, arguments->tracer);
    command->callback([arguments, &run] { run = [arguments] { return run_probe(*arguments); }; });
}

}  // namespace twinray::cli
