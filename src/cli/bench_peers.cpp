// `twinray bench` against its peers: POV-Ray 3.7 per frame, Embree 3 per first hit, and generated
// sphere fields of growing size.
#include "cli/bench_run.h"
#include "cli/tracers.h"
#include "pov/exporter.h"
#include "pov/povray_runner.h"
#include "scene/sphere_field.h"
#include "sse/tracer.h"
#if TWINRAY_WITH_EMBREE
#include "peers/embree_peer.h"
#endif

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace twinray::cli::bench {

namespace fs = std::filesystem;

// Wall time per frame (process start-up included, about 0.7 s of it).
void bench_povray(const std::string& name, const scene::Scene& scene, const BenchArguments& arguments,
                  const fs::path& povray, int all_threads, const std::vector<double>& sse_seconds, Report& report) {
    scene::ImageSize size = scene::resolve_image_size(scene, arguments.width, 0);
    fs::path folder = fs::temp_directory_path() / ("twinray-bench-povray-" + std::to_string(::getpid()));
    fs::create_directories(folder);
    std::string pov_text = pov::export_pov(scene, size.width, size.height);
    // The same scene at 1 x 1 pixel: POV-Ray's start-up and parse, the fixed cost inside every frame time.
    std::string tiny_text = pov::export_pov(scene, 1, 1);
    std::vector<double> seconds[3];
    for (int run = 0; run < arguments.runs; ++run) {
        for (int k = 0; k < 3; ++k) {
            auto start = std::chrono::steady_clock::now();
            if (k < 2) {
                pov::render_with_povray(povray, folder, name, pov_text, size.width, size.height,
                                        k == 0 ? 1 : all_threads);
            } else {
                // Its own file name: OpenImageIO caches images by name, and the size differs.
                pov::render_with_povray(povray, folder, name + "-1x1", tiny_text, 1, 1, 1);
            }
            seconds[k].push_back(seconds_since(start));
        }
    }
    fs::remove_all(folder);
    double one = median(seconds[0]), all = median(seconds[1]), start_up = median(seconds[2]);
    report.povray.add_row({name, cell("%.3f", one), cell("%.3f", all), cell("%.3f", start_up),
                           cell("%.4f", sse_seconds[0]), cell("%.4f", sse_seconds[1]),
                           cell("%.1f", one / sse_seconds[0]), cell("%.1f", all / sse_seconds[1]),
                           cell("%.1f", (one - start_up) / sse_seconds[0])});
}

void bench_first_hits(const std::string& name, const scene::Scene& scene, int width, int runs, Accel accel,
                      Report& report) {
    RenderOptions options;
    options.width = width;
    options.threads = 1;
    options.accel = accel;
    std::vector<double> exact, fast;
    sse::FirstHits hits;
    for (int run = 0; run < runs; ++run) {
        hits = sse::cast_primary_rays(scene, options);
        exact.push_back(static_cast<double>(hits.rays) / hits.seconds / 1e6);
        sse::FirstHits fast_hits = sse::cast_primary_rays(scene, options, all_fast_knobs());
        fast.push_back(static_cast<double>(fast_hits.rays) / fast_hits.seconds / 1e6);
    }
    std::vector<std::string> row = {name, std::to_string(hits.rays), cell("%.2f", median(exact)),
                                    cell("%.2f", median(fast))};
#if TWINRAY_WITH_EMBREE
    if (std::string reason = peers::embree_unsupported_reason(scene); !reason.empty()) {
        row.insert(row.end(), {"n/a: " + reason, "", "", "", ""});
    } else
        try {
            peers::EmbreePeer embree(scene, width);
            std::vector<double> single, packets;
            std::uint64_t embree_hits = 0;
            for (int run = 0; run < runs; ++run) {
                peers::FirstHitRun one = embree.cast_single();
                peers::FirstHitRun four = embree.cast_packets();
                single.push_back(static_cast<double>(one.rays) / one.seconds / 1e6);
                packets.push_back(static_cast<double>(four.rays) / four.seconds / 1e6);
                embree_hits = one.hits;
            }
            row.insert(row.end(),
                       {cell("%.2f", median(single)), cell("%.2f", median(packets)),
                        cell("%.2f", median(exact) / median(single)), cell("%.2f", median(exact) / median(packets)),
                        std::to_string(static_cast<long long>(hits.hits) - static_cast<long long>(embree_hits))});
        } catch (const std::runtime_error& error) {
            row.insert(row.end(), {std::string("failed: ") + error.what(), "", "", "", ""});
        }
#else
    row.insert(row.end(), {"not built", "", "", "", ""});
#endif
    report.first_hit.add_row(row);
}

void bench_scaling(const BenchArguments& arguments, int all_threads, Report& report) {
    const std::vector<Configuration> configurations = {
        {"ref<double>", "reference", {}, 1},
        {"ref<float>", "reference-float", {}, 1},
        {"sse exact", "sse", {}, 1},
        {"sse fast", "sse", all_fast_knobs(), 1},
        {"sse exact " + std::to_string(all_threads) + "T", "sse", {}, all_threads},
    };
    report.scaling.headers = {"spheres", "image"};
    for (const Configuration& configuration : configurations) {
        report.scaling.headers.push_back(configuration.label + " ns/ray");
    }
    report.scaling.headers.push_back("sse first hit ns/ray");
#if TWINRAY_WITH_EMBREE
    report.scaling.headers.push_back("embree rtcIntersect1 ns/ray");
#endif
    const std::pair<int, int> family[] = {{10, 320}, {100, 320}, {1000, 160}, {10000, 80}};
    for (auto [count, width] : family) {
        scene::Scene scene = scene::sphere_field(count);
        scene::ImageSize size = scene::resolve_image_size(scene, width, 0);
        std::vector<std::string> row = {std::to_string(count),
                                        std::to_string(size.width) + "x" + std::to_string(size.height)};
        for (const Timings& timing :
             time_renders(configurations, scene, width, arguments.runs, nullptr, arguments.accel)) {
            row.push_back(cell("%.1f", 1e3 / median(timing.mrays)));
        }
        RenderOptions options;
        options.width = width;
        options.threads = 1;
        options.accel = arguments.accel;
        std::vector<double> first_hit;
        for (int run = 0; run < arguments.runs; ++run) {
            sse::FirstHits hits = sse::cast_primary_rays(scene, options);
            first_hit.push_back(hits.seconds * 1e9 / static_cast<double>(hits.rays));
        }
        row.push_back(cell("%.1f", median(first_hit)));
#if TWINRAY_WITH_EMBREE
        peers::EmbreePeer embree(scene, width);
        std::vector<double> single;
        for (int run = 0; run < arguments.runs; ++run) {
            peers::FirstHitRun one = embree.cast_single();
            single.push_back(one.seconds * 1e9 / static_cast<double>(one.rays));
        }
        row.push_back(cell("%.1f", median(single)));
#endif
        report.scaling.add_row(row);
        std::fputs(".", stderr);
    }
}

}  // namespace twinray::cli::bench
