// The depth control's trade (scene/depth_control.h): on every scene with mirrors or glass, rays traced and
// time with the proven cutoff against no cutoff at all (min_weight 0), and what the cutoff changed.
#include "cli/bench_run.h"
#include "cli/tracers.h"
#include "compare/image_compare.h"

#include <cmath>

namespace twinray::cli::bench {
namespace {

struct Measured {
    std::vector<double> seconds;
    TraceTally tally;
    Image image{1, 1};
};

// The most any component moves in the PNG (image_file.h's quantize_8bit), in 8-bit levels.
long largest_level_change(const Image& a, const Image& b) {
    return std::lround(255 * compare::measure(compare::quantized_8bit(a), compare::quantized_8bit(b), {}).max_error);
}

}  // namespace

void bench_depth_control(const std::string& name, const scene::Scene& scene, const BenchArguments& arguments,
                         Report& report) {
    if (!scene.has_reflection() && !scene.has_transparency()) {
        return;
    }
    scene::Scene without_cutoff = scene;
    without_cutoff.min_weight = 0.0;
    RenderOptions options;
    options.width = arguments.width;
    options.threads = 1;
    for (const char* tracer : {"reference", "sse"}) {
        Measured cut, full;
        // Alternated, so a slow spell of the shared machine weighs on both sides of the ratio.
        for (int run = 0; run < arguments.runs; ++run) {
            for (auto [measured, rendered] :
                 {std::pair{&cut, &scene}, std::pair<Measured*, const scene::Scene*>{&full, &without_cutoff}}) {
                auto start = std::chrono::steady_clock::now();
                RenderResult result = render_with(tracer, *rendered, options, {});
                measured->seconds.push_back(seconds_since(start));
                measured->tally = result.tally;
                measured->image = std::move(result.image);
            }
        }
        compare::Metrics change = compare::measure(full.image, cut.image, {});
        report.depth.add_row({name, tracer, std::to_string(full.tally.rays), std::to_string(cut.tally.rays),
                              std::to_string(cut.tally.dropped_rays), std::to_string(cut.tally.pixels_over_budget),
                              cell("%.4f", median(full.seconds)), cell("%.4f", median(cut.seconds)),
                              cell("%.2f", median(full.seconds) / median(cut.seconds)), cell("%.3g", change.max_error),
                              std::to_string(largest_level_change(full.image, cut.image))});
    }
}

}  // namespace twinray::cli::bench
