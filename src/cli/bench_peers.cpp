// `twinray bench` against its peers: POV-Ray 3.7 per frame, Embree 3 per first hit.
#include "cli/bench_run.h"
#include "cli/tracers.h"
#include "pov/exporter.h"
#include "pov/povray_runner.h"
#include "scene/placement.h"
#include "sse/tracer.h"
#if TWINRAY_WITH_EMBREE
#include "peers/embree_peer.h"
#endif

#include <sys/resource.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace twinray::cli::bench {

namespace fs = std::filesystem;

namespace {

// CPU time (user + system) of the child processes waited for so far: POV-Ray's, once render_with_povray
// returns.
double children_cpu_seconds() {
    rusage usage{};
    getrusage(RUSAGE_CHILDREN, &usage);
    auto seconds = [](const timeval& t) {
        return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
    };
    return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

}  // namespace

PovrayTimes time_povray(const std::string& name, const scene::Scene& scene, int width, int runs, const fs::path& povray,
                        const std::vector<int>& threads, bool start_up) {
    scene::ImageSize size = scene::resolve_image_size(scene, width, 0);
    fs::path folder = fs::temp_directory_path() / ("twinray-bench-povray-" + std::to_string(::getpid()));
    fs::create_directories(folder);
    std::string pov_text = pov::export_pov(scene, size.width, size.height);
    std::string tiny_text = start_up ? pov::export_pov(scene, 1, 1) : std::string();
    const std::size_t frames = threads.size();
    // Per frame, and last the 1 x 1 one.
    std::vector<std::vector<double>> wall(frames + 1), cpu(frames + 1), set_up(frames), trace(frames);
    for (int run = 0; run < runs; ++run) {
        for (std::size_t k = 0; k < frames + (start_up ? 1 : 0); ++k) {
            auto start = std::chrono::steady_clock::now();
            double cpu_start = children_cpu_seconds();
            if (k < frames) {
                pov::PovrayStatistics statistics;
                pov::render_with_povray(povray, folder, name, pov_text, size.width, size.height, threads[k],
                                        &statistics);
                set_up[k].push_back(statistics.parse_cpu_seconds + statistics.bounding_cpu_seconds);
                trace[k].push_back(statistics.trace_cpu_seconds);
            } else {
                // Its own file name: OpenImageIO caches images by name, and the size differs.
                pov::render_with_povray(povray, folder, name + "-1x1", tiny_text, 1, 1, 1);
            }
            wall[k].push_back(seconds_since(start));
            cpu[k].push_back(children_cpu_seconds() - cpu_start);
        }
    }
    fs::remove_all(folder);
    PovrayTimes times;
    for (std::size_t k = 0; k < frames; ++k) {
        times.frame_wall.push_back(median(wall[k]));
        times.frame_cpu.push_back(median(cpu[k]));
        times.set_up_cpu.push_back(median(set_up[k]));
        times.trace_cpu.push_back(median(trace[k]));
    }
    if (start_up) {
        times.start_up_wall = median(wall[frames]);
        times.start_up_cpu = median(cpu[frames]);
    }
    return times;
}

// Wall time per frame (process start-up included, about 0.7 s of it).
void bench_povray(const std::string& name, const scene::Scene& scene, const BenchArguments& arguments,
                  const fs::path& povray, int all_threads, const std::vector<double>& sse_seconds, Report& report) {
    PovrayTimes times = time_povray(name, scene, arguments.width, arguments.runs, povray, {1, all_threads});
    double one = times.frame_wall[0], all = times.frame_wall[1], start_up = times.start_up_wall;
    report.povray.add_row({name, cell("%.3f", one), cell("%.3f", all), cell("%.3f", start_up),
                           cell("%.4f", sse_seconds[0]), cell("%.4f", sse_seconds[1]),
                           cell("%.1f", one / sse_seconds[0]), cell("%.1f", all / sse_seconds[1]),
                           cell("%.1f", (one - start_up) / sse_seconds[0])});
}

namespace {

void bench_first_hits_of(const std::string& name, const scene::Scene& scene, int width, int runs, Accel accel,
                         Report& report) {
    RenderOptions options;
    options.width = width;
    options.threads = 1;
    options.accel = accel;
    std::vector<double> exact, fast;
    sse::FirstHits hits;
    for (int run = 0; run < runs; ++run) {
        hits = sse::cast_primary_rays(scene, options);
        exact.push_back(static_cast<double>(hits.rays) / hits.tracing_cpu_seconds / 1e6);
        sse::FirstHits fast_hits = sse::cast_primary_rays(scene, options, all_fast_knobs());
        fast.push_back(static_cast<double>(fast_hits.rays) / fast_hits.tracing_cpu_seconds / 1e6);
    }
    std::vector<std::string> row = {name, std::to_string(hits.rays), cell("%.2f", median(exact)),
                                    cell("%.2f", median(fast))};
    // Embree's five columns, then its three in robust mode (timed on meshes only: shared edges are what it
    // is for).
    auto left_out = [&row](const std::string& why) { row.insert(row.end(), {why, "", "", "", "", "", "", ""}); };
#if TWINRAY_WITH_EMBREE
    if (std::string reason = peers::embree_unsupported_reason(scene); !reason.empty()) {
        left_out("n/a: " + reason);
    } else
        try {
            peers::EmbreePeer embree(scene, width);
            std::optional<peers::EmbreePeer> robust;
            if (scene.has_meshes()) {
                robust.emplace(scene, width, peers::EmbreeIsa::widest, peers::EmbreeMode::robust);
            }
            auto mrays = [](const peers::FirstHitRun& run) {
                return static_cast<double>(run.rays) / run.seconds / 1e6;
            };
            std::vector<double> single, packets, robust_single;
            std::uint64_t embree_hits = 0, robust_hits = 0;
            for (int run = 0; run < runs; ++run) {
                peers::FirstHitRun one = embree.cast_single();
                single.push_back(mrays(one));
                packets.push_back(mrays(embree.cast_packets()));
                embree_hits = one.hits;
                if (robust) {
                    peers::FirstHitRun robust_one = robust->cast_single();
                    robust_single.push_back(mrays(robust_one));
                    robust_hits = robust_one.hits;
                }
            }
            auto hits_difference = [&hits](std::uint64_t embree_count) {
                return std::to_string(static_cast<long long>(hits.hits) - static_cast<long long>(embree_count));
            };
            row.insert(row.end(), {cell("%.2f", median(single)), cell("%.2f", median(packets)),
                                   cell("%.2f", median(exact) / median(single)),
                                   cell("%.2f", median(exact) / median(packets)), hits_difference(embree_hits)});
            if (robust) {
                row.insert(row.end(),
                           {cell("%.2f", median(robust_single)), cell("%.2f", median(exact) / median(robust_single)),
                            hits_difference(robust_hits)});
            } else {
                row.insert(row.end(), {"no meshes", "", ""});
            }
        } catch (const std::runtime_error& error) {
            left_out(std::string("failed: ") + error.what());
        }
#else
    left_out("not built");
#endif
    report.first_hit.add_row(row);
}

}  // namespace

// A scene of instances is timed beside itself flattened (each instance's triangles written out in world
// coordinates), where that fits the primitive limit: what instancing costs per ray.
void bench_first_hits(const std::string& name, const scene::Scene& scene, int width, int runs, Accel accel,
                      Report& report) {
    bench_first_hits_of(name, scene, width, runs, accel, report);
    if (!scene.has_instances()) {
        return;
    }
    scene::Scene flat = scene::flattened(scene);
    if (flat.primitive_count() <= scene::max_scene_primitives) {
        bench_first_hits_of(name + " flattened", flat, width, runs, accel, report);
    }
}

}  // namespace twinray::cli::bench
