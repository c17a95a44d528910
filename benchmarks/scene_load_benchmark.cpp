// Scene loading, timed and weighed (ci/whole-process, docs/performance.md "Whole process"):
//   scene_load_benchmark write COUNT FILE   writes the sphere field of `twinray bench --scaling` with
//                                           COUNT spheres as a scene file (numbers to 6 digits)
//   scene_load_benchmark load FILE [RUNS]   loads FILE RUNS times (default 5) and prints the median
//                                           time, primitives per second and the peak memory while
//                                           loading above the loaded scene itself, per primitive
#include "scene/loader.h"
#include "scene/sphere_field.h"

#include <malloc.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace {

using namespace twinray;

std::string vec3(const scene::Vec3& v) {
    char text[96];
    std::snprintf(text, sizeof text, "[%.6g, %.6g, %.6g]", v[0], v[1], v[2]);
    return text;
}

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

void write_sphere_field(int count, const std::string& file) {
    const scene::Scene field = scene::sphere_field(count);
    std::ofstream out(file, std::ios::binary);
    out << "{\n  \"format\": \"twinray-scene/1\",\n  \"image\": {\"width\": " << field.width
        << ", \"height\": " << field.height << "},\n  \"camera\": {\"eye\": " << vec3(field.camera.eye)
        << ", \"look_at\": " << vec3(field.camera.look_at) << ", \"up\": " << vec3(field.camera.up)
        << ", \"fov_deg\": " << number(field.camera.fov_deg) << "},\n  \"background\": " << vec3(field.background)
        << ",\n  \"max_depth\": " << field.max_depth << ",\n  \"materials\": {";
    for (std::size_t i = 1; i < field.materials.size(); ++i) {
        out << (i > 1 ? ",\n" : "\n") << "    \"" << field.material_names[i]
            << "\": {\"color\": " << vec3(field.materials[i].color)
            << ", \"phong\": " << number(field.materials[i].phong) << "}";
    }
    out << "\n  },\n  \"lights\": [{\"position\": " << vec3(field.lights[0].position) << "}],\n  \"objects\": [";
    for (std::size_t i = 0; i < field.objects.size(); ++i) {
        const auto& sphere = std::get<scene::Sphere>(field.objects[i].shape);
        out << (i > 0 ? ",\n" : "\n") << "    {\"type\": \"sphere\", \"center\": " << vec3(sphere.center)
            << ", \"radius\": " << number(sphere.radius) << ", \"material\": \""
            << field.material_names[static_cast<std::size_t>(field.objects[i].material)] << "\"}";
    }
    out << "\n  ]\n}\n";
    if (!out.flush()) {
        throw std::runtime_error("cannot write " + file);
    }
}

// A field of /proc/self/status in bytes (VmRSS, VmHWM).
long status_bytes(const std::string& field) {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.starts_with(field + ":")) {
            return std::stol(line.substr(field.size() + 1)) * 1024;
        }
    }
    throw std::runtime_error("no " + field + " in /proc/self/status");
}

// Makes VmHWM start again from the current resident size.
void reset_peak() {
    std::ofstream("/proc/self/clear_refs") << "5";
}

struct LoadRun {
    double seconds;
    long scene_bytes;  // resident after loading, the scene kept, freed memory given back
    long peak_above;   // the peak while loading, above that
    long primitives;
};

// In a fresh process each time, so that no run inherits another's heap.
LoadRun load_once(const std::string& file) {
    const long before = status_bytes("VmRSS");
    reset_peak();
    const auto start = std::chrono::steady_clock::now();
    const scene::Scene scene = scene::load_scene(file);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const long peak = status_bytes("VmHWM");
    malloc_trim(0);
    const long loaded = status_bytes("VmRSS");
    return {seconds, loaded - before, peak - loaded, static_cast<long>(scene.leaf_paths.size())};
}

LoadRun load_in_child(const std::string& file) {
    int channel[2];
    if (pipe(channel) != 0) {
        throw std::runtime_error("pipe failed");
    }
    const pid_t child = fork();
    if (child == 0) {
        close(channel[0]);
        int status = 1;
        try {
            const LoadRun run = load_once(file);
            status = write(channel[1], &run, sizeof run) == static_cast<ssize_t>(sizeof run) ? 0 : 1;
        } catch (const std::exception& error) {
            std::fprintf(stderr, "scene_load_benchmark: %s\n", error.what());
        }
        _exit(status);
    }
    close(channel[1]);
    LoadRun run{};
    const bool received = read(channel[0], &run, sizeof run) == static_cast<ssize_t>(sizeof run);
    close(channel[0]);
    int status = 0;
    waitpid(child, &status, 0);
    if (!received || status != 0) {
        throw std::runtime_error("loading " + file + " failed");
    }
    return run;
}

template <class T>
T median(std::vector<T> values) {
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

void load(const std::string& file, int runs) {
    std::vector<double> seconds;
    std::vector<long> scene_bytes, above;
    long primitives = 0;
    for (int i = 0; i < runs; ++i) {
        const LoadRun run = load_in_child(file);
        seconds.push_back(run.seconds);
        scene_bytes.push_back(run.scene_bytes);
        above.push_back(run.peak_above);
        primitives = run.primitives;
    }
    const double time = median(seconds);
    const auto per_primitive = [primitives](long bytes) {
        return static_cast<double>(bytes) / static_cast<double>(primitives);
    };
    std::printf(
        "%ld primitives: median %.3f s (min %.3f, max %.3f) of %d, %.0f primitives/s; scene %.0f bytes per "
        "primitive, peak while loading %.0f bytes per primitive above it\n",
        primitives, time, *std::min_element(seconds.begin(), seconds.end()),
        *std::max_element(seconds.begin(), seconds.end()), runs, static_cast<double>(primitives) / time,
        per_primitive(median(scene_bytes)), per_primitive(median(above)));
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const std::vector<std::string> arguments(argv + 1, argv + argc);
        if (arguments.size() == 3 && arguments[0] == "write") {
            write_sphere_field(std::stoi(arguments[1]), arguments[2]);
            return 0;
        }
        if ((arguments.size() == 2 || arguments.size() == 3) && arguments[0] == "load") {
            load(arguments[1], arguments.size() == 3 ? std::stoi(arguments[2]) : 5);
            return 0;
        }
        std::fprintf(stderr, "usage: scene_load_benchmark write COUNT FILE | load FILE [RUNS]\n");
        return 1;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "scene_load_benchmark: %s\n", error.what());
        return 1;
    }
}
