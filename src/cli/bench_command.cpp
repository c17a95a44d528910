#include "cli/bench_command.h"

#include "cli/exit_codes.h"
#include "cli/tracers.h"
#include "scene/loader.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace twinray::cli {
namespace {

namespace fs = std::filesystem;

struct BenchArguments {
    std::vector<std::string> scenes;
    int runs = 5;
    int threads = 0;
    int width = 0;
};

struct Configuration {
    std::string label;
    std::string tracer;
    int threads;
};

// The median of `runs` renders, in Mrays/s: the median resists the odd run disturbed by the machine.
double median_mrays(const std::string& tracer, const scene::Scene& scene, int width, int threads, int runs) {
    std::vector<double> speeds;
    for (int run = 0; run < runs; ++run) {
        RenderOptions options;
        options.width = width;
        options.threads = threads;
        auto start = std::chrono::steady_clock::now();
        RenderResult result = render_with(tracer, scene, options);
        double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        speeds.push_back(static_cast<double>(result.rays) / seconds / 1e6);
    }
    std::sort(speeds.begin(), speeds.end());
    return speeds[speeds.size() / 2];
}

std::vector<std::string> default_scenes() {
    std::vector<std::string> names = {"planes", "spheres", "cylinders", "complete1", "complete2", "csg"};
    std::vector<std::string> paths;
    for (const std::string& name : names) {
        paths.push_back("scenes/" + name + ".json");
    }
    return paths;
}

int run_bench(const BenchArguments& arguments) {
    std::vector<std::string> scene_paths = arguments.scenes.empty() ? default_scenes() : arguments.scenes;
    int all_threads = resolve_thread_count(arguments.threads);
    std::vector<Configuration> configurations = {
        {"ref<double>", "reference", 1},
        {"ref<float>", "reference-float", 1},
        {"sse 1T", "sse", 1},
        {"sse " + std::to_string(all_threads) + "T", "sse", all_threads},
    };
    if (std::string reason = tracer_unavailable_reason("sse"); !reason.empty()) {
        std::cerr << "twinray bench: " << reason << "\n";
        return exit_cpu_unsupported;
    }
    std::printf("Mrays/s, median of %d renders %s\n\n", arguments.runs,
                arguments.width == 0 ? "at each scene's own size" : ("at width " + std::to_string(arguments.width)).c_str());
    std::printf("%-12s", "scene");
    for (const Configuration& configuration : configurations) {
        std::printf(" %12s", configuration.label.c_str());
    }
    std::printf(" %12s %12s %12s\n", "sse/double", "sse/float", "nT/1T");
    for (const std::string& path : scene_paths) {
        scene::Scene scene;
        try {
            scene = scene::load_scene(path);
        } catch (const scene::SceneError& error) {
            std::cerr << "twinray bench: invalid scene: " << error.what() << "\n";
            return exit_invalid_scene;
        }
        std::vector<double> speeds;
        for (const Configuration& configuration : configurations) {
            speeds.push_back(median_mrays(configuration.tracer, scene, arguments.width, configuration.threads, arguments.runs));
        }
        std::printf("%-12s", fs::path(path).stem().string().c_str());
        for (double speed : speeds) {
            std::printf(" %12.2f", speed);
        }
        std::printf(" %11.2fx %11.2fx %11.2fx\n", speeds[2] / speeds[0], speeds[2] / speeds[1], speeds[3] / speeds[2]);
        std::fflush(stdout);
    }
    return exit_success;
}

}  // namespace

void add_bench_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<BenchArguments>();
    CLI::App* command = app.add_subcommand(
        "bench", "Measure Mrays/s of reference<double>, reference<float> and sse (1 thread and all) side by side");
    command->add_option("scenes", arguments->scenes,
                        "Scene files (default: scenes/{planes,spheres,cylinders,complete1,complete2,csg}.json)");
    command->add_option("--runs", arguments->runs, "Renders per configuration; the median is reported")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    command->add_option("--width", arguments->width, "Render width (height keeps each scene's aspect; default: the scene's)")
        ->check(CLI::Range(1, 16384));
    command->add_option("--threads", arguments->threads, "Threads of the multi-threaded column (default: all cores)")
        ->check(CLI::Range(1, 1024));
    command->callback([arguments, &run] { run = [arguments] { return run_bench(*arguments); }; });
}

}  // namespace twinray::cli
