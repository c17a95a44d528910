// `twinray probe`'s command line: its options, and the pixel or ray they name once checked.
#pragma once

#include "render/ray_tree.h"
#include "scene/scene.h"
#include "sse/tracer.h"

#include <CLI/CLI.hpp>

#include <stdexcept>
#include <string>

namespace twinray::cli::probe {

struct Arguments {
    std::string scene_path;
    std::string pixel;
    std::string ray;
    int width = 0;
    int height = 0;
    bool json = false;
    Accel accel = Accel::automatic;
    std::string tracer = "sse";  // the tracer whose tree is set beside the reference's: a name or plugin:PATH
};

// A command line that cannot be probed: exit status 1 (usage), its message on stderr.
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// What to probe: a pixel (its primary ray, as each tracer's render makes it) or a ray given by hand.
struct Target {
    bool is_pixel = false;
    int x = 0, y = 0;
    int width = 0, height = 0;  // of the image the pixel belongs to
    Vec3d origin{};
    Vec3d direction{};  // normalised
};

void add_options(CLI::App& command, Arguments& arguments);

// The pixel or the ray the arguments name, or UsageError. A pixel's image is sized by place_pixel, once
// the scene is loaded.
Target parse_target(const Arguments& arguments);

// Sizes the pixel's image as render does (--width, --height, else the scene's size) and checks that the
// pixel lies in it, or UsageError.
void place_pixel(const scene::Scene& scene, const Arguments& arguments, Target& target);

}  // namespace twinray::cli::probe
