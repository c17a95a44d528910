// First hits of primary rays on the given scene files, one thread, CPU time, in alternated rounds: each round
// casts the SSE tracer's packets (sse::cast_primary_rays, --accel bvh) and then, where Embree is built, its
// rtcIntersect1 in each mode and ISA `twinray bench --scaling` times, so that this machine's drift of speed
// over seconds falls on every side alike. Prints the median ns per ray of each side and the median of its ratios
// to ours within a round: the quick loop for work on the walk and the leaves (`bench --scaling` is the full
// table). --flattened also times a scene of instances flattened into world coordinates (scene::flattened, where
// that fits the primitive limit), as `twinray bench` does: issue 25's "within 1.5x of flattened".
//   first_hit_benchmark [--runs N] [--width W] [--no-peers] [--flattened] SCENE...
//   (--no-peers: the SSE tracer alone, to profile)
#include "math/median.h"
#include "scene/loader.h"
#include "scene/placement.h"
#include "sse/tracer.h"

#if TWINRAY_WITH_EMBREE
#include "peers/embree_peer.h"
#endif

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <vector>

namespace {

using namespace twinray;

using math::median;

struct Side {
    std::string name;
    std::vector<double> seconds;
    std::uint64_t rays = 0;
    std::uint64_t hits = 0;

    void add_round(double round_seconds, std::uint64_t round_rays, std::uint64_t round_hits) {
        seconds.push_back(round_seconds);
        rays = round_rays;
        hits = round_hits;
    }
};

void time_scene(const std::string& file, int runs, int width, [[maybe_unused]] bool with_peers, bool with_flattened) {
    const scene::Scene scene = scene::load_scene(file);
    std::optional<scene::Scene> flat;
    if (with_flattened && scene.has_instances()) {
        flat = scene::flattened(scene);
        if (flat->primitive_count() > scene::max_scene_primitives) {
            std::printf("%s: flattened, %llu primitives pass the limit of %llu: not timed\n", file.c_str(),
                        static_cast<unsigned long long>(flat->primitive_count()),
                        static_cast<unsigned long long>(scene::max_scene_primitives));
            flat.reset();
        }
    }
    RenderOptions options;
    options.width = width;
    options.threads = 1;
    options.accel = Accel::bvh;
    std::vector<Side> sides = {{"sse exact", {}, 0, 0}};
    if (flat) {
        sides.push_back({"sse exact flattened", {}, 0, 0});
    }
#if TWINRAY_WITH_EMBREE
    const std::size_t first_peer = sides.size();
    struct Variant {
        const char* name;
        peers::EmbreeIsa isa;
        peers::EmbreeMode mode;
    };
    const Variant variants[] = {{"embree widest", peers::EmbreeIsa::widest, peers::EmbreeMode::standard},
                                {"embree widest robust", peers::EmbreeIsa::widest, peers::EmbreeMode::robust},
                                {"embree sse4.2", peers::EmbreeIsa::sse42, peers::EmbreeMode::standard},
                                {"embree sse4.2 robust", peers::EmbreeIsa::sse42, peers::EmbreeMode::robust}};
    for (std::size_t i = 0; with_peers && i < std::size(variants); ++i) {
        sides.push_back({variants[i].name, {}, 0, 0});
    }
#endif
    const auto cast_ours = [&](const scene::Scene& cast, Side& side) {
        const sse::FirstHits ours = sse::cast_primary_rays(cast, options);
        side.add_round(ours.tracing_cpu_seconds, ours.rays, ours.hits);
    };
    for (int run = 0; run < runs; ++run) {
        cast_ours(scene, sides[0]);
        if (flat) {
            cast_ours(*flat, sides[1]);  // pushed right after ours
        }
#if TWINRAY_WITH_EMBREE
        for (std::size_t i = 0; first_peer + i < sides.size(); ++i) {
            peers::EmbreePeer peer(scene, width, variants[i].isa, variants[i].mode);
            const peers::FirstHitRun theirs = peer.cast_single();
            sides[first_peer + i].add_round(theirs.seconds, theirs.rays, theirs.hits);
        }
#endif
    }
    std::printf("%s: %llu primitives, %d runs, width %d\n", file.c_str(),
                static_cast<unsigned long long>(scene.primitive_count()), runs, width);
    // Ratios are taken within each round, then their median: this VM's speed drifts by a third over minutes,
    // far more than the rounds of one side differ from each other.
    for (const Side& side : sides) {
        std::vector<double> ratios;
        for (std::size_t round = 0; round < side.seconds.size(); ++round) {
            ratios.push_back(side.seconds[round] / sides[0].seconds[round]);
        }
        const double ns = median(side.seconds) * 1e9 / static_cast<double>(side.rays);
        std::printf("  %-22s %8.1f ns/ray  %5.2fx ours  %llu of %llu rays hit\n", side.name.c_str(), ns, median(ratios),
                    static_cast<unsigned long long>(side.hits), static_cast<unsigned long long>(side.rays));
    }
}

}  // namespace

int main(int argc, char** argv) {
    int runs = 5;
    int width = 640;
    bool with_peers = true;
    bool with_flattened = false;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
        const std::string argument = argv[i];
        if ((argument == "--runs" || argument == "--width") && i + 1 < argc) {
            const int value = std::atoi(argv[++i]);
            if (value < 1) {
                std::fprintf(stderr, "first_hit_benchmark: %s wants a positive whole number\n", argument.c_str());
                return 2;
            }
            (argument == "--runs" ? runs : width) = value;
        } else if (argument == "--no-peers") {
            with_peers = false;
        } else if (argument == "--flattened") {
            with_flattened = true;
        } else if (argument.rfind("--", 0) == 0) {
            std::fprintf(stderr, "first_hit_benchmark: unknown option %s\n", argument.c_str());
            return 2;
        } else {
            files.push_back(argument);
        }
    }
    if (files.empty()) {
        std::fprintf(stderr, "usage: first_hit_benchmark [--runs N] [--width W] [--no-peers] [--flattened] SCENE...\n");
        return 2;
    }
    try {
        for (const std::string& file : files) {
            time_scene(file, runs, width, with_peers, with_flattened);
        }
    } catch (const std::exception& error) {
        std::fprintf(stderr, "first_hit_benchmark: %s\n", error.what());
        return 1;
    }
    return 0;
}
