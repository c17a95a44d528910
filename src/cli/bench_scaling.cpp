// `twinray bench --scaling` (docs/performance.md, "Scaling"): scene families from 10 to a million primitives,
// with every figure a target of issue 13 is held against side by side in one run: time per ray of both tracers
// with and without their BVH, first hits against Embree 3, whole renders against POV-Ray 3.7, the BVH's build
// time and bytes, and the render on all threads against one.
#include "cli/bench_run.h"
#include "cli/generate_scene.h"
#include "cli/tracers.h"
#include "pov/povray_runner.h"
#include "scene/loader.h"
#include "scene/sphere_field.h"
#include "sse/tracer.h"
#if TWINRAY_WITH_EMBREE
#include "peers/embree_peer.h"
#endif

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace twinray::cli::bench {
namespace {

namespace fs = std::filesystem;

// What one configuration may cost per frame: slower ones render a smaller image (their time per ray stays
// comparable) or, if even the smallest would take longer, are left out with the time it would have taken.
constexpr double frame_budget_seconds = 1.0;
constexpr int smallest_width = 20;

struct Family {
    const char* name;
    scene::Scene (*make)(int size);
};

scene::Scene generated(const char* family, int size) {
    std::string text;
    generate_scene(family, size, 1, {[&](std::string_view piece) { text.append(piece); }, {}});
    return scene::parse_scene(text, family);
}

// Spheres alone (Embree's native primitive, for the first-hit target); the sphereflake, reflective; a lattice
// of cylinders joined by spheres (cylinders for the POV-Ray target); a tessellated sphere, one closed mesh of
// shared vertices, and the SPD tetra, 4^d closed shells (the largest 4^(d+1) triangles not above the size asked
// for: 262 144 for a million).
const Family families[] = {
    {"spheres", [](int size) { return scene::sphere_field(size); }},
    {"fractal", [](int size) { return generated("fractal", size); }},
    {"lattice", [](int size) { return generated("lattice", size); }},
    {"sphere-mesh", [](int size) { return generated("sphere-mesh", size); }},
    {"tetra", [](int size) { return generated("tetra", size); }},
};

#if TWINRAY_WITH_EMBREE
// Embree as the first-hit table times it: its widest kernels (the target's peer, and its build) and its SSE4.2
// ones, as narrow as ours; on meshes each in robust mode too, Embree's answer to rays slipping through the edges
// triangles share, which our watertight test rules out.
struct EmbreeVariant {
    peers::EmbreeIsa isa;
    peers::EmbreeMode mode;
};
constexpr EmbreeVariant embree_variants[] = {
    {peers::EmbreeIsa::widest, peers::EmbreeMode::standard},
    {peers::EmbreeIsa::sse42, peers::EmbreeMode::standard},
    {peers::EmbreeIsa::widest, peers::EmbreeMode::robust},
    {peers::EmbreeIsa::sse42, peers::EmbreeMode::robust},
};

// Embree's coherent packets (RTC_INTERSECT_CONTEXT_FLAG_COHERENT) on its widest kernels and on its SSE4.2 ones (as
// wide as ours: where its widest are far ahead, this says how much of that is their 16 lanes), at each width its API
// offers; the table keeps the fastest.
constexpr int embree_packet_lanes[] = {4, 8, 16};
#endif

// The first-hit table's Embree cells, ns/ray and the ratio to ours per variant, then the coherent packets' ns/ray,
// their width and ratio on the widest kernels and on SSE4.2, when none is timed.
std::vector<std::string> embree_left_out(const std::string& why) {
    return {why, "", "", "", "", "", "", "", "", "", "", "", "", ""};
}

struct ScaledConfiguration {
    Configuration configuration;
    Accel accel;
};

const ScaledConfiguration render_configurations[] = {
    {{"sse bvh", "sse", {}, 1}, Accel::bvh},
    {{"sse brute", "sse", {}, 1}, Accel::none},
    {{"ref<double> bvh", "reference", {}, 1}, Accel::bvh},
    {{"ref<double> brute", "reference", {}, 1}, Accel::none},
};

// A configuration's time per ray at the sizes before (measured or, once left out, predicted), to predict the
// next size's: its growth over the last step again (brute force's is about the primitive count's).
struct Trend {
    double ns_per_ray = 0, previous_ns_per_ray = 0;
    double rays_per_pixel = 0;
    std::int64_t primitives = 0;

    double predict(std::int64_t next_primitives) const {
        double growth = previous_ns_per_ray > 0
                            ? ns_per_ray / previous_ns_per_ray
                            : static_cast<double>(next_primitives) / static_cast<double>(primitives);
        return ns_per_ray * std::max(1.0, growth);
    }
    void record(double ns, double per_pixel, std::int64_t count) {
        previous_ns_per_ray = ns_per_ray;
        ns_per_ray = ns;
        rays_per_pixel = per_pixel;
        primitives = count;
    }
};

std::int64_t pixels(const scene::Scene& scene, int width) {
    scene::ImageSize size = scene::resolve_image_size(scene, width, 0);
    return static_cast<std::int64_t>(size.width) * size.height;
}

std::string image_text(const scene::Scene& scene, int width) {
    scene::ImageSize size = scene::resolve_image_size(scene, width, 0);
    return std::to_string(size.width) + "x" + std::to_string(size.height);
}

// The widest of base_width, base_width / 2, ... down to smallest_width whose frame fits the budget by the
// trend's prediction; 0 if none does.
int affordable_width(const scene::Scene& scene, int base_width, const Trend& trend, std::int64_t primitives) {
    if (trend.primitives == 0) {
        return base_width;  // the first size: ten primitives cost nothing
    }
    double ns = trend.predict(primitives);
    for (int width = base_width; width >= smallest_width; width /= 2) {
        if (ns * 1e-9 * trend.rays_per_pixel * static_cast<double>(pixels(scene, width)) <= frame_budget_seconds) {
            return width;
        }
    }
    return 0;
}

double median_ns_per_ray(const std::vector<double>& seconds, std::uint64_t rays) {
    return median(seconds) * 1e9 / static_cast<double>(rays);
}

void progress(const std::string& text) {
    std::fputs(text.c_str(), stderr);
    std::fflush(stderr);
}

// One family at one size: a row of each scaling table but the threads'.
struct SizeRun {
    const BenchArguments& arguments;
    const std::optional<fs::path>& povray;
    Report& report;
    const char* family;
    const scene::Scene& scene;
    std::int64_t primitives;

    // Per configuration: ns per ray, or "—" and what a frame would have cost. Sets the SSE BVH's timings and
    // width (0: left out).
    void renders(std::vector<Trend>& trends, double& sse_at_100, Timings& sse_bvh, int& sse_width) const {
        std::vector<std::string> times, widths;
        sse_width = 0;
        for (std::size_t i = 0; i < std::size(render_configurations); ++i) {
            const auto& [configuration, accel] = render_configurations[i];
            progress(" " + configuration.label);
            int width = affordable_width(scene, arguments.width, trends[i], primitives);
            if (width == 0) {
                double ns = trends[i].predict(primitives);
                double frame =
                    ns * 1e-9 * trends[i].rays_per_pixel * static_cast<double>(pixels(scene, smallest_width));
                times.push_back("— (" + cell("%.0f", frame) + " s a frame at " + image_text(scene, smallest_width) +
                                ")");
                widths.emplace_back("—");
                trends[i].record(ns, trends[i].rays_per_pixel, primitives);
                continue;
            }
            Timings timing = time_renders({configuration}, scene, width, arguments.runs, nullptr, accel)[0];
            double ns = median_ns_per_ray(timing.tracing_cpu_seconds, timing.rays);
            trends[i].record(ns, static_cast<double>(timing.rays) / static_cast<double>(pixels(scene, width)),
                             primitives);
            times.push_back(cell("%.1f", ns));
            widths.push_back(std::to_string(width));
            if (i == 0) {
                sse_bvh = timing;
                sse_width = width;
            }
        }
        double sse_ns = trends[0].ns_per_ray;
        if (primitives >= 50 && primitives < 500) {
            sse_at_100 = sse_ns;  // the row the growth target starts from (100, or its family's nearest)
        }
        std::vector<std::string> row = {family, std::to_string(primitives)};
        row.insert(row.end(), times.begin(), times.end());
        row.push_back(sse_at_100 > 0 ? cell("%.2f", sse_ns / sse_at_100) : "");
        std::string joined;
        for (const std::string& width : widths) {
            joined += (joined.empty() ? "" : " / ") + width;
        }
        row.push_back(joined);
        row.push_back(cell("%.2f", trends[0].rays_per_pixel));
        report.scaling.add_row(row);
    }

    // First hits of the SSE tracer (--accel as given), Embree's rtcIntersect1 (embree_variants) and its coherent
    // packets on the same primary rays, both BVHs' builds, and POV-Ray's trace against the SSE tracer's render at the
    // SSE BVH's width, with --accel as given: what `twinray render` runs (at 10 spheres, auto's brute force renders
    // in about half the BVH's time).
    void peers(const Timings& sse_bvh, int sse_width) const {
        progress(" first-hits, builds");
        RenderOptions options;
        options.width = arguments.width;
        options.threads = 1;
        options.accel = arguments.accel;
        // Each run times every side in turn, ours and Embree's: this VM's speed drifts by a third over seconds,
        // and a ratio of two sides timed far apart would carry that drift.
        std::vector<double> sse_cpu, sse_build_cpu, embree_build_cpu;
#if TWINRAY_WITH_EMBREE
        std::vector<std::vector<double>> embree_cpu(std::size(embree_variants));  // per variant; empty: not timed
        // Per width, on the widest kernels and on SSE4.2.
        std::vector<std::vector<double>> embree_packet_cpu(std::size(embree_packet_lanes));
        std::vector<std::vector<double>> embree_sse42_packet_cpu(std::size(embree_packet_lanes));
#endif
        sse::FirstHits hits;
        sse::BvhStats stats;
        for (int run = 0; run < arguments.runs; ++run) {
            hits = sse::cast_primary_rays(scene, options);
            sse_cpu.push_back(hits.tracing_cpu_seconds);
            stats = sse::Tracer(scene, {}, Accel::bvh).bvh_stats();
            sse_build_cpu.push_back(stats.build_cpu_seconds);
#if TWINRAY_WITH_EMBREE
            for (std::size_t i = 0; arguments.peers && i < std::size(embree_variants); ++i) {
                const auto [isa, mode] = embree_variants[i];
                if (mode == peers::EmbreeMode::robust && !scene.has_meshes()) {
                    continue;
                }
                peers::EmbreePeer peer(scene, arguments.width, isa, mode);
                if (i == 0) {
                    embree_build_cpu.push_back(peer.build_seconds());
                }
                if (mode == peers::EmbreeMode::standard) {
                    for (std::size_t k = 0; k < std::size(embree_packet_lanes); ++k) {
                        (isa == peers::EmbreeIsa::widest ? embree_packet_cpu : embree_sse42_packet_cpu)[k].push_back(
                            peer.cast_packets(embree_packet_lanes[k]).seconds);
                    }
                }
                embree_cpu[i].push_back(peer.cast_single().seconds);
            }
#endif
        }
        double sse_ns = median_ns_per_ray(sse_cpu, hits.rays);
        std::vector<std::string> row = {family, std::to_string(primitives), std::to_string(hits.rays),
                                        cell("%.1f", sse_ns)};
        std::vector<std::string> embree = embree_left_out("left out (--no-peers)");
        std::vector<std::string> build = {"", ""};
#if TWINRAY_WITH_EMBREE
        if (arguments.peers) {
            embree.clear();
            for (const std::vector<double>& seconds : embree_cpu) {
                if (seconds.empty()) {
                    embree.insert(embree.end(), {"no meshes", ""});
                    continue;
                }
                double ns = median_ns_per_ray(seconds, hits.rays);
                embree.insert(embree.end(), {cell("%.1f", ns), cell("%.2f", ns / sse_ns)});
            }
            // The fastest packet width on this scene, named beside its time.
            for (const auto* per_width : {&embree_packet_cpu, &embree_sse42_packet_cpu}) {
                double packet_ns = 0;
                int fastest_lanes = 0;
                for (std::size_t k = 0; k < std::size(embree_packet_lanes); ++k) {
                    double ns = median_ns_per_ray((*per_width)[k], hits.rays);
                    if (fastest_lanes == 0 || ns < packet_ns) {
                        packet_ns = ns;
                        fastest_lanes = embree_packet_lanes[k];
                    }
                }
                embree.insert(embree.end(), {cell("%.1f", packet_ns), std::to_string(fastest_lanes),
                                             cell("%.2f", packet_ns / sse_ns)});
            }
            double build_seconds = median(embree_build_cpu);
            build = {cell("%.1f", build_seconds * 1e3),
                     cell("%.2f", static_cast<double>(primitives) / build_seconds / 1e6)};
        }
#else
        embree = embree_left_out("not built");
        build = {"not built", ""};
#endif
        row.insert(row.end(), embree.begin(), embree.end());
        row.push_back(sse_width > 0 ? image_text(scene, sse_width) : "—");
        Timings sse_render = sse_bvh;
        if (sse_width > 0 && arguments.accel != Accel::bvh) {
            progress(" sse " + accel_name(arguments.accel));
            sse_render =
                time_renders({{"sse", "sse", {}, 1}}, scene, sse_width, arguments.runs, nullptr, arguments.accel)[0];
        }
        double sse_seconds = sse_width > 0 ? median(sse_render.tracing_cpu_seconds) : 0;
        if (sse_width == 0) {
            row.insert(row.end(), {"—", "", "", "", "", "", ""});
        } else if (!arguments.peers) {
            row.insert(row.end(), {"left out (--no-peers)", "", "", cell("%.4f", sse_seconds), "", "", ""});
        } else if (!povray) {
            row.insert(row.end(), {"not installed", "", "", cell("%.4f", sse_seconds), "", "", ""});
        } else {
            progress(" povray");
            try {
                PovrayTimes pov = time_povray(family, scene, sse_width, arguments.runs, *povray, {1}, false);
                // POV-Ray's start-up removed as POV-Ray itself reports its trace: at a million primitives its
                // parse takes 15 s and the trace 1 to 3, too little a difference of two whole processes to
                // survive their noise.
                double trace = pov.trace_cpu[0];
                double pov_ns_per_ray = trace * 1e9 / static_cast<double>(sse_render.rays);
                row.insert(row.end(),
                           {cell("%.3f", pov.frame_cpu[0]), cell("%.3f", pov.set_up_cpu[0]), cell("%.3f", trace),
                            cell("%.4f", sse_seconds), cell("%.1f", trace / sse_seconds), cell("%.1f", pov_ns_per_ray),
                            cell("%.1f", pov_ns_per_ray / 10)});
            } catch (const pov::PovrayError& error) {
                progress(std::string("\nPOV-Ray failed: ") + error.what() + "\n");
                row.insert(row.end(), {"failed", "", "", cell("%.4f", sse_seconds), "", "", ""});
            }
        }
        report.scaling_peers.add_row(row);
        build_row(stats, median(sse_build_cpu), build);
    }

    // The SSE tracer's BVH (sse::Tracer::bvh_stats): build time on one thread, rate, bytes per item.
    void build_row(const sse::BvhStats& stats, double seconds, const std::vector<std::string>& embree_build) const {
        double rate = static_cast<double>(stats.items) / seconds / 1e6;
        std::vector<std::string> row = {
            family,
            std::to_string(primitives),
            std::to_string(stats.items),
            std::to_string(stats.nodes),
            cell("%.2f", seconds * 1e3),
            cell("%.2f", rate),
            cell("%.1f", static_cast<double>(stats.bytes) / static_cast<double>(stats.items))};
        row.insert(row.end(), embree_build.begin(), embree_build.end());
        report.scaling_build.add_row(row);
    }
};

}  // namespace

void bench_scaling(const BenchArguments& arguments, int all_threads, const std::optional<fs::path>& povray,
                   Report& report) {
    for (const Family& family : families) {
        std::vector<Trend> trends(std::size(render_configurations));
        double sse_at_100 = 0;
        scene::Scene largest;
        std::int64_t largest_primitives = 0;
        for (int size = 10; size <= arguments.scaling_max; size *= 10) {
            progress(std::string("scaling: ") + family.name + " " + std::to_string(size) + ":");
            scene::Scene scene = family.make(size);
            const auto primitives = static_cast<std::int64_t>(scene.primitive_count());  // a mesh's triangles each
            progress(" " + std::to_string(primitives) + " primitives;");
            SizeRun run{arguments, povray, report, family.name, scene, primitives};
            Timings sse_bvh;
            int sse_width = 0;
            run.renders(trends, sse_at_100, sse_bvh, sse_width);
            run.peers(sse_bvh, sse_width);
            progress("\n");
            if (size * 10 > arguments.scaling_max) {
                largest = std::move(scene);
                largest_primitives = primitives;
            }
        }
        // All threads against one at the largest size, the images compared bit for bit.
        progress(std::string("scaling: ") + family.name + " " + std::to_string(largest_primitives) + ": threads\n");
        const std::vector<Configuration> threads = {{"sse bvh 1T", "sse", {}, 1},
                                                    {"sse bvh all", "sse", {}, all_threads}};
        std::vector<Image> images;
        std::vector<Timings> timings =
            time_renders(threads, largest, arguments.width, arguments.runs, &images, Accel::bvh);
        std::vector<double> speedups;
        for (std::size_t run = 0; run < timings[0].tracing_seconds.size(); ++run) {
            speedups.push_back(timings[0].tracing_seconds[run] / timings[1].tracing_seconds[run]);
        }
        report.scaling_threads.add_row(
            {family.name, std::to_string(largest_primitives), image_text(largest, arguments.width),
             cell("%.4f", median(timings[0].tracing_seconds)), cell("%.4f", median(timings[1].tracing_seconds)),
             cell("%.2f", median(speedups)), same_bits(images[0], images[1]) ? "yes" : "NO"});
    }
}

}  // namespace twinray::cli::bench
