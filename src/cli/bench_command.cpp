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
    int width = 640;
};

struct Configuration {
    std::string label;
    std::string tracer;
    int threads;
};

double mrays_of_one_render(const std::string& tracer, const scene::Scene& scene, int width, int threads) {
    RenderOptions options;
    options.width = width;
    options.threads = threads;
    auto start = std::chrono::steady_clock::now();
    RenderResult result = render_with(tracer, scene, options);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return static_cast<double>(result.rays) / seconds / 1e6;
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    std::size_t middle = values.size() / 2;
    return values.size() % 2 == 1 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
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
        // A control: how the plain scalar code scales on this machine, for reading the sse column.
        {"ref " + std::to_string(all_threads) + "T", "reference", all_threads},
    };
    if (std::string reason = tracer_unavailable_reason("sse"); !reason.empty()) {
        std::cerr << "twinray bench: " << reason << "\n";
        return exit_cpu_unsupported;
    }
    std::printf("Mrays/s, median of %d runs at width %d; ratios are medians of per-run ratios\n\n", arguments.runs,
                arguments.width);
    std::printf("%-12s", "scene");
    for (const Configuration& configuration : configurations) {
        std::printf(" %12s", configuration.label.c_str());
    }
    std::printf(" %12s %12s %12s %12s\n", "sse/double", "sse/float", "sse nT/1T", "ref nT/1T");
    for (const std::string& path : scene_paths) {
        scene::Scene scene;
        try {
            scene = scene::load_scene(path);
        } catch (const scene::SceneError& error) {
            std::cerr << "twinray bench: invalid scene: " << error.what() << "\n";
            return exit_invalid_scene;
        }
        // Configurations take turns within each run, and each ratio is the median of per-run ratios, so
        // a slow spell of a shared machine weighs on both sides of a ratio instead of on one column.
        std::vector<std::vector<double>> speeds(configurations.size());
        std::vector<double> over_double, over_float, over_one_thread, reference_over_one_thread;
        for (int run = 0; run < arguments.runs; ++run) {
            std::vector<double> this_run;
            for (const Configuration& configuration : configurations) {
                this_run.push_back(mrays_of_one_render(configuration.tracer, scene, arguments.width, configuration.threads));
            }
            for (std::size_t i = 0; i < configurations.size(); ++i) {
                speeds[i].push_back(this_run[i]);
            }
            over_double.push_back(this_run[2] / this_run[0]);
            over_float.push_back(this_run[2] / this_run[1]);
            over_one_thread.push_back(this_run[3] / this_run[2]);
            reference_over_one_thread.push_back(this_run[4] / this_run[0]);
        }
        std::printf("%-12s", fs::path(path).stem().string().c_str());
        for (const std::vector<double>& configuration_speeds : speeds) {
            std::printf(" %12.2f", median(configuration_speeds));
        }
        std::printf(" %11.2fx %11.2fx %11.2fx %11.2fx\n", median(over_double), median(over_float), median(over_one_thread),
                    median(reference_over_one_thread));
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
    command->add_option("--runs", arguments->runs, "Runs; each renders every configuration once, and medians are reported")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    command->add_option("--width", arguments->width,
                        "Render width; the height keeps each scene's aspect (long enough renders to time well)")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    command->add_option("--threads", arguments->threads, "Threads of the multi-threaded column (default: all cores)")
        ->check(CLI::Range(1, 1024));
    command->callback([arguments, &run] { run = [arguments] { return run_bench(*arguments); }; });
}

}  // namespace twinray::cli
