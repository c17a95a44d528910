// The page `twinray diff` writes (DIR/index.html), laid out for triage: a summary, the scenes failures first
// with a filter, and per scene the images, the error map with its failing clusters boxed, the numbers and
// the commands to run next. Opens from disk: no network, no external resources.
#pragma once

#include "accuracy/attribution.h"
#include "compare/failing_clusters.h"
#include "compare/image_compare.h"
#include "compare/tolerances.h"

#include <optional>
#include <string>
#include <vector>

namespace twinray::cli {

// POV-Ray's render of the scene against the reference's, both as 8-bit PNGs store them.
struct PovrayColumn {
    double seconds = 0;
    compare::Metrics metrics;
    long within_two_levels = 0;
};

struct SceneReport {
    std::string name;        // the scene file's stem, also the folder of its images
    std::string scene_path;  // as given on the command line, for the commands the page prints
    std::string judged;      // the tracer judged against the reference, for people: "SSE" or the plug-in's description
    compare::SceneTolerances tolerances;
    compare::Metrics metrics;
    compare::Verdict verdict = compare::Verdict::pass;
    double reference_seconds = 0, sse_seconds = 0;  // tracing alone, without the tracer's set-up
    int width = 0, height = 0;
    std::vector<compare::PixelError> worst;
    std::vector<compare::FailingCluster> clusters;
    accuracy::Attribution attribution;  // why each pixel over the warn threshold differs
    std::string attribution_failure;    // why the verdict rule fails the scene; empty if it does not
    std::optional<PovrayColumn> povray;
};

// The legend's image, written beside the page.
inline constexpr const char* legend_file = "legend.png";

// "0.0123%": count as a share of total.
std::string percent(long count, long total);

// The `twinray probe` command of one pixel, its size given so that it finds the pixel whatever the scene's.
std::string probe_command(const SceneReport& report, const compare::PixelError& pixel);

// Scenes are shown FAIL first, then WARN, then PASS, each by name.
// `thresholds_source` names where the scenes' thresholds came from (the manifest, or the built-in defaults).
// `judged` names the tracer the reference is held against, as SceneReport::judged does.
std::string report_page(std::vector<SceneReport> reports, const compare::HeatMapScale& scale, bool with_povray,
                        const std::string& thresholds_source, const std::string& judged);

}  // namespace twinray::cli
