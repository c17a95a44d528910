#include "cli/bench_command.h"

#include "accuracy/ray_accuracy.h"
#include "accuracy/watertight.h"
#include "cli/bench_run.h"
#include "cli/exit_codes.h"
#include "cli/generate_scene.h"
#include "cli/tracers.h"
#include "compare/image_compare.h"
#include "io/atomic_file.h"
#include "pov/povray_runner.h"
#include "reference/tracer.h"
#include "scene/loader.h"
#include "sse/tracer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace twinray::cli::bench {

std::vector<Timings> time_renders(const std::vector<Configuration>& configurations, const scene::Scene& scene,
                                  int width, int runs, std::vector<Image>* last_images, Accel accel) {
    std::vector<Timings> timings(configurations.size());
    if (last_images != nullptr) {
        last_images->assign(configurations.size(), Image(1, 1));
    }
    for (int run = 0; run < runs; ++run) {
        for (std::size_t i = 0; i < configurations.size(); ++i) {
            const Configuration& configuration = configurations[i];
            RenderOptions options;
            options.width = width;
            options.threads = configuration.threads;
            options.accel = accel;
            auto start = std::chrono::steady_clock::now();
            RenderResult result = render_with(configuration.tracer, scene, options, configuration.precision);
            double seconds = seconds_since(start);
            timings[i].seconds.push_back(seconds);
            timings[i].mrays.push_back(static_cast<double>(result.tally.rays) / seconds / 1e6);
            timings[i].tracing_seconds.push_back(result.tracing_seconds);
            timings[i].tracing_cpu_seconds.push_back(result.tracing_cpu_seconds);
            timings[i].rays = result.tally.rays;
            if (last_images != nullptr && run + 1 == runs) {
                (*last_images)[i] = std::move(result.image);
            }
        }
        for (Timings& timing : timings) {
            timing.speedups.push_back(timing.mrays.back() / timings[0].mrays.back());
        }
    }
    return timings;
}

namespace {

namespace fs = std::filesystem;

// reference<double> first: every ratio and every error is against it.
std::vector<Configuration> trade_configurations(int all_threads) {
    auto sse_with = [](const char* label, sse::Precision precision) {
        return Configuration{label, "sse", precision, 1};
    };
    return {
        {"ref<double>", "reference", {}, 1},
        {"ref<float>", "reference-float", {}, 1},
        sse_with("sse exact", {}),
        sse_with("sse rcp", {.fast_rcp = true}),
        sse_with("sse rsqrt", {.fast_rsqrt = true}),
        sse_with("sse dpps", {.dpps = true}),
        sse_with("sse textbook", {.textbook_quadratic = true}),
        sse_with("sse mt", {.moller_trumbore = true}),
        sse_with("sse ftz", {.flush_denormals = true}),
        sse_with("sse fast", all_fast_knobs()),
        {"sse exact " + std::to_string(all_threads) + "T", "sse", {}, all_threads},
    };
}

// The plug-ins' rows follow twinray's own, each labelled by its file's name.
void add_plugin_configurations(const std::vector<std::string>& plugins, std::vector<Configuration>& configurations) {
    for (const std::string& plugin : plugins) {
        configurations.push_back(
            {"plugin " + fs::path(plugin.substr(plugin.find(':') + 1)).stem().string(), plugin, {}, 1});
    }
}

accuracy::RayAccuracy ray_accuracy(const Configuration& configuration, const scene::Scene& scene,
                                   const std::vector<std::optional<accuracy::FirstHit>>& expected, int width,
                                   int height, Accel accel) {
    const std::unique_ptr<tracing::AnyTracer> tracer =
        tracing::make_tracer(configuration.tracer, scene, configuration.precision, accel);
    return accuracy::measure_rays(expected, accuracy::first_hits_of(*tracer, width, height), width, height);
}

// The configurations that can trace `scene`: a plug-in that lacks one of its kinds is left out of this scene's
// rows, with a note; any other plug-in error ends the bench (plugin::PluginError).
std::vector<std::size_t> runnable_on(const std::string& name, const scene::Scene& scene,
                                     const std::vector<Configuration>& configurations) {
    std::vector<std::size_t> runnable;
    for (std::size_t i = 0; i < configurations.size(); ++i) {
        if (is_plugin(configurations[i].tracer)) {
            try {
                tracing::make_tracer(configurations[i].tracer, scene);
            } catch (const plugin::UnsupportedKind& refused) {
                std::fprintf(stderr, "\ntwinray bench: %s left out of %s: %s\n", configurations[i].label.c_str(),
                             name.c_str(), refused.what());
                continue;
            }
        }
        runnable.push_back(i);
    }
    return runnable;
}

// Across scenes, per configuration: speed-ups (for the geometric mean) and the worst errors.
struct Summary {
    std::vector<double> speedups;
    double image_rms = 0, image_max = 0, over_share = 0, t_p999 = 0, t_max = 0, normal_max = 0;
    long rays = 0, hit_miss = 0;
};

// One scene: timings, then the accuracy of each configuration's last image and of its primary rays.
void bench_scene(const std::string& name, const scene::Scene& scene, const BenchArguments& arguments,
                 const std::vector<Configuration>& all_configurations, std::vector<Summary>& all_summaries,
                 std::vector<double>& sse_seconds, Report& report) {
    const std::vector<std::size_t> runnable = runnable_on(name, scene, all_configurations);
    std::vector<Configuration> configurations;
    for (std::size_t i : runnable) {
        configurations.push_back(all_configurations[i]);
    }
    std::vector<Image> images;
    std::vector<Timings> timings =
        time_renders(configurations, scene, arguments.width, arguments.runs, &images, arguments.accel);
    const int width = images[0].width(), height = images[0].height();
    reference::Tracer<double> oracle(scene);
    auto expected = accuracy::all_first_hits(accuracy::first_hits_of(oracle, width, height), width, height);
    Image reference_image = compare::clamped(images[0]);
    compare::Thresholds over_one_level;
    over_one_level.fail = over_one_level.warn = 1.0 / 255.0;
    for (std::size_t i = 0; i < configurations.size(); ++i) {
        compare::Metrics image = compare::measure(reference_image, compare::clamped(images[i]), over_one_level);
        accuracy::RayAccuracy rays = ray_accuracy(configurations[i], scene, expected, width, height, arguments.accel);
        double over_share = static_cast<double>(image.fail_pixels) / static_cast<double>(image.pixel_count);
        const Timings& t = timings[i];
        report.trade.add_row(
            {name, configurations[i].label, cell("%.2f", median(t.mrays)),
             cell("%.2f", *std::min_element(t.mrays.begin(), t.mrays.end())),
             cell("%.2f", *std::max_element(t.mrays.begin(), t.mrays.end())), cell("%.2f", median(t.speedups)),
             cell("%.3g", image.max_error), cell("%.3g", image.rms_error),
             cell("%.1f", image.rms_error == 0 ? INFINITY : image.psnr), cell("%.3f", 100 * over_share),
             cell("%.3g", rays.t_relative_p50), cell("%.3g", rays.t_relative_p999), cell("%.3g", rays.t_relative_max),
             cell("%.3g", rays.normal_angle_max_degrees), cell("%.0f", rays.per_million(rays.hit_miss_disagreements)),
             cell("%.0f", rays.per_million(rays.other_object))});
        Summary& s = all_summaries[runnable[i]];
        s.speedups.push_back(median(t.speedups));
        s.image_rms = std::max(s.image_rms, image.rms_error);
        s.image_max = std::max(s.image_max, image.max_error);
        s.over_share = std::max(s.over_share, over_share);
        s.t_p999 = std::max(s.t_p999, rays.t_relative_p999);
        s.t_max = std::max(s.t_max, rays.t_relative_max);
        s.normal_max = std::max(s.normal_max, rays.normal_angle_max_degrees);
        s.rays += rays.rays;
        s.hit_miss += rays.hit_miss_disagreements;
    }
    // Seconds per frame of sse exact on one thread and on all (the last of twinray's own), for the POV-Ray table.
    const std::size_t own = all_configurations.size() - arguments.plugins.size();
    sse_seconds = {median(timings[2].seconds), median(timings[own - 1].seconds)};
}

// A knob's price in watertightness: the misses and double hits per million of the watertightness suite's rays
// (every family, 1, 10⁴ and 10⁷ from the origin, size 1, aimed at shared edges, vertices and random points; the
// whole table is `twinray watertight`). The SSE tracer's only: the reference is the oracle.
std::string leaks_per_million(const Configuration& configuration) {
    if (configuration.tracer != "sse") {
        return "";
    }
    std::uint64_t rays = 0, leaks = 0;
    for (const std::string& family : accuracy::watertight_families()) {
        for (double distance : {1.0, 1e4, 1e7}) {
            accuracy::WatertightCase watertight = accuracy::make_watertight_case(family, distance, 1.0, 2000);
            accuracy::WatertightTally tally = accuracy::count_watertightness(
                watertight, accuracy::sse_crossings(watertight.scene, configuration.precision));
            rays += tally.rays;
            leaks += tally.misses + tally.double_hits;
        }
    }
    return cell("%.0f", 1e6 * static_cast<double>(leaks) / static_cast<double>(rays));
}

void add_summary(const std::vector<Configuration>& configurations, const std::vector<Summary>& summaries,
                 Report& report) {
    for (std::size_t i = 0; i < configurations.size(); ++i) {
        const Summary& s = summaries[i];
        if (s.speedups.empty()) {
            continue;  // a plug-in that traced none of the scenes
        }
        double log_sum = 0;
        for (double speedup : s.speedups) {
            log_sum += std::log(speedup);
        }
        double geometric_mean = std::exp(log_sum / static_cast<double>(s.speedups.size()));
        report.summary.add_row(
            {configurations[i].label, cell("%.2f", geometric_mean),
             cell("%.2f", *std::min_element(s.speedups.begin(), s.speedups.end())),
             cell("%.2f", *std::max_element(s.speedups.begin(), s.speedups.end())), cell("%.3g", s.image_max),
             cell("%.3g", s.image_rms), cell("%.3f", 100 * s.over_share), cell("%.3g", s.t_p999), cell("%.3g", s.t_max),
             cell("%.3g", s.normal_max),
             cell("%.0f", s.rays == 0 ? 0 : 1e6 * static_cast<double>(s.hit_miss) / static_cast<double>(s.rays)),
             leaks_per_million(configurations[i])});
    }
}

std::vector<std::string> default_scenes() {
    std::vector<std::string> paths;
    if (fs::is_directory("scenes")) {
        for (const auto& entry : fs::directory_iterator("scenes")) {
            if (entry.path().extension() == ".json") {
                paths.push_back(entry.path().string());
            }
        }
    }
    std::sort(paths.begin(), paths.end());
    return paths;
}

// Half the bench's width: 320 by default, at which 128 glass CSG objects by brute force take about a second a frame.
int crossover_width(const BenchArguments& arguments) {
    return std::max(1, arguments.width / 2);
}

Report empty_report(int all_threads, const BenchArguments& arguments) {
    std::string setting =
        "median of " + std::to_string(arguments.runs) + " runs, width " + std::to_string(arguments.width);
    Report report;
    report.trade.title = "Speed and accuracy against ref<double> per scene (" + setting +
                         "; rays: primary, shadow, reflected, refracted)";
    report.trade.headers = {"scene",     "configuration",  "Mrays/s",           "min",
                            "max",       "speed-up",       "img max err",       "img RMS",
                            "PSNR dB",   "% px > 1/255",   "t rel p50",         "t rel p99.9",
                            "t rel max", "normal max deg", "hit/miss per Mray", "other object per Mray"};
    report.summary.title = "Every scene: geometric mean speed-up over ref<double> and the worst error of any scene";
    report.summary.headers = {"configuration", "speed-up geomean", "speed-up min",      "speed-up max",
                              "img max err",   "img RMS",          "% px > 1/255",      "t rel p99.9",
                              "t rel max",     "normal max deg",   "hit/miss per Mray", "watertight leaks per M"};
    report.process.title = "Whole process: twinray render part by part and as a command (ms, " + setting + ")";
    report.process.headers = {"scene", "part", "ms"};
    report.povray.title =
        "POV-Ray 3.7 (no antialiasing, wall time per frame incl. start-up) against sse exact, " + setting;
    report.povray.headers = {"scene",
                             "povray +WT1 s",
                             "povray +WT" + std::to_string(all_threads) + " s",
                             "povray 1x1 px s",
                             "sse 1T s",
                             "sse " + std::to_string(all_threads) + "T s",
                             "povray/sse 1T",
                             "povray/sse " + std::to_string(all_threads) + "T",
                             "(povray - 1x1)/sse 1T"};
    report.first_hit.title =
        "First hits of primary rays only, one thread (Mrays/s, CPU time of the casts; Embree robust: "
        "RTC_SCENE_FLAG_ROBUST, on meshes), " +
        setting;
    report.first_hit.headers = {"scene",
                                "rays",
                                "sse exact",
                                "sse fast",
                                "embree rtcIntersect1",
                                "embree rtcIntersect4 coherent",
                                "sse/embree1",
                                "sse/embree4",
                                "hits sse - embree",
                                "embree robust rtcIntersect1",
                                "sse/embree robust1",
                                "hits sse - embree robust"};
    report.depth.title =
        "Adaptive depth control on scenes with mirrors or glass: the proven cutoff against none "
        "(min_weight 0), one thread, " +
        setting;
    report.depth.headers = {
        "scene",          "tracer",       "rays, no cutoff", "rays, cutoff", "rays left out (cutoff + budget)",
        "px over budget", "s, no cutoff", "s, cutoff",       "speed-up",     "img max change",
        "max PNG levels"};
    const std::string scaling_setting = "median of " + std::to_string(arguments.runs) + " runs, width " +
                                        std::to_string(arguments.width) + " unless shown";
    report.scaling.title =
        "Scaling: time per ray (ns, CPU time of one thread, every ray: primary, shadow, "
        "reflected, refracted; " +
        scaling_setting + ")";
    report.scaling.headers = {"family",
                              "primitives",
                              "sse bvh ns/ray",
                              "sse brute ns/ray",
                              "ref<double> bvh ns/ray",
                              "ref<double> brute ns/ray",
                              "sse bvh growth from ~100",
                              "widths: sse bvh / brute / ref bvh / brute",
                              "rays per pixel"};
    report.scaling_peers.title =
        "Scaling against peers: first hits of primary rays (ns/ray, sse --accel " + accel_name(arguments.accel) +
        "; Embree on the widest kernels this CPU runs and on its SSE4.2 ones, on meshes also with "
        "RTC_SCENE_FLAG_ROBUST, and its coherent rtcIntersect4/8/16 on the widest and on SSE4.2, the fastest shown) "
        "and whole renders (s, sse --accel " +
        accel_name(arguments.accel) +
        ") "
        "against POV-Ray 3.7 +WT1 without its start-up "
        "(its trace, as its statistics give it); CPU time of one thread, " +
        scaling_setting;
    report.scaling_peers.headers = {"family",
                                    "primitives",
                                    "first-hit rays",
                                    "sse first hit ns/ray",
                                    "embree rtcIntersect1 ns/ray",
                                    "embree/sse",
                                    "embree sse4.2 ns/ray",
                                    "embree sse4.2/sse",
                                    "embree robust ns/ray",
                                    "embree robust/sse",
                                    "embree robust sse4.2 ns/ray",
                                    "embree robust sse4.2/sse",
                                    "embree coherent packets ns/ray",
                                    "embree packet lanes",
                                    "embree packets/sse",
                                    "embree sse4.2 coherent packets ns/ray",
                                    "embree sse4.2 packet lanes",
                                    "embree sse4.2 packets/sse",
                                    "image",
                                    "povray +WT1 s (process)",
                                    "povray parse + bounding s",
                                    "povray trace s",
                                    "sse render s",
                                    "povray trace/sse",
                                    "povray trace ns/ray",
                                    "10x budget ns/ray"};
    report.scaling_build.title = "Scaling: BVH build on one thread (CPU time, " + scaling_setting +
                                 "); bytes of its nodes and leaf items per item";
    report.scaling_build.headers = {"family",         "primitives",      "bvh items",
                                    "bvh nodes",      "sse build ms",    "sse M items/s",
                                    "bytes per item", "embree build ms", "embree M prims/s"};
    report.scaling_threads.title = "Scaling: the SSE tracer with its BVH on " + std::to_string(all_threads) +
                                   " threads against one at the largest size (wall time of the pixel loop, " +
                                   scaling_setting + ")";
    report.scaling_threads.headers = {
        "family",   "primitives",          "image", "1 thread s", std::to_string(all_threads) + " threads s",
        "speed-up", "images bit-identical"};
    report.scaling_floor.title =
        "Scaling: the memory floor of this machine (ns per load of a 64-byte line from a random cycle on 2 MB pages, "
        "one chase at a time and 32 interleaved; median of " +
        std::to_string(arguments.runs) + " runs)";
    report.scaling_floor.headers = {"load", "buffer", "dependent ns/load", "32 in flight ns/load"};
    const std::string crossover_setting = "the SSE tracer, CPU time of one thread per ray (every ray), " +
                                          std::to_string(crossover_width(arguments)) + " wide, median of " +
                                          std::to_string(arguments.runs) + " alternated runs";
    report.scaling_crossover.title =
        "Scaling: the crossover of --accel auto, brute force against the BVH on a grid of each kind on a floor (" +
        crossover_setting + "); auto's weight: what brute force spends a packet, in sphere tests, a BVH above " +
        std::to_string(sse::bvh_crossover) + ", or " + std::to_string(sse::bvh_crossover_with_secondary_rays) +
        " where a material reflects or transmits";
    report.scaling_crossover.headers = {
        "kind",        "material",     "objects",    "primitives", "auto weight",
        "auto builds", "brute ns/ray", "bvh ns/ray", "bvh/brute",  "images bit-identical"};
    report.scaling_crossover_summary.title =
        "Scaling: where the BVH pays (faster at that size and every larger one) and where --accel auto builds it (" +
        crossover_setting + ")";
    report.scaling_crossover_summary.headers = {"kind",
                                                "material",
                                                "bvh faster from objects",
                                                "its auto weight",
                                                "auto's bvh from objects",
                                                "its auto weight",
                                                "sizes where auto's choice is over 5% slower"};
    return report;
}

// Each table with the suffix of its CSV file: the trade table is FILE itself, the others are beside it.
struct Output {
    const BenchTable* table;
    const char* suffix;
};

std::vector<Output> outputs_of(const Report& report) {
    return {{&report.trade, ""},
            {&report.summary, "summary"},
            {&report.process, "process"},
            {&report.povray, "povray"},
            {&report.first_hit, "first-hit"},
            {&report.depth, "depth"},
            {&report.scaling, "scaling"},
            {&report.scaling_peers, "scaling-peers"},
            {&report.scaling_build, "scaling-build"},
            {&report.scaling_threads, "scaling-threads"},
            {&report.scaling_floor, "scaling-floor"},
            {&report.scaling_crossover, "scaling-crossover"},
            {&report.scaling_crossover_summary, "scaling-crossover-summary"}};
}

// The tables with rows, as Markdown in one file and as CSV: FILE, FILE-summary.csv, FILE-povray.csv, ...
void write_outputs(const BenchArguments& arguments, const std::vector<Output>& outputs) {
    if (!arguments.markdown_path.empty()) {
        std::string text;
        for (const Output& output : outputs) {
            text += to_markdown(*output.table);
        }
        io::write_text_atomically(arguments.markdown_path, text);
    }
    if (!arguments.csv_path.empty()) {
        fs::path csv(arguments.csv_path);
        for (const Output& output : outputs) {
            std::string suffix = *output.suffix == 0 ? "" : std::string("-") + output.suffix;
            io::write_text_atomically(csv.parent_path() / (csv.stem().string() + suffix + csv.extension().string()),
                                      to_csv(*output.table));
        }
    }
}

int run_bench(const BenchArguments& arguments) {
    if (std::string reason = tracer_unavailable_reason("sse"); !reason.empty()) {
        std::cerr << "twinray bench: " << reason << "\n";
        return exit_cpu_unsupported;
    }
    std::vector<std::string> scene_paths = arguments.scaling_only     ? std::vector<std::string>{}
                                           : arguments.scenes.empty() ? default_scenes()
                                                                      : arguments.scenes;
    if (scene_paths.empty() && !arguments.scaling_only) {
        std::cerr << "twinray bench: no scenes given and no scenes/*.json in the current folder\n";
        return exit_usage;
    }
    int all_threads = resolve_thread_count(arguments.threads);
    std::vector<Configuration> configurations = trade_configurations(all_threads);
    add_plugin_configurations(arguments.plugins, configurations);
    std::vector<std::pair<std::string, scene::Scene>> scenes;
    for (const std::string& path : scene_paths) {
        try {
            scenes.emplace_back(fs::path(path).stem().string(), scene::load_scene(path));
        } catch (const scene::SceneError& error) {
            std::cerr << "twinray bench: invalid scene: " << error.what() << "\n";
            return exit_invalid_scene;
        }
    }
    Report report = empty_report(all_threads, arguments);
    std::vector<Summary> summaries(configurations.size());
    std::optional<fs::path> povray = arguments.peers ? pov::find_povray() : std::nullopt;
    for (std::size_t i = 0; i < scenes.size(); ++i) {
        const auto& [name, scene] = scenes[i];
        std::vector<double> sse_seconds;
        try {
            bench_scene(name, scene, arguments, configurations, summaries, sse_seconds, report);
        } catch (const plugin::PluginError& error) {
            std::cerr << "\ntwinray bench: " << error.what() << "\n";
            return plugin_exit_status(error);
        }
        bench_depth_control(name, scene, arguments, report);
        try {
            bench_process(name, scene_paths[i], scene, arguments, report);
        } catch (const std::exception& error) {
            std::cerr << "twinray bench: the whole process of " << name << " left out: " << error.what() << "\n";
        }
        if (povray) {
            try {
                bench_povray(name, scene, arguments, *povray, all_threads, sse_seconds, report);
            } catch (const pov::PovrayError& error) {
                std::cerr << "twinray bench: POV-Ray failed on " << name << ", left out of its table: " << error.what()
                          << "\n";
            }
        }
        if (arguments.peers) {
            bench_first_hits(name, scene, arguments.width, arguments.runs, arguments.accel, report);
        }
        std::fputs(".", stderr);
    }
    if (!scenes.empty()) {
        add_summary(configurations, summaries, report);
        std::fputs("\n", stderr);
    }
    if (arguments.scaling || arguments.scaling_only) {
        bench_scaling(arguments, all_threads, povray, report);
        if (arguments.floor) {
            std::fputs("scaling: the memory floor\n", stderr);
            bench_memory_floor(arguments.runs, report);
        }
        if (arguments.crossover) {
            bench_crossover(crossover_width(arguments), arguments.runs, report);
        }
    }
    std::vector<Output> outputs;
    for (const Output& output : outputs_of(report)) {
        if (!output.table->rows.empty()) {
            outputs.push_back(output);
            std::fputs(to_console(*output.table).c_str(), stdout);
        }
    }
    if (arguments.peers && !povray) {
        std::puts("POV-Ray: not installed (no povray on PATH), so no POV-Ray table.");
    }
    try {
        write_outputs(arguments, outputs);
    } catch (const io::FileWriteError& error) {
        std::cerr << "twinray bench: " << error.what() << "\n";
        return exit_output_error;
    }
    return exit_success;
}

}  // namespace
}  // namespace twinray::cli::bench

namespace twinray::cli {

void add_bench_command(CLI::App& app, std::function<int()>& run) {
    using namespace bench;
    auto arguments = std::make_shared<BenchArguments>();
    CLI::App* command = app.add_subcommand(
        "bench",
        "Speed against accuracy: every tracer and precision knob on each scene, against reference<double>, POV-Ray "
        "and Embree; and the whole process (start-up, loading, writing)");
    CLI::Option* scenes =
        command->add_option("scenes", arguments->scenes, "Scene files (default: every scenes/*.json)");
    command->add_option("--runs", arguments->runs, "Runs; each renders every configuration once; medians are reported")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    command
        ->add_option("--width", arguments->width,
                     "Render width; the height keeps each scene's aspect (long enough renders to time well)")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    command->add_option("--threads", arguments->threads, "Threads of the multi-threaded columns (default: all cores)")
        ->check(CLI::Range(1, 1024));
    command->add_flag("--scaling", arguments->scaling,
                      "Also time scenes of 10 to 1000000 primitives (a sphere field, the sphereflake, a lattice of "
                      "cylinders, a sphere mesh, the SPD tetra): both tracers with and without their BVH, Embree, "
                      "POV-Ray, the BVH's build, threads");
    command->add_flag("--scaling-only", arguments->scaling_only, "The scaling tables alone: no scene is rendered")
        ->excludes(scenes);
    command
        ->add_option("--scaling-max", arguments->scaling_max,
                     "The largest size --scaling asks for (10, 100, ... up to it; 100000 for a quicker run)")
        ->check(CLI::Range(10, max_generated_primitives))
        ->capture_default_str();
    command->add_flag("!--no-peers", arguments->peers, "Leave out POV-Ray and the first-hit table (Embree)");
    command->add_flag("!--no-floor", arguments->floor,
                      "Leave out --scaling's memory floor of this machine (a few seconds, a minute under a sanitizer)");
    command->add_flag("!--no-crossover", arguments->crossover,
                      "Leave out --scaling's crossover of --accel auto: grids of each kind, brute force against the "
                      "BVH (about a minute at --runs 5)");
    add_accel_option(*command, arguments->accel);
    add_plugin_option(*command, arguments->plugins);
    command->add_option("--csv", arguments->csv_path,
                        "Write the table as CSV to FILE, and the other tables beside it (FILE-summary.csv, ...)");
    command->add_option("--markdown", arguments->markdown_path, "Write every table as Markdown to FILE");
    command->callback([arguments, &run] { run = [arguments] { return run_bench(*arguments); }; });
}

}  // namespace twinray::cli
