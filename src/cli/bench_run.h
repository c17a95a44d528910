// What the parts of `twinray bench` share: its arguments, the configurations it times, its tables and
// the timing helpers (bench_command.cpp: speed against accuracy; bench_peers.cpp: POV-Ray, Embree and
// the generated scenes; bench_process.cpp: the whole process).
#pragma once

#include "cli/bench_table.h"
#include "image/image.h"
#include "scene/scene.h"
#include "sse/tracer.h"

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace twinray::cli::bench {

struct BenchArguments {
    std::vector<std::string> scenes;
    int runs = 5;
    int threads = 0;
    int width = 640;
    bool scaling = false;
    bool peers = true;
    std::string csv_path;
    std::string markdown_path;
    Accel accel = Accel::automatic;  // of every configuration's tracer
};

struct Configuration {
    std::string label;
    std::string tracer;
    sse::Precision precision;
    int threads = 1;
};

struct Report {
    BenchTable trade, summary, process, povray, first_hit, scaling, depth;
};

// Every knob that can buy speed (--precision fast); dpps is the thesis's choice, timed on its own.
inline sse::Precision all_fast_knobs() {
    return {.fast_rcp = true, .fast_rsqrt = true, .textbook_quadratic = true, .flush_denormals = true};
}

double median(std::vector<double> values);

inline double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Speeds of one configuration over the runs (Mrays/s), its per-run ratios to the first
// configuration's, and seconds per frame.
struct Timings {
    std::vector<double> mrays, speedups, seconds;
};

// Every configuration renders once per run, in turn, so a slow spell of the shared machine weighs on
// both sides of a ratio instead of on one column; each ratio is the median of per-run ratios.
std::vector<Timings> time_renders(const std::vector<Configuration>& configurations, const scene::Scene& scene,
                                  int width, int runs, std::vector<Image>* last_images, Accel accel = Accel::automatic);

// POV-Ray 3.7 on the same scene exported at the same size, against the SSE tracer's seconds per frame
// on one thread and on all.
void bench_povray(const std::string& name, const scene::Scene& scene, const BenchArguments& arguments,
                  const std::filesystem::path& povray, int all_threads, const std::vector<double>& sse_seconds,
                  Report& report);
// First hits of primary rays only: the SSE tracer (exact and --precision fast) against Embree 3.
void bench_first_hits(const std::string& name, const scene::Scene& scene, int width, int runs, Accel accel,
                      Report& report);
// The generated sphere field: time per ray as the scene grows, at a resolution that shrinks with it.
void bench_scaling(const BenchArguments& arguments, int all_threads, Report& report);

// With mirrors or glass: rays, seconds and image change of the proven cutoff against none (min_weight 0), both
// tracers on one thread.
void bench_depth_control(const std::string& name, const scene::Scene& scene, const BenchArguments& arguments,
                         Report& report);

// The whole process of `twinray render` on one scene file, part by part: start-up, loading, rendering
// (sse exact, one thread), writing .png and .exr; and the whole command, sse and reference<double>.
void bench_process(const std::string& name, const std::filesystem::path& scene_file, const scene::Scene& scene,
                   const BenchArguments& arguments, Report& report);

}  // namespace twinray::cli::bench
