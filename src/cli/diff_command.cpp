#include "cli/diff_command.h"

#include "accuracy/attribution.h"
#include "cli/diff_report.h"
#include "cli/exit_codes.h"
#include "cli/tracers.h"
#include "compare/failing_clusters.h"
#include "compare/image_compare.h"
#include "compare/tolerances.h"
#include "image/image_file.h"
#include "io/atomic_file.h"
#include "plugin/plugin.h"
#include "pov/exporter.h"
#include "pov/povray_runner.h"
#include "scene/loader.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace twinray::cli {
namespace {

namespace fs = std::filesystem;

struct DiffArguments {
    std::vector<std::string> scenes;
    std::string output_folder;
    std::string tolerances = "tests/tolerances.json";
    int width = 0;
    double linear_map_scale = 0;  // > 0: the heat maps are linear up to it instead of logarithmic
    bool with_povray = false;
    std::string json_path;
    Accel accel = Accel::automatic;
    std::string tracer = default_tracer;  // the tracer judged against the reference
};

struct TimedRender {
    Image image;
    double seconds;
};

// The image as stored (clamped) and the time spent tracing it: the tracer's set-up (compiling the scene) is
// left out, as is loading the scene, so the speed-up compares tracing with tracing.
TimedRender timed_render(const tracing::AnyTracer& tracer, int width) {
    RenderOptions options;
    options.width = width;
    RenderResult result = tracer.render(options);
    return {compare::clamped(result.image), result.tracing_seconds};
}

// Failing pixels with at most this many pixels between them are boxed as one cluster; the largest are boxed.
constexpr int cluster_gap = 4;
constexpr int max_clusters = 20;

compare::HeatMapScale heat_map_scale(const DiffArguments& arguments) {
    return arguments.linear_map_scale > 0 ? compare::HeatMapScale::linear(arguments.linear_map_scale)
                                          : compare::HeatMapScale::logarithmic(1e-7, 1);
}

// Why the pixels over the warn threshold differ (accuracy/attribution.h), and the worst unexplained ones.
void print_attribution(const SceneReport& report) {
    const accuracy::Attribution& a = report.attribution;
    std::printf("%-12s why:", "");
    for (int c = 0; c < accuracy::cause_count; ++c) {
        std::printf(" %s %ld", accuracy::cause_name(static_cast<accuracy::Cause>(c)),
                    a.counts[static_cast<std::size_t>(c)]);
    }
    std::printf("%s\n", report.attribution_failure.empty() ? "" : ("  -> FAIL: " + report.attribution_failure).c_str());
    for (std::size_t i = 0; i < std::min<std::size_t>(3, a.unexplained.size()); ++i) {
        const accuracy::AttributedPixel& pixel = a.unexplained[i];
        std::printf("%-12s unexplained: %s at depth %d, ray %.2g rad off (band %.2g): %s\n", "",
                    pixel.cause.what.c_str(), pixel.cause.depth, pixel.cause.deviation, pixel.cause.band,
                    probe_command(report, {pixel.x, pixel.y, pixel.error}).c_str());
    }
}

// What scripts read of a diff (--json): per scene its verdict and metrics, the pixels per cause and every
// unexplained pixel with its probe command.
nlohmann::json report_json(const std::vector<SceneReport>& reports) {
    nlohmann::json scenes = nlohmann::json::array();
    for (const SceneReport& r : reports) {
        nlohmann::json causes = nlohmann::json::object();
        for (int c = 0; c < accuracy::cause_count; ++c) {
            causes[accuracy::cause_name(static_cast<accuracy::Cause>(c))] =
                r.attribution.counts[static_cast<std::size_t>(c)];
        }
        nlohmann::json unexplained = nlohmann::json::array();
        for (const accuracy::AttributedPixel& pixel : r.attribution.unexplained) {
            unexplained.push_back({{"x", pixel.x},
                                   {"y", pixel.y},
                                   {"error", pixel.error},
                                   {"what", pixel.cause.what},
                                   {"depth", pixel.cause.depth},
                                   {"deviation", pixel.cause.deviation},
                                   {"band", pixel.cause.band},
                                   {"probe", probe_command(r, {pixel.x, pixel.y, pixel.error})}});
        }
        scenes.push_back({{"name", r.name},
                          {"scene", r.scene_path},
                          {"verdict", compare::to_string(r.verdict)},
                          {"width", r.width},
                          {"height", r.height},
                          {"max_error", r.metrics.max_error},
                          {"rms_error", r.metrics.rms_error},
                          {"pixels_over_fail", r.metrics.fail_pixels},
                          {"pixels_over_warn", r.metrics.warn_pixels},
                          {"causes", causes},
                          {"attribution_failure", r.attribution_failure},
                          {"unexplained", unexplained}});
    }
    return {{"scenes", scenes}};
}

PovrayColumn povray_column(const fs::path& povray, const scene::Scene& scene, const Image& reference,
                           const fs::path& scene_folder, const compare::HeatMapScale& scale) {
    fs::path work = scene_folder / "povray_work";
    fs::create_directories(work);
    auto start = std::chrono::steady_clock::now();
    Image pov_image =
        pov::render_with_povray(povray, work, "scene", pov::export_pov(scene, reference.width(), reference.height()),
                                reference.width(), reference.height());
    PovrayColumn column;
    column.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    Image reference_8bit = compare::quantized_8bit(reference);
    compare::Thresholds two_levels{2.5 / 255.0, 100, 1, 2.5 / 255.0, 100};
    column.metrics = compare::measure(reference_8bit, pov_image, two_levels);
    column.within_two_levels = column.metrics.pixel_count - column.metrics.fail_pixels;
    write_image(pov_image, scene_folder / "povray.png");
    write_image(compare::error_heat_map(reference_8bit, pov_image, scale), scene_folder / "povray_error.png");
    return column;
}

int run_diff(const DiffArguments& arguments) {
    if (std::string reason = tracer_unavailable_reason(arguments.tracer); !reason.empty()) {
        std::cerr << "twinray diff: " << reason << "\n";
        return exit_cpu_unsupported;
    }
    compare::ToleranceManifest manifest = compare::ToleranceManifest::defaults();
    std::string thresholds_source = "the built-in defaults (" + arguments.tolerances + " not found)";
    if (fs::exists(arguments.tolerances)) {
        thresholds_source = arguments.tolerances;
        try {
            manifest = compare::ToleranceManifest::load(arguments.tolerances);
        } catch (const std::runtime_error& error) {
            std::cerr << "twinray diff: invalid tolerances: " << error.what() << "\n";
            return exit_usage;
        }
    }
    std::vector<std::pair<std::string, scene::Scene>> scenes;
    for (const std::string& path : arguments.scenes) {
        try {
            scenes.emplace_back(path, scene::load_scene(path));
        } catch (const scene::SceneError& error) {
            std::cerr << "twinray diff: invalid scene: " << error.what() << "\n";
            return exit_invalid_scene;
        }
    }
    fs::path folder(arguments.output_folder);
    std::error_code made;
    fs::create_directories(folder, made);
    if (made || !fs::is_directory(folder)) {
        std::cerr << "twinray diff: cannot create " << folder.string() << (made ? ": " + made.message() : "") << "\n";
        return exit_output_error;
    }
    std::optional<fs::path> povray;
    if (arguments.with_povray) {
        povray = pov::find_povray();
        if (!povray) {
            std::cerr
                << "twinray diff: --pov needs povray on PATH: install the Debian package `povray` (ci/setup does)\n";
            return exit_usage;
        }
    }
    std::vector<SceneReport> reports;
    compare::Verdict worst_verdict = compare::Verdict::pass;
    try {
        const compare::HeatMapScale scale = heat_map_scale(arguments);
        write_image(compare::heat_map_legend(scale, 400, 1), folder / legend_file);
        std::string judged_label = arguments.tracer;
        for (const auto& [path, scene] : scenes) {
            SceneReport report;
            report.name = fs::path(path).stem().string();
            report.scene_path = path;
            report.tolerances = manifest.for_scene(report.name);
            const std::unique_ptr<tracing::AnyTracer> judged =
                tracing::make_tracer(arguments.tracer, scene, {}, arguments.accel);
            report.judged = arguments.tracer == default_tracer ? "SSE" : judged->description();
            judged_label = report.judged;
            TimedRender reference =
                timed_render(*tracing::make_tracer("reference", scene, {}, arguments.accel), arguments.width);
            TimedRender sse = timed_render(*judged, arguments.width);
            report.reference_seconds = reference.seconds;
            report.sse_seconds = sse.seconds;
            report.width = reference.image.width();
            report.height = reference.image.height();
            report.metrics = compare::measure(reference.image, sse.image, report.tolerances.sse);
            report.verdict = compare::judge(report.metrics, report.tolerances.sse);
            report.worst = compare::worst_pixels(reference.image, sse.image, 10);
            report.clusters = compare::failing_clusters(reference.image, sse.image, report.tolerances.sse.fail,
                                                        cluster_gap, max_clusters);
            report.attribution =
                accuracy::attribute_pixels(scene, reference.image, sse.image, *judged, report.tolerances.sse.warn);
            report.attribution_failure = accuracy::attribution_failure(report.attribution, report.metrics.pixel_count);
            if (!report.attribution_failure.empty()) {
                report.verdict = compare::Verdict::fail;
            }
            fs::path scene_folder = folder / report.name;
            fs::create_directories(scene_folder);
            write_image(reference.image, scene_folder / "reference.png");
            write_image(sse.image, scene_folder / "sse.png");
            write_image(compare::error_heat_map(reference.image, sse.image, scale), scene_folder / "error.png");
            write_image(compare::fail_mask(reference.image, sse.image, report.tolerances.sse.fail),
                        scene_folder / "mask.png");
            if (povray) {
                report.povray = povray_column(*povray, scene, reference.image, scene_folder, scale);
            }
            std::printf("%-12s speed-up %6.1fx  max error %.4f  over %.4g: %8s  %s\n", report.name.c_str(),
                        report.reference_seconds / report.sse_seconds, report.metrics.max_error,
                        report.tolerances.sse.fail,
                        percent(report.metrics.fail_pixels, report.metrics.pixel_count).c_str(),
                        compare::to_string(report.verdict));
            print_attribution(report);
            std::fflush(stdout);
            worst_verdict = std::max(worst_verdict, report.verdict);
            reports.push_back(std::move(report));
        }
        if (!arguments.json_path.empty()) {
            io::write_text_atomically(arguments.json_path, report_json(reports).dump(2) + "\n");
        }
        io::write_text_atomically(folder / "index.html", report_page(std::move(reports), scale, arguments.with_povray,
                                                                     thresholds_source, judged_label));
    } catch (const ImageFileError& error) {
        std::cerr << "twinray diff: " << error.what() << "\n";
        return exit_output_error;
    } catch (const io::FileWriteError& error) {
        std::cerr << "twinray diff: " << error.what() << "\n";
        return exit_output_error;
    } catch (const fs::filesystem_error& error) {
        std::cerr << "twinray diff: " << error.what() << "\n";
        return exit_output_error;
    } catch (const pov::PovrayError& error) {
        std::cerr << "twinray diff: " << error.what() << "\n";
        return exit_internal_error;
    } catch (const plugin::PluginError& error) {
        std::cerr << "twinray diff: " << error.what() << "\n";
        return plugin_exit_status(error);
    }
    std::printf("report: %s\n", (folder / "index.html").string().c_str());
    return static_cast<int>(worst_verdict);
}

}  // namespace

void add_diff_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<DiffArguments>();
    CLI::App* command = app.add_subcommand(
        "diff",
        "Render each scene with the reference and the SSE tracer (or --tracer's) and write, per scene, both images, an "
        "error heat\n"
        "map (logarithmic, 1e-7 to 1), a mask of failing pixels and DIR/index.html, a report for triage that opens\n"
        "from disk: failures first, a filter, failing clusters boxed, the commands to probe and approve. Prints\n"
        "one line per scene.\n"
        "Exit status: the worst verdict, 0 pass, 1 warn, 2 fail; 2 also for an invalid scene, 3 unwritable DIR;\n"
        "7, 8, 9 a plug-in that cannot be used, lacks a kind, breaks the contract (README).");
    command->add_option("scenes", arguments->scenes, "Scene files")->required();
    command->add_option("-o,--output", arguments->output_folder, "Folder for the report (created if missing)")
        ->required();
    command
        ->add_option("--tolerances", arguments->tolerances,
                     "Per-scene thresholds (built-in defaults if the file is missing)")
        ->capture_default_str();
    command
        ->add_option("--width", arguments->width, "Render width (default: each scene's; the height keeps its aspect)")
        ->check(CLI::Range(1, 16384));
    command
        ->add_option("--map-scale", arguments->linear_map_scale,
                     "Linear heat maps, brightest at this error (default: logarithmic from 1e-7 to 1)")
        ->check(CLI::PositiveNumber);
    command->add_option(
        "--json", arguments->json_path,
        "Also write every scene's verdict, metrics, causes per class and unexplained pixels (with their "
        "probe commands) to FILE as JSON");
    command->add_flag(
        "--pov", arguments->with_povray,
        "Also render each scene with POV-Ray 3.7 (twinray pov) and show its image and error map against the reference");
    add_accel_option(*command, arguments->accel);
    add_tracer_option(*command, arguments->tracer);
    command->callback([arguments, &run] { run = [arguments] { return run_diff(*arguments); }; });
}

}  // namespace twinray::cli
