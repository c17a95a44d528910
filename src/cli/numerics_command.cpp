#include "cli/numerics_command.h"

#include "cli/exit_codes.h"
#include "io/atomic_file.h"
#include "numerics/numerics.h"
#include "scene/loader.h"
#include "sse/cpu.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace twinray::cli {
namespace {

namespace fs = std::filesystem;

struct NumericsArguments {
    std::vector<std::string> scenes;
    std::string csv_path;
    int grid = 24;
    bool footprint = false;
    int footprint_width = 0;  // 0: the scene's own
};

std::vector<numerics::TracerKind> available_tracers() {
    std::vector<numerics::TracerKind> kinds = {numerics::TracerKind::reference_double,
                                               numerics::TracerKind::reference_float};
    if (sse::cpu_supports_sse41()) {
        kinds.push_back(numerics::TracerKind::sse);
    } else {
        std::cerr << "twinray numerics: this CPU lacks SSE4.1; the sse tracer is left out\n";
    }
    return kinds;
}

// One row per scene, case and tracer; the scene's objects are of size 1, so the scale is their size.
std::string scale_table(const std::vector<std::pair<std::string, scene::Scene>>& scenes, int grid) {
    std::ostringstream csv;
    csv << "subject,tracer,scale,shift,camera_distance,rays,hits,max_error_over_size,secondary_rays,acne,leaks\n";
    for (const auto& [subject, scene] : scenes) {
        for (const numerics::ScaleCase& c : numerics::scale_cases()) {
            scene::Scene moved = numerics::transformed(scene, c.scale, c.shift, c.camera_distance);
            for (numerics::TracerKind kind : available_tracers()) {
                numerics::Measurement m = numerics::measure(moved, kind, grid, c.scale);
                char row[256];
                std::snprintf(row, sizeof row, "%s,%s,%g,%g,%g,%d,%d,%.3e,%d,%d,%d\n", subject.c_str(),
                              numerics::tracer_name(kind), c.scale, c.shift, c.camera_distance, m.rays, m.hits,
                              m.max_error, m.secondary, m.acne, m.leaks);
                csv << row;
            }
        }
    }
    return csv.str();
}

// Per tracer and primitive type, the largest error/footprint ratio at each shift, and the first shift
// where it passes 1.
std::string footprint_table(const scene::Scene& scene, int width) {
    std::ostringstream csv;
    csv << "tracer,primitive,shift,max_error_over_pixel_footprint\n";
    for (numerics::TracerKind kind : available_tracers()) {
        for (double shift : numerics::footprint_shifts()) {
            for (const numerics::FootprintRatio& r :
                 numerics::footprint_ratios(numerics::transformed(scene, 1.0, shift), kind, width)) {
                char row[160];
                std::snprintf(row, sizeof row, "%s,%s,%g,%.3e\n", numerics::tracer_name(kind), r.primitive.c_str(),
                              shift, r.max_ratio);
                csv << row;
            }
        }
    }
    return csv.str();
}

int run_numerics(const NumericsArguments& arguments) {
    if (arguments.footprint && arguments.scenes.size() != 1) {
        std::cerr << "twinray numerics: --footprint takes exactly one scene (e.g. scenes/showcase.json)\n";
        return exit_usage;
    }
    std::vector<std::pair<std::string, scene::Scene>> scenes;
    for (const std::string& path : arguments.scenes) {
        try {
            scenes.emplace_back(fs::path(path).stem().string(), scene::load_scene(path));
        } catch (const scene::SceneError& error) {
            std::cerr << "twinray numerics: invalid scene: " << error.what() << "\n";
            return exit_invalid_scene;
        }
        // Its exact geometry (numerics/exact_geometry.cpp) is written per primitive in the world; meshes and the
        // parts of solid shapes' instances have none yet.
        if (scenes.back().second.has_meshes()) {
            std::cerr
                << "twinray numerics: " << path
                << ": meshes are not measured yet (the exact geometry of the scale table and the footprint covers "
                   "planes, spheres, cylinders and boxes); `twinray watertight` measures meshes\n";
            return exit_invalid_scene;
        }
        if (!scenes.back().second.solid_instances.empty()) {
            std::cerr << "twinray numerics: " << path
                      << ": instances of CSG shapes are not measured yet (the exact geometry of the scale table and "
                         "the footprint covers primitives in the world); write the shape's tree where it stands, "
                         "with the instance's transform on it, to measure it\n";
            return exit_invalid_scene;
        }
    }
    const scene::Scene& first = scenes.front().second;
    std::string table =
        arguments.footprint
            ? footprint_table(first, arguments.footprint_width > 0 ? arguments.footprint_width : first.width)
            : scale_table(scenes, arguments.grid);
    if (arguments.csv_path.empty()) {
        std::cout << table;
        return exit_success;
    }
    try {
        io::write_text_atomically(arguments.csv_path, table);
    } catch (const io::FileWriteError& error) {
        std::cerr << "twinray numerics: " << error.what() << "\n";
        return exit_output_error;
    }
    return exit_success;
}

}  // namespace

void add_numerics_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<NumericsArguments>();
    CLI::App* command = app.add_subcommand(
        "numerics",
        "Numerical stability at the extremes (docs/numerics.md). Each scene (objects of size 1 at the origin, e.g.\n"
        "tests/data/extremes/*.json) is scaled 1e-4 .. 1e6 and moved 10 .. 1e6 from the origin; per tracer: the\n"
        "largest distance of a primary hit point from the true surface over the object's size, and how many\n"
        "secondary rays re-hit the surface they left (acne) or leaked through a solid. CSV on stdout or --csv.\n"
        "--footprint SCENE: the scene moved 1 .. 1e7 from the origin; per primitive type the largest ratio of\n"
        "that error to the pixel's footprint.");
    command->add_option("scenes", arguments->scenes, "Scene files")->required()->check(CLI::ExistingFile);
    command->add_option("--csv", arguments->csv_path, "Write the CSV here (atomically) instead of stdout");
    command->add_option("--grid", arguments->grid, "Primary rays per side of the grid")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    command->add_flag("--footprint", arguments->footprint,
                      "Error against pixel footprint, scene moved away from the origin");
    command
        ->add_option("--footprint-width", arguments->footprint_width,
                     "Image width for --footprint (default: the scene's)")
        ->check(CLI::Range(1, 4096));
    command->callback([arguments, &run] { run = [arguments] { return run_numerics(*arguments); }; });
}

}  // namespace twinray::cli
