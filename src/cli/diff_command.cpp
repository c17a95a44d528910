#include "cli/diff_command.h"

#include "cli/exit_codes.h"
#include "cli/tracers.h"
#include "compare/image_compare.h"
#include "compare/tolerances.h"
#include "image/image_file.h"
#include "io/atomic_file.h"
#include "pov/exporter.h"
#include "pov/povray_runner.h"
#include "scene/loader.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
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
    double map_scale = 4.0 / 255.0;
    bool with_povray = false;
    Accel accel = Accel::automatic;
};

// POV-Ray's render of the scene against the reference's, both as 8-bit PNGs store them.
struct PovrayColumn {
    double seconds = 0;
    compare::Metrics metrics;
    long within_two_levels = 0;
};

struct TimedRender {
    Image image;
    double seconds;
};

struct SceneReport {
    std::string name;
    std::string scene_path;
    compare::SceneTolerances tolerances;
    compare::Metrics metrics;
    compare::Verdict verdict;
    double reference_seconds, sse_seconds;
    int width, height;
    std::vector<compare::PixelError> worst;
    std::optional<PovrayColumn> povray;
};

TimedRender timed_render(const std::string& tracer, const scene::Scene& scene, int width,
                         Accel accel = Accel::automatic) {
    RenderOptions options;
    options.width = width;
    options.accel = accel;
    auto start = std::chrono::steady_clock::now();
    RenderResult result = render_with(tracer, scene, options);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return {compare::clamped(result.image), seconds};
}

std::string html_escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

std::string format(const char* pattern, double value) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, pattern, value);
    return buffer;
}

// The size is given explicitly so the command finds the same pixel whatever --width diff ran at.
std::string probe_command(const SceneReport& report, const compare::PixelError& pixel) {
    return "twinray probe " + report.scene_path + " --pixel " + std::to_string(pixel.x) + "," +
           std::to_string(pixel.y) + " --width " + std::to_string(report.width) + " --height " +
           std::to_string(report.height);
}

std::string percent(long count, long total) {
    return format("%.4f%%", 100.0 * static_cast<double>(count) / static_cast<double>(std::max(total, 1L)));
}

std::string report_row(const SceneReport& r) {
    std::ostringstream html;
    const compare::Thresholds& t = r.tolerances.sse;
    html << "<tr class=\"" << compare::to_string(r.verdict) << "\">\n"
         << "<td><h2>" << html_escape(r.name) << "</h2><p class=\"verdict\">" << compare::to_string(r.verdict) << "</p>"
         << "<p>" << r.width << " &times; " << r.height << "</p>"
         << "<p>reference " << format("%.3f s", r.reference_seconds) << "<br>sse " << format("%.3f s", r.sse_seconds)
         << "<br>speed-up " << format("%.1f&times;", r.reference_seconds / r.sse_seconds) << "</p></td>\n";
    std::vector<std::string> images = {"reference", "sse", "error", "mask"};
    if (r.povray) {
        images.insert(images.end(), {"povray", "povray_error"});
    }
    for (const std::string& image : images) {
        std::string file = html_escape(r.name) + "/" + image + ".png";
        html << "<td><a href=\"" << file << "\"><img src=\"" << file << "\" alt=\"" << image << "\"></a></td>\n";
    }
    html << "<td class=\"metrics\"><table>"
         << "<tr><th>mean</th><td>" << format("%.3g", r.metrics.mean_error) << "</td></tr>"
         << "<tr><th>RMS</th><td>" << format("%.3g", r.metrics.rms_error) << "</td></tr>"
         << "<tr><th>PSNR</th><td>" << format("%.1f dB", r.metrics.psnr) << "</td></tr>"
         << "<tr><th>max</th><td>" << format("%.4f", r.metrics.max_error) << " at " << r.metrics.max_x << ","
         << r.metrics.max_y << " ("
         << "RGB"[std::clamp(r.metrics.max_channel, 0, 2)] << ")</td></tr>"
         << "<tr><th>over " << format("%.4g", t.fail) << "</th><td>" << r.metrics.fail_pixels << " ("
         << percent(r.metrics.fail_pixels, r.metrics.pixel_count) << ")</td></tr>"
         << "<tr><th>thresholds</th><td>fail&nbsp;%&nbsp;&le;&nbsp;" << format("%.4g", t.fail_percent)
         << ", max&nbsp;&le;&nbsp;" << format("%.4g", t.hard_fail) << "</td></tr></table>";
    if (r.povray) {
        html << "<p>POV-Ray " << format("%.3f s", r.povray->seconds)
             << " (one thread, with start-up): " << percent(r.povray->within_two_levels, r.povray->metrics.pixel_count)
             << " of pixels within 2/255 of the reference, max "
             << format("%.0f/255", r.povray->metrics.max_error * 255.0) << "</p>";
    }
    if (!r.tolerances.why.empty()) {
        html << "<p class=\"why\">" << html_escape(r.tolerances.why) << "</p>";
    }
    html << "<details><summary>worst " << r.worst.size() << " pixels</summary><ol>";
    for (const compare::PixelError& pixel : r.worst) {
        html << "<li>(" << pixel.x << ", " << pixel.y << ") " << format("%.4f", pixel.error) << "<br><code>"
             << html_escape(probe_command(r, pixel)) << "</code></li>";
    }
    html << "</ol></details></td>\n</tr>\n";
    return html.str();
}

std::string report_page(const std::vector<SceneReport>& reports, double map_scale, bool with_povray) {
    std::ostringstream html;
    html
        << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>twinray diff</title>\n<style>\n"
        << "body{font-family:sans-serif;margin:1em;background:#fafafa;color:#222}\n"
        << "table.report{border-collapse:collapse}\n.report>tbody>tr>td{border-top:1px solid "
           "#ccc;padding:.5em;vertical-align:top}\n"
        << "img{max-width:240px;image-rendering:pixelated;display:block}\nh2{margin:0}\n"
        << ".PASS .verdict{color:#080;font-weight:bold}.WARN .verdict{color:#b60;font-weight:bold}.FAIL "
           ".verdict{color:#c00;font-weight:bold}\n"
        << ".metrics "
           "th{text-align:left;padding-right:.5em;font-weight:normal;color:#555}.metrics{min-width:20em}.why{max-width:"
           "24em;font-size:80%;color:#555}\n"
        << "code{font-size:85%}\n.legend img{width:300px;height:16px}\n.legend span{display:inline-block;width:150px}\n"
        << "</style></head><body>\n<h1>twinray diff: reference&lt;double&gt; against sse</h1>\n"
        << "<p>Images are compared as stored (clamped to [0, 1]). Thresholds per scene: "
           "<code>tests/tolerances.json</code>.</p>\n"
        << "<div class=\"legend\"><p>Error map: largest channel difference per pixel,</p><img src=\"legend.png\" "
           "alt=\"legend\">"
        << "<span>0</span><span style=\"text-align:right\">&ge; " << format("%.4g", map_scale) << " ("
        << format("%.3g", map_scale * 255.0)
        << "/255)</span><p>Mask: white where a pixel is over the scene's fail threshold; the reference, dimmed, "
           "elsewhere.</p></div>\n"
        << "<table class=\"report\"><thead><tr><th>scene</th><th>reference</th><th>sse</th><th>error "
           "map</th><th>mask</th>"
        << (with_povray ? "<th>POV-Ray</th><th>POV-Ray error map (vs reference, 8-bit)</th>" : "")
        << "<th>metrics</th></tr></thead><tbody>\n";
    for (const SceneReport& report : reports) {
        html << report_row(report);
    }
    html << "</tbody></table>\n</body></html>\n";
    return html.str();
}

PovrayColumn povray_column(const fs::path& povray, const scene::Scene& scene, const Image& reference,
                           const fs::path& scene_folder, double map_scale) {
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
    write_image(compare::error_heat_map(reference_8bit, pov_image, map_scale), scene_folder / "povray_error.png");
    return column;
}

int run_diff(const DiffArguments& arguments) {
    if (std::string reason = tracer_unavailable_reason("sse"); !reason.empty()) {
        std::cerr << "twinray diff: " << reason << "\n";
        return exit_cpu_unsupported;
    }
    compare::ToleranceManifest manifest = compare::ToleranceManifest::defaults();
    if (fs::exists(arguments.tolerances)) {
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
        write_image(compare::heat_map_legend(256, 1), folder / "legend.png");
        for (const auto& [path, scene] : scenes) {
            SceneReport report;
            report.name = fs::path(path).stem().string();
            report.scene_path = path;
            report.tolerances = manifest.for_scene(report.name);
            TimedRender reference = timed_render("reference", scene, arguments.width, arguments.accel);
            TimedRender sse = timed_render("sse", scene, arguments.width, arguments.accel);
            report.reference_seconds = reference.seconds;
            report.sse_seconds = sse.seconds;
            report.width = reference.image.width();
            report.height = reference.image.height();
            report.metrics = compare::measure(reference.image, sse.image, report.tolerances.sse);
            report.verdict = compare::judge(report.metrics, report.tolerances.sse);
            report.worst = compare::worst_pixels(reference.image, sse.image, 10);
            fs::path scene_folder = folder / report.name;
            fs::create_directories(scene_folder);
            write_image(reference.image, scene_folder / "reference.png");
            write_image(sse.image, scene_folder / "sse.png");
            write_image(compare::error_heat_map(reference.image, sse.image, arguments.map_scale),
                        scene_folder / "error.png");
            write_image(compare::fail_mask(reference.image, sse.image, report.tolerances.sse.fail),
                        scene_folder / "mask.png");
            if (povray) {
                report.povray = povray_column(*povray, scene, reference.image, scene_folder, arguments.map_scale);
            }
            std::printf("%-12s speed-up %6.1fx  max error %.4f  over %.4g: %8s  %s\n", report.name.c_str(),
                        report.reference_seconds / report.sse_seconds, report.metrics.max_error,
                        report.tolerances.sse.fail,
                        percent(report.metrics.fail_pixels, report.metrics.pixel_count).c_str(),
                        compare::to_string(report.verdict));
            std::fflush(stdout);
            worst_verdict = std::max(worst_verdict, report.verdict);
            reports.push_back(std::move(report));
        }
        io::write_text_atomically(folder / "index.html",
                                  report_page(reports, arguments.map_scale, arguments.with_povray));
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
    }
    std::printf("report: %s\n", (folder / "index.html").string().c_str());
    return static_cast<int>(worst_verdict);
}

}  // namespace

void add_diff_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<DiffArguments>();
    CLI::App* command = app.add_subcommand(
        "diff",
        "Render each scene with the reference and the SSE tracer and write, per scene, both images, an error heat\n"
        "map, a mask of failing pixels and DIR/index.html (opens from disk). Prints one line per scene.\n"
        "Exit status: the worst verdict, 0 pass, 1 warn, 2 fail; 2 also for an invalid scene, 3 unwritable DIR.");
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
    command->add_option("--map-scale", arguments->map_scale, "Error shown brightest in the heat maps")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    command->add_flag(
        "--pov", arguments->with_povray,
        "Also render each scene with POV-Ray 3.7 (twinray pov) and show its image and error map against the reference");
    add_accel_option(*command, arguments->accel);
    command->callback([arguments, &run] { run = [arguments] { return run_diff(*arguments); }; });
}

}  // namespace twinray::cli
