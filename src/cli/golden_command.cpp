#include "cli/golden_command.h"

#include "cli/exit_codes.h"
#include "compare/image_compare.h"
#include "image/image_file.h"
#include "reference/tracer.h"
#include "scene/loader.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace twinray::cli {
namespace {

namespace fs = std::filesystem;

struct GoldenArguments {
    bool update = false;
    std::vector<std::string> scenes;
    std::string scenes_folder = "scenes";
    std::string golden_folder = "golden";
};

std::vector<std::string> all_scenes(const fs::path& folder) {
    std::vector<std::string> paths;
    for (const auto& entry : fs::directory_iterator(folder)) {
        if (entry.path().extension() == ".json") {
            paths.push_back(entry.path().string());
        }
    }
    std::sort(paths.begin(), paths.end());
    return paths;
}

// What changes against the image it replaces: every pixel with any channel moved by a level.
std::string change_against(const fs::path& old_path, const Image& image) {
    if (!fs::exists(old_path)) {
        return "new";
    }
    try {
        compare::Thresholds any_level{0.5 / 255.0, 0, 1, 0.5 / 255.0, 0};
        compare::Metrics m = compare::measure(compare::read_image(old_path), image, any_level);
        if (m.fail_pixels == 0) {
            return "unchanged";
        }
        char text[128];
        std::snprintf(text, sizeof text, "%ld pixels changed, max %.0f/255", m.fail_pixels, m.max_error * 255.0);
        return text;
    } catch (const compare::ImageReadError& error) {
        return std::string("replaces an unreadable or differently sized image (") + error.what() + ")";
    }
}

int run_golden(const GoldenArguments& arguments) {
    if (!arguments.update) {
        std::cerr << "twinray golden: nothing to do; golden images change only on purpose: pass --update "
                     "(ctest -L golden checks them)\n";
        return exit_usage;
    }
    std::vector<std::string> scenes;
    try {
        scenes = arguments.scenes.empty() ? all_scenes(arguments.scenes_folder) : arguments.scenes;
    } catch (const fs::filesystem_error& error) {
        std::cerr << "twinray golden: " << error.what() << "\n";
        return exit_usage;
    }
    for (const std::string& path : scenes) {
        scene::Scene scene;
        try {
            scene = scene::load_scene(path);
        } catch (const scene::SceneError& error) {
            std::cerr << "twinray golden: invalid scene: " << error.what() << "\n";
            return exit_invalid_scene;
        }
        Image image = compare::quantized_8bit(reference::render<double>(scene, {}).image);
        fs::path target = fs::path(arguments.golden_folder) / (fs::path(path).stem().string() + ".png");
        std::string change = change_against(target, image);
        try {
            write_image(image, target);
        } catch (const ImageFileError& error) {
            std::cerr << "twinray golden: " << error.what() << "\n";
            return exit_output_error;
        }
        std::printf("%-40s %s\n", target.string().c_str(), change.c_str());
    }
    return exit_success;
}

}  // namespace

void add_golden_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<GoldenArguments>();
    CLI::App* command = app.add_subcommand(
        "golden",
        "Regenerate golden images: the reference tracer's 8-bit render of each scene, written atomically, with\n"
        "what changed per scene. Never runs implicitly: `ctest -L golden` only checks.");
    command->add_flag("--update", arguments->update,
                      "Write the golden images (required: updating is always on purpose)");
    command->add_option("scenes", arguments->scenes, "Scene files (default: every .json in --scenes-folder)");
    command->add_option("--scenes-folder", arguments->scenes_folder, "Where the scenes are")->capture_default_str();
    command->add_option("--golden-folder", arguments->golden_folder, "Where the golden images are")
        ->capture_default_str();
    command->callback([arguments, &run] { run = [arguments] { return run_golden(*arguments); }; });
}

}  // namespace twinray::cli
