// What the parts of `twinray bench` share: its arguments, the configurations it times, its tables and
// the timing helpers (bench_command.cpp: speed against accuracy; bench_peers.cpp: POV-Ray and Embree;
// bench_scaling.cpp: scenes of growing size; bench_process.cpp: the whole process).
#pragma once

#include "cli/bench_table.h"
#include "image/image.h"
#include "math/median.h"
#include "scene/scene.h"
#include "sse/tracer.h"

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace twinray::cli::bench {

struct BenchArguments {
    std::vector<std::string> scenes;
    int runs = 5;
    int threads = 0;
    int width = 640;
    bool scaling = false;
    bool scaling_only = false;    // the scaling tables alone, no scene of `scenes`
    int scaling_max = 1'000'000;  // the largest size the scaling asks a family for
    bool peers = true;
    bool floor = true;      // --scaling's memory floor of this machine (bench_floor.cpp)
    bool crossover = true;  // --scaling's crossover of --accel auto (bench_crossover.cpp)
    std::string csv_path;
    std::string markdown_path;
    Accel accel = Accel::automatic;    // of every configuration's tracer
    std::vector<std::string> plugins;  // --tracer plugin:PATH, each a row of the trade table beside twinray's own
};

struct Configuration {
    std::string label;
    std::string tracer;
    sse::Precision precision;
    int threads = 1;
};

struct Report {
    BenchTable trade, summary, process, povray, first_hit, depth;
    // --scaling: time per ray, first hits against Embree and renders against POV-Ray, the BVH's build, threads.
    BenchTable scaling, scaling_peers, scaling_build, scaling_threads;
    BenchTable scaling_floor;  // the caches' and DRAM's time per line, what a time per ray is set against
    // Brute force against the BVH on grids of each kind, and where the BVH starts to pay beside what auto builds.
    BenchTable scaling_crossover, scaling_crossover_summary;
};

// Every knob that can buy speed (--precision fast); dpps is the thesis's choice, timed on its own.
inline sse::Precision all_fast_knobs() {
    return {.fast_rcp = true, .fast_rsqrt = true, .textbook_quadratic = true, .flush_denormals = true};
}

using math::median;

// Whether two images are the same bit for bit.
inline bool same_bits(const Image& a, const Image& b) {
    return a.width() == b.width() && a.height() == b.height() &&
           std::memcmp(a.pixels().data(), b.pixels().data(), a.pixels().size() * sizeof(Rgb)) == 0;
}

inline double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Speeds of one configuration over the runs (Mrays/s), its per-run ratios to the first
// configuration's, and seconds per frame (the whole render call); the pixel loop's wall and CPU seconds
// alone (RenderResult), and the rays of a frame.
struct Timings {
    std::vector<double> mrays, speedups, seconds;
    std::vector<double> tracing_seconds, tracing_cpu_seconds;
    std::uint64_t rays = 0;
};

// Every configuration renders once per run, in turn, so a slow spell of the shared machine weighs on
// both sides of a ratio instead of on one column; each ratio is the median of per-run ratios.
std::vector<Timings> time_renders(const std::vector<Configuration>& configurations, const scene::Scene& scene,
                                  int width, int runs, std::vector<Image>* last_images, Accel accel = Accel::automatic);

// POV-Ray 3.7 on `scene` exported at `width`, median of `runs`, the runs taking the frames in turn: a frame on
// each of `threads` (the wall and CPU time, user + system, of POV-Ray's process, and the CPU seconds its own
// statistics give for its parse and bounding together and for its trace) and, with `start_up`, the same scene
// at 1 x 1 pixel (its start-up, parse and bounding, the fixed cost inside every frame).
struct PovrayTimes {
    std::vector<double> frame_wall, frame_cpu;
    std::vector<double> set_up_cpu, trace_cpu;
    double start_up_wall = 0, start_up_cpu = 0;
};
PovrayTimes time_povray(const std::string& name, const scene::Scene& scene, int width, int runs,
                        const std::filesystem::path& povray, const std::vector<int>& threads, bool start_up = true);

// POV-Ray 3.7 on the same scene exported at the same size, against the SSE tracer's seconds per frame
// on one thread and on all.
void bench_povray(const std::string& name, const scene::Scene& scene, const BenchArguments& arguments,
                  const std::filesystem::path& povray, int all_threads, const std::vector<double>& sse_seconds,
                  Report& report);
// First hits of primary rays only: the SSE tracer (exact and --precision fast) against Embree 3.
void bench_first_hits(const std::string& name, const scene::Scene& scene, int width, int runs, Accel accel,
                      Report& report);
// Scenes of 10 to arguments.scaling_max primitives (a sphere field, the sphereflake, a lattice of cylinders, a
// sphere mesh and the SPD tetra, of as many triangles):
// both tracers with and without their BVH, first hits against Embree, whole renders against POV-Ray (when
// `povray` is given), the BVH's build, and one thread against all (bench_scaling.cpp).
void bench_scaling(const BenchArguments& arguments, int all_threads, const std::optional<std::filesystem::path>& povray,
                   Report& report);
// Grids of 1 to 128 objects of each kind of bounded primitive, matte and glass: the SSE tracer by brute force and
// through its BVH at `width`, and the weight Accel::automatic gives each grid (bench_crossover.cpp).
void bench_crossover(int width, int runs, Report& report);
// The time of a load hitting each cache level and missing to DRAM, one at a time and overlapped (bench_floor.cpp).
void bench_memory_floor(int runs, Report& report);

// With mirrors or glass: rays, seconds and image change of the proven cutoff against none (min_weight 0), both
// tracers on one thread.
void bench_depth_control(const std::string& name, const scene::Scene& scene, const BenchArguments& arguments,
                         Report& report);

// The whole process of `twinray render` on one scene file, part by part: start-up, loading, rendering
// (sse exact, one thread), writing .png and .exr; and the whole command, sse and reference<double>.
void bench_process(const std::string& name, const std::filesystem::path& scene_file, const scene::Scene& scene,
                   const BenchArguments& arguments, Report& report);

}  // namespace twinray::cli::bench
