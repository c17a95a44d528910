#include "cli/probe_arguments.h"

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

namespace twinray::cli::probe {
namespace {

std::vector<std::string> split_commas(const std::string& text) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        std::size_t comma = text.find(',', start);
        parts.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (comma == std::string::npos) {
            return parts;
        }
        start = comma + 1;
    }
}

// The whole token must be the number (from_chars: no locale, no leading space; a leading '+' is allowed).
template <typename Number>
std::optional<Number> parse_number(std::string token) {
    if (!token.empty() && token.front() == '+') {
        token.erase(0, 1);
    }
    Number value{};
    const char* end = token.data() + token.size();
    auto [stop, error] = std::from_chars(token.data(), end, value);
    if (token.empty() || error != std::errc() || stop != end) {
        return std::nullopt;
    }
    return value;
}

void parse_pixel(const std::string& text, Target& target) {
    std::vector<std::string> parts = split_commas(text);
    std::optional<int> x = parts.size() == 2 ? parse_number<int>(parts[0]) : std::nullopt;
    std::optional<int> y = parts.size() == 2 ? parse_number<int>(parts[1]) : std::nullopt;
    if (!x || !y) {
        throw UsageError("--pixel wants X,Y: two integers, counted from 0 at the top-left; got \"" + text + "\"");
    }
    target.is_pixel = true;
    target.x = *x;
    target.y = *y;
}

void parse_ray(const std::string& text, Target& target) {
    std::vector<std::string> parts = split_commas(text);
    std::vector<double> values;
    for (const std::string& part : parts) {
        if (std::optional<double> value = parse_number<double>(part)) {
            values.push_back(*value);
        }
    }
    if (parts.size() != 6 || values.size() != 6) {
        throw UsageError("--ray wants ox,oy,oz,dx,dy,dz: six numbers, the origin then the direction; got \"" + text +
                         "\"");
    }
    for (double value : values) {
        if (!std::isfinite(value)) {
            throw UsageError("--ray: every component must be a finite number; got \"" + text + "\"");
        }
    }
    for (int axis = 0; axis < 3; ++axis) {
        if (std::fabs(values[static_cast<std::size_t>(axis)]) > FLT_MAX) {
            throw UsageError(
                "--ray: the origin is beyond single precision (|component| > 3.4e38), which the sse tracer uses");
        }
    }
    // Normalised after scaling by the largest component, so that neither tiny nor huge values overflow.
    double largest = std::max({std::fabs(values[3]), std::fabs(values[4]), std::fabs(values[5])});
    if (largest == 0) {
        throw UsageError("--ray: the direction (dx,dy,dz) must not be zero");
    }
    Vec3d d{values[3] / largest, values[4] / largest, values[5] / largest};
    double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    target.origin = {values[0], values[1], values[2]};
    target.direction = {d[0] / length, d[1] / length, d[2] / length};
}

}  // namespace

void add_options(CLI::App& command, Arguments& arguments) {
    command.add_option("scene", arguments.scene_path, "Scene file (twinray-scene/1 JSON)")->required();
    command.add_option("--pixel", arguments.pixel, "X,Y: the pixel's primary ray, as render traces it (0,0 top-left)");
    command.add_option("--ray", arguments.ray,
                       "ox,oy,oz,dx,dy,dz: a ray given by hand; the direction is normalised, so t is a distance");
    command
        .add_option("--width", arguments.width,
                    "Image width for --pixel, as render; alone, the height follows the scene's aspect ratio")
        ->check(CLI::Range(1, 16384));
    command
        .add_option("--height", arguments.height,
                    "Image height for --pixel, as render; alone, the width follows the scene's aspect ratio")
        ->check(CLI::Range(1, 16384));
    command.add_flag("--json", arguments.json, "Print one JSON object (docs/probe.md) instead of the table");
}

Target parse_target(const Arguments& arguments) {
    Target target;
    if (arguments.pixel.empty() == arguments.ray.empty()) {
        throw UsageError("give exactly one of --pixel X,Y or --ray ox,oy,oz,dx,dy,dz");
    }
    if (!arguments.pixel.empty()) {
        parse_pixel(arguments.pixel, target);
    } else {
        if (arguments.width != 0 || arguments.height != 0) {
            throw UsageError("--width and --height size the image of --pixel; they mean nothing with --ray");
        }
        parse_ray(arguments.ray, target);
    }
    return target;
}

void place_pixel(const scene::Scene& scene, const Arguments& arguments, Target& target) {
    try {
        scene::ImageSize size = scene::resolve_image_size(scene, arguments.width, arguments.height);
        target.width = size.width;
        target.height = size.height;
    } catch (const std::invalid_argument& error) {
        throw UsageError(error.what());
    }
    if (target.x < 0 || target.x >= target.width || target.y < 0 || target.y >= target.height) {
        throw UsageError("pixel " + std::to_string(target.x) + "," + std::to_string(target.y) + " is outside the " +
                         std::to_string(target.width) + " x " + std::to_string(target.height) + " image (x from 0 to " +
                         std::to_string(target.width - 1) + ", y from 0 to " + std::to_string(target.height - 1) + ")");
    }
}

}  // namespace twinray::cli::probe
