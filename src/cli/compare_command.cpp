#include "cli/compare_command.h"

#include "cli/exit_codes.h"
#include "compare/image_compare.h"
#include "image/image_file.h"

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

namespace twinray::cli {
namespace {

struct CompareArguments {
    std::string first, second;
    compare::Thresholds thresholds;
    std::string map_path;
    double map_scale = 0;
};

int run_compare(const CompareArguments& arguments) {
    Image a(1, 1), b(1, 1);
    try {
        a = compare::read_image(arguments.first);
        b = compare::read_image(arguments.second);
    } catch (const compare::ImageReadError& error) {
        std::cerr << "twinray compare: " << error.what() << "\n";
        return exit_unreadable_image;
    }
    compare::Metrics metrics;
    try {
        metrics = compare::measure(a, b, arguments.thresholds);
    } catch (const compare::ImageReadError& error) {
        std::cerr << "twinray compare: " << arguments.first << " and " << arguments.second << ": " << error.what()
                  << "\n";
        return exit_unreadable_image;
    }
    compare::Verdict verdict = compare::judge(metrics, arguments.thresholds);
    const char* channels = "RGB";
    double total = static_cast<double>(metrics.pixel_count);
    std::printf("Comparing \"%s\" and \"%s\" (%d x %d)\n", arguments.first.c_str(), arguments.second.c_str(), a.width(),
                a.height());
    std::printf("  Mean error = %.6g\n  RMS error = %.6g\n  Peak SNR = %.6g\n", metrics.mean_error, metrics.rms_error,
                metrics.psnr);
    std::printf("  Max error  = %.6g @ (%d, %d, %c)\n", metrics.max_error, metrics.max_x, metrics.max_y,
                channels[std::min(std::max(metrics.max_channel, 0), 2)]);
    std::printf("  %ld pixels (%.4g%%) over %.6g (warn)\n", metrics.warn_pixels,
                100.0 * static_cast<double>(metrics.warn_pixels) / total, arguments.thresholds.warn);
    std::printf("  %ld pixels (%.4g%%) over %.6g (fail)\n", metrics.fail_pixels,
                100.0 * static_cast<double>(metrics.fail_pixels) / total, arguments.thresholds.fail);
    if (!arguments.map_path.empty()) {
        double scale = arguments.map_scale > 0 ? arguments.map_scale : arguments.thresholds.fail;
        try {
            write_image(compare::error_heat_map(a, b, compare::HeatMapScale::linear(scale)), arguments.map_path);
        } catch (const ImageFileError& error) {
            std::cerr << "twinray compare: " << error.what() << "\n";
            return exit_output_error;
        }
        std::printf("  error map: %s (inferno, black = 0, brightest >= %.6g)\n", arguments.map_path.c_str(), scale);
    }
    std::printf("%s\n", compare::to_string(verdict));
    return static_cast<int>(verdict);
}

}  // namespace

void add_compare_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<CompareArguments>();
    CLI::App* command = app.add_subcommand(
        "compare",
        "Compare two images like idiff: prints mean, RMS, PSNR, the max error with its pixel and channel, and the\n"
        "pixels over each threshold. Exit status: 0 pass, 1 warn, 2 fail, 4 an image cannot be read or the sizes "
        "differ.");
    command->add_option("first", arguments->first, "Reference image (any format OpenImageIO reads)")->required();
    command->add_option("second", arguments->second, "Image to compare with it")->required();
    command
        ->add_option("--fail", arguments->thresholds.fail, "A pixel fails where any channel differs by more than this")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    command->add_option("--failpercent", arguments->thresholds.fail_percent, "FAIL if more than this % of pixels fail")
        ->check(CLI::Range(0.0, 100.0))
        ->capture_default_str();
    command
        ->add_option("--hardfail", arguments->thresholds.hard_fail,
                     "FAIL if any difference exceeds this (default: none)")
        ->check(CLI::NonNegativeNumber);
    command
        ->add_option("--warn", arguments->thresholds.warn, "A pixel warns where any channel differs by more than this")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    command->add_option("--warnpercent", arguments->thresholds.warn_percent, "WARN if more than this % of pixels warn")
        ->check(CLI::Range(0.0, 100.0))
        ->capture_default_str();
    command->add_option("--map", arguments->map_path, "Also write an error heat map (.png or .exr)");
    command
        ->add_option("--map-scale", arguments->map_scale,
                     "Error shown brightest in the map (default: the --fail threshold)")
        ->check(CLI::PositiveNumber);
    command->callback([arguments, &run] { run = [arguments] { return run_compare(*arguments); }; });
}

}  // namespace twinray::cli
