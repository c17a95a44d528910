#include "cli/pov_command.h"

#include "cli/exit_codes.h"
#include "io/atomic_file.h"
#include "pov/exporter.h"
#include "scene/loader.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

namespace twinray::cli {
namespace {

namespace fs = std::filesystem;

struct PovArguments {
    std::string scene_path;
    std::string output_path;
    int width = 0;
    int height = 0;
};

int run_pov(const PovArguments& arguments) {
    fs::path output = arguments.output_path.empty() ? fs::path(fs::path(arguments.scene_path).stem().string() + ".pov")
                                                    : fs::path(arguments.output_path);
    if (std::string problem = io::output_folder_problem(output); !problem.empty()) {
        std::cerr << "twinray pov: cannot write " << output.string() << ": " << problem << "\n";
        return exit_output_error;
    }
    scene::Scene scene;
    try {
        scene = scene::load_scene(arguments.scene_path);
    } catch (const scene::SceneError& error) {
        std::cerr << "twinray pov: invalid scene: " << error.what() << "\n";
        return exit_invalid_scene;
    }
    scene::ImageSize size{};
    try {
        size = scene::resolve_image_size(scene, arguments.width, arguments.height);
    } catch (const std::invalid_argument& error) {
        std::cerr << "twinray pov: " << error.what() << "\n";
        return exit_usage;
    }
    try {
        io::write_text_atomically(output, pov::export_pov(scene, size.width, size.height));
    } catch (const io::FileWriteError& error) {
        std::cerr << "twinray pov: " << error.what() << "\n";
        return exit_output_error;
    }
    std::printf("scene:       %s\n", arguments.scene_path.c_str());
    std::printf("resolution:  %d x %d\n", size.width, size.height);
    std::printf("wrote:       %s\n", output.string().c_str());
    std::printf("render with: povray +I%s +O%s.png +W%d +H%d -D -A +FN8 File_Gamma=1.0\n", output.string().c_str(),
                output.stem().string().c_str(), size.width, size.height);
    return exit_success;
}

}  // namespace

void add_pov_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<PovArguments>();
    CLI::App* command =
        app.add_subcommand("pov", "Export a scene as a POV-Ray 3.7 scene (.pov) that renders the same image");
    command->add_option("scene", arguments->scene_path, "Scene file (twinray-scene/1 JSON)")->required();
    command->add_option("-o,--output", arguments->output_path, "Output POV-Ray scene; default: SCENE's name .pov");
    command->add_option("--width", arguments->width, "Image width; alone, the height follows the scene's aspect ratio")
        ->check(CLI::Range(1, 16384));
    command
        ->add_option("--height", arguments->height, "Image height; alone, the width follows the scene's aspect ratio")
        ->check(CLI::Range(1, 16384));
    command->callback([arguments, &run] { run = [arguments] { return run_pov(*arguments); }; });
}

}  // namespace twinray::cli
