// The whole process a user starts, part by part (docs/performance.md, "Whole process"): what `twinray
// render` spends around the render loop, and the whole command timed as a child process.
#include "cli/bench_run.h"
#include "cli/tracers.h"
#include "image/image_file.h"
#include "scene/loader.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stdexcept>
#include <string>
#include <vector>

extern char** environ;

namespace twinray::cli::bench {
namespace {

namespace fs = std::filesystem;

// Seconds from spawning this very binary with `arguments` to its exit, its output discarded.
double run_twinray(const std::vector<std::string>& arguments) {
    const std::string self = fs::read_symlink("/proc/self/exe").string();
    std::vector<char*> argv{const_cast<char*>(self.c_str())};
    for (const std::string& argument : arguments) {
        argv.push_back(const_cast<char*>(argument.c_str()));
    }
    argv.push_back(nullptr);
    posix_spawn_file_actions_t quiet;
    posix_spawn_file_actions_init(&quiet);
    posix_spawn_file_actions_addopen(&quiet, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&quiet, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    const auto start = std::chrono::steady_clock::now();
    pid_t child = 0;
    const int failed = posix_spawn(&child, self.c_str(), &quiet, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&quiet);
    int status = 0;
    if (failed != 0 || waitpid(child, &status, 0) != child || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        throw std::runtime_error("twinray " + arguments.front() + " failed as a child process");
    }
    return seconds_since(start);
}

template <class Step>
double median_ms(int runs, Step step) {
    std::vector<double> seconds;
    for (int run = 0; run < runs; ++run) {
        const auto start = std::chrono::steady_clock::now();
        step();
        seconds.push_back(seconds_since(start));
    }
    return 1e3 * median(seconds);
}

}  // namespace

void bench_process(const std::string& name, const fs::path& scene_file, const scene::Scene& scene,
                   const BenchArguments& arguments, Report& report) {
    const fs::path folder = fs::temp_directory_path() / ("twinray-bench-process-" + std::to_string(::getpid()));
    fs::create_directories(folder);
    const int runs = arguments.runs;
    const std::string width = std::to_string(arguments.width);
    auto row = [&](const std::string& part, double ms) { report.process.add_row({name, part, cell("%.1f", ms)}); };
    if (report.process.rows.empty()) {
        report.process.add_row(
            {"(any)", "start-up: twinray --help", cell("%.1f", median_ms(runs, [] { run_twinray({"--help"}); }))});
    }
    row("load the scene file", median_ms(runs, [&] { scene::load_scene(scene_file); }));
    RenderOptions options;
    options.width = arguments.width;
    options.threads = 1;
    Image image(1, 1);
    row("render, sse exact, 1 thread", median_ms(runs, [&] { image = render_with("sse", scene, options, {}).image; }));
    row("write .png", median_ms(runs, [&] { write_image(image, folder / "image.png"); }));
    row("write .exr", median_ms(runs, [&] { write_image(image, folder / "image.exr"); }));
    const std::string output = (folder / "render.png").string();
    for (const char* tracer : {"sse", "reference"}) {
        row(std::string("whole twinray render --tracer ") + tracer + " --threads 1 -o .png", median_ms(runs, [&] {
                run_twinray({"render", scene_file.string(), "--width", width, "--threads", "1", "--tracer", tracer,
                             "-o", output});
            }));
    }
    fs::remove_all(folder);
}

}  // namespace twinray::cli::bench
