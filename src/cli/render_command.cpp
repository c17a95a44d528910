#include "cli/render_command.h"

#include "cli/exit_codes.h"
#include "cli/tracers.h"
#include "image/image_file.h"
#include "io/atomic_file.h"
#include "plugin/plugin.h"
#include "scene/depth_control.h"
#include "scene/loader.h"
#include "scene/mesh_file.h"
#include "scene/refusal.h"

#include <unistd.h>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace twinray::cli {
namespace {

namespace fs = std::filesystem;

// Set by SIGINT (Ctrl-C); the render loop reads it between items (RenderOptions::cancel). A lock-free
// atomic is safe to store to from a signal handler.
std::atomic<bool> interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free);

void on_interrupt(int) {
    interrupted.store(true, std::memory_order_relaxed);
}

// Catches SIGINT for as long as it lives, then restores what was there before. It lives for the whole
// render command, writing included: a Ctrl-C that arrives once the image is being written lets the
// write finish (a second or so) rather than leave a half-written temporary file beside the target.
class InterruptCatcher {
public:
    InterruptCatcher() {
        struct sigaction action {};
        action.sa_handler = on_interrupt;
        sigemptyset(&action.sa_mask);
        installed_ = ::sigaction(SIGINT, &action, &previous_) == 0;
    }
    ~InterruptCatcher() {
        if (installed_) {
            ::sigaction(SIGINT, &previous_, nullptr);
        }
    }
    InterruptCatcher(const InterruptCatcher&) = delete;
    InterruptCatcher& operator=(const InterruptCatcher&) = delete;

private:
    struct sigaction previous_ {};
    bool installed_ = false;
};

struct RenderArguments {
    std::string scene_path;
    std::string output_path;
    int width = 0;
    int height = 0;
    std::string tracer = default_tracer;
    int threads = 0;
    std::size_t max_primitives = scene::max_scene_primitives;
    sse::Precision precision;
    Accel accel = Accel::automatic;
};

// Refuse an output we could not write before spending time on the render.
std::string output_problem(const fs::path& output) {
    if (!is_supported_image_path(output)) {
        return "unsupported image format \"" + output.extension().string() +
               "\"; allowed: .png (8-bit) or .exr (float)";
    }
    return io::output_folder_problem(output);
}

// Progress only for a person watching: on a terminal, once a render has run for about a second.
std::function<void(double)> terminal_progress(std::chrono::steady_clock::time_point start) {
    if (!::isatty(STDERR_FILENO)) {
        return nullptr;
    }
    return [start](double fraction) {
        if (std::chrono::steady_clock::now() - start > std::chrono::seconds(1)) {
            std::fprintf(stderr, "\rrendering %3d%%", static_cast<int>(fraction * 100.0));
            std::fflush(stderr);
        }
    };
}

// What the depth control left out (scene/depth_control.h) and, if the ray budget ran out anywhere, where to
// look first.
void print_depth_control(const scene::Scene& scene, const std::string& scene_path, const RenderResult& result) {
    const TraceTally& tally = result.tally;
    if (scene.min_weight) {
        std::printf("rays left out: %llu (min_weight %g)\n", static_cast<unsigned long long>(tally.dropped_rays),
                    *scene.min_weight);
    } else {
        std::printf("rays left out: %llu (proven cutoff, each pixel within 0.49/255)\n",
                    static_cast<unsigned long long>(tally.dropped_rays));
    }
    if (tally.pixels_over_budget == 0) {
        return;
    }
    int width = result.image.width();
    long long first = tally.first_pixel_over_budget;
    std::printf(
        "ray budget:  %llu pixel%s ran out of their %d rays (their error is not bounded by the cutoff);\n"
        "             the first: twinray probe %s --pixel %lld,%lld --width %d --height %d\n",
        static_cast<unsigned long long>(tally.pixels_over_budget), tally.pixels_over_budget == 1 ? "" : "s",
        scene::DepthControl::ray_budget, scene_path.c_str(), first % width, first / width, width,
        result.image.height());
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// One mesh's triangles, those with no area that no tracer ever hits, and its topology (glass needs a closed mesh:
// a ray must leave what it entered); `placed` says how many instances place a mesh shape.
// The file is left out where the name begins with it (a glTF file's mesh at the top level: "truck.glb mesh 2").
void print_mesh(const char* label, const std::string& name, bool name_begins_with_file, const scene::MeshData& data,
                const std::string& placed) {
    const scene::MeshTopology topology = scene::topology_of(data);
    const bool file_named = data.file.empty() || name_begins_with_file;
    std::printf("%s%s%s: %zu triangles, %zu vertices, %zu degenerate (never hit)%s; %s", label, name.c_str(),
                file_named ? "" : (" (" + data.file + ")").c_str(), data.triangles.size(), data.vertices.size(),
                data.degenerate.size(), data.smooth ? ", smooth" : "", topology.closed() ? "closed" : "open");
    if (!topology.closed()) {
        std::printf(" (%zu boundary, %zu non-manifold, %zu inconsistently wound edges)", topology.boundary_edges,
                    topology.non_manifold_edges, topology.inconsistently_wound_edges);
    }
    std::printf("%s\n", placed.c_str());
}

// Each mesh, each mesh shape once with its count of instances, as print_mesh prints them: counted before the render,
// which may give up the scene's objects and meshes (render_giving_up_geometry).
struct MeshLine {
    const char* label;
    std::string name;
    bool name_begins_with_file;
    std::shared_ptr<const scene::MeshData> data;
    std::string placed;
};

std::vector<MeshLine> mesh_lines(const scene::Scene& scene) {
    std::vector<MeshLine> lines;
    std::vector<std::size_t> instances(scene.mesh_shapes.size(), 0);
    for (const scene::Mesh& mesh : scene.meshes) {
        if (mesh.placement) {
            ++instances[static_cast<std::size_t>(mesh.placement->shape)];
        } else {
            lines.push_back(
                {"mesh:        ", scene.leaf_paths[static_cast<std::size_t>(mesh.leaf)], false, mesh.data, ""});
        }
    }
    for (std::size_t i = 0; i < scene.mesh_shapes.size(); ++i) {
        const std::size_t count = instances[i];
        const scene::MeshShape& shape = scene.mesh_shapes[i];
        lines.push_back({"shape:       ", shape.name, shape.name_begins_with_file, shape.data,
                         "; placed by " + std::to_string(count) + (count == 1 ? " instance" : " instances")});
    }
    return lines;
}

// The meshes' lines; then what the loader read and does not use.
void print_meshes(const std::vector<MeshLine>& lines, const scene::Scene& scene) {
    for (const MeshLine& line : lines) {
        print_mesh(line.label, line.name, line.name_begins_with_file, *line.data, line.placed);
    }
    for (const std::string& warning : scene.warnings) {
        std::fprintf(stderr, "twinray render: warning: %s\n", warning.c_str());
    }
}

int run_render(const RenderArguments& arguments) {
    InterruptCatcher catch_ctrl_c;
    fs::path output = arguments.output_path.empty() ? fs::path(fs::path(arguments.scene_path).stem().string() + ".png")
                                                    : fs::path(arguments.output_path);
    if (std::string problem = output_problem(output); !problem.empty()) {
        std::cerr << "twinray render: cannot write " << output.string() << ": " << problem << "\n";
        return is_supported_image_path(output) ? exit_output_error : exit_usage;
    }
    if (std::string reason = tracer_unavailable_reason(arguments.tracer); !reason.empty()) {
        std::cerr << "twinray render: " << reason << "\n";
        return exit_cpu_unsupported;
    }
    if (std::string problem = precision_problem(arguments.tracer, arguments.precision); !problem.empty()) {
        std::cerr << "twinray render: " << problem << "\n";
        return exit_usage;
    }
    scene::Scene scene;
    const auto load_start = std::chrono::steady_clock::now();
    try {
        scene = scene::load_scene(arguments.scene_path, arguments.max_primitives);
    } catch (const scene::SceneError& error) {
        std::cerr << "twinray render: invalid scene: " << error.what() << "\n";
        return exit_invalid_scene;
    }
    const double load_seconds = seconds_since(load_start);
    scene::ImageSize size{};
    try {
        size = scene::resolve_image_size(scene, arguments.width, arguments.height);
    } catch (const std::invalid_argument& error) {
        std::cerr << "twinray render: " << error.what() << "\n";
        return exit_usage;
    }
    if (std::int64_t pixels = std::int64_t{size.width} * size.height; pixels > max_image_pixels) {
        std::cerr << "twinray render: " << size.width << " x " << size.height << " is " << pixels
                  << " pixels, more than the limit of " << max_image_pixels
                  << " (8192 x 8192, 768 MiB of float pixels); ask for a smaller --width or --height\n";
        return exit_usage;
    }
    RenderOptions options;
    options.width = arguments.width;
    options.height = arguments.height;
    options.threads = resolve_thread_count(arguments.threads);
    options.cancel = &interrupted;
    options.accel = arguments.accel;
    auto start = std::chrono::steady_clock::now();
    options.progress = terminal_progress(start);
    auto clear_progress = [&] {
        if (options.progress) {
            std::fprintf(stderr, "\r              \r");
        }
    };
    const std::vector<MeshLine> meshes = mesh_lines(scene);
    std::optional<RenderResult> rendered;
    std::string accel_choice;
    try {
        rendered.emplace(
            render_giving_up_geometry(arguments.tracer, scene, options, arguments.precision, &accel_choice));
        // A Ctrl-C after the last item but before the write still means "stop": nothing is written.
        if (interrupted.load(std::memory_order_relaxed)) {
            throw RenderCancelled();
        }
    } catch (const RenderCancelled&) {
        clear_progress();
        std::cerr << "twinray render: interrupted; " << output.string() << " was not written\n";
        return exit_interrupted;
    } catch (const plugin::PluginError& error) {
        clear_progress();
        const int status = plugin_exit_status(error);
        std::cerr << "twinray render: " << error.what()
                  << (status == exit_plugin_fault ? "; " + output.string() + " was not written" : "") << "\n";
        return status;
    }
    const double render_seconds = seconds_since(start);
    clear_progress();
    const RenderResult& result = *rendered;
    const auto write_start = std::chrono::steady_clock::now();
    try {
        write_image(result.image, output);
    } catch (const ImageFileError& error) {
        std::cerr << "twinray render: " << error.what() << "\n";
        return exit_output_error;
    }
    const double write_seconds = seconds_since(write_start);
    std::printf("scene:       %s\n", arguments.scene_path.c_str());
    std::printf("tracer:      %s (%d thread%s)\n", arguments.tracer.c_str(), options.threads,
                options.threads == 1 ? "" : "s");
    if (arguments.tracer == "sse") {
        std::printf("precision:   %s\n", sse::precision_name(arguments.precision).c_str());
    }
    std::printf("accel:       %s%s\n", accel_name(arguments.accel).c_str(),
                accel_choice.empty() ? "" : (" (" + accel_choice + ")").c_str());
    std::printf("resolution:  %d x %d\n", result.image.width(), result.image.height());
    std::printf("rays traced: %llu\n", static_cast<unsigned long long>(result.tally.rays));
    print_depth_control(scene, arguments.scene_path, result);
    print_meshes(meshes, scene);
    // As POV-Ray's statistics: loading, building (compiling the scene and its BVH) and writing apart from
    // tracing, since a large mesh takes longer to load and build than to trace; the speed is the trace's.
    std::printf("load time:   %.3f s\n", load_seconds);
    std::printf("build time:  %.3f s\n", render_seconds - result.tracing_seconds);
    std::printf("trace time:  %.3f s\n", result.tracing_seconds);
    std::printf("write time:  %.3f s\n", write_seconds);
    std::printf("wall time:   %.3f s\n", seconds_since(load_start));
    std::printf("speed:       %.2f Mrays/s\n", static_cast<double>(result.tally.rays) / result.tracing_seconds / 1e6);
    std::printf("wrote:       %s\n", output.string().c_str());
    return exit_success;
}

}  // namespace

void add_render_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<RenderArguments>();
    CLI::App* command = app.add_subcommand("render", "Render a scene to an image (PNG or EXR)");
    command->add_option("scene", arguments->scene_path, "Scene file (twinray-scene/1 JSON)")->required();
    command->add_option("-o,--output", arguments->output_path,
                        "Output image: .png (8-bit, clamped, no gamma) or .exr (float); default: SCENE's name .png");
    command->add_option("--width", arguments->width, "Image width; alone, the height follows the scene's aspect ratio")
        ->check(CLI::Range(1, 16384));
    command
        ->add_option("--height", arguments->height, "Image height; alone, the width follows the scene's aspect ratio")
        ->check(CLI::Range(1, 16384));
    add_tracer_option(*command, arguments->tracer);
    command
        ->add_option("--threads", arguments->threads,
                     "Worker threads (default: all cores); the image is identical for any count")
        ->check(CLI::Range(1, 1024));
    command
        ->add_option("--max-primitives", arguments->max_primitives,
                     "Refuse (status 2) a scene of more primitives: a memory budget, about " +
                         std::to_string(scene::bytes_per_primitive) + " bytes per primitive. At most " +
                         std::to_string(scene::max_scene_primitives) + ", the default")
        ->check(CLI::Range(std::size_t{1}, scene::max_scene_primitives));
    add_precision_options(*command, arguments->precision);
    add_accel_option(*command, arguments->accel);
    command->callback([arguments, &run] { run = [arguments] { return run_render(*arguments); }; });
}

}  // namespace twinray::cli
