#include "cli/diff_report.h"
#include "io/formatted.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace twinray::cli {

// The size is given explicitly so the command finds the same pixel whatever --width diff ran at.
std::string probe_command(const SceneReport& report, const compare::PixelError& pixel) {
    return "twinray probe " + report.scene_path + " --pixel " + std::to_string(pixel.x) + "," +
           std::to_string(pixel.y) + " --width " + std::to_string(report.width) + " --height " +
           std::to_string(report.height);
}

namespace {

std::string html_escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

std::string count_of(long count, const std::string& noun) {
    return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

// 1e-07 as 1e-7: the legend's ticks read as a user would write them.
std::string short_number(double value) {
    std::string text = io::formatted("%.3g", value);
    for (const char* padded : {"e-0", "e+0"}) {
        if (auto at = text.find(padded); at != std::string::npos) {
            text.replace(at, 3, padded[1] == '-' ? "e-" : "e");
        }
    }
    return text;
}

std::string approve_command(const SceneReport& report) {
    return "twinray golden --update " + report.scene_path;
}

// The command as text to select, and a button that copies it.
std::string copyable(const std::string& command) {
    return "<div class=\"command\"><code>" + html_escape(command) +
           "</code><button type=\"button\" class=\"copy\">copy</button></div>";
}

std::string image_path(const SceneReport& r, const char* image) {
    return html_escape(r.name) + "/" + image + ".png";
}

std::string figure(const SceneReport& r, const char* image, const std::string& caption) {
    return "<figure><img src=\"" + image_path(r, image) + "\" alt=\"" + image + "\" width=\"" +
           std::to_string(r.width) + "\" height=\"" + std::to_string(r.height) + "\"><figcaption>" + caption +
           "</figcaption></figure>\n";
}

// The reference, swapped for the judged tracer's image while hovered, or kept swapped by a click (the page's script).
std::string flip_figure(const SceneReport& r) {
    const std::string judged = html_escape(r.judged);
    std::ostringstream html;
    html << "<figure class=\"flip\"><div class=\"frame\" title=\"hover: " << judged << "; click: keep " << judged
         << "\">";
    for (const char* image : {"reference", "sse"}) {
        html << "<img class=\"" << image << "\" src=\"" << image_path(r, image) << "\" alt=\"" << image << "\" width=\""
             << r.width << "\" height=\"" << r.height << "\">";
    }
    html << "</div><figcaption><b class=\"showing-reference\">reference</b><b class=\"showing-sse\">" << judged
         << "</b>"
         << " &mdash; hover or click to flip</figcaption></figure>\n";
    return html.str();
}

std::string cluster_description(const compare::FailingCluster& cluster) {
    return count_of(cluster.pixels, "failing pixel") + " in x " + std::to_string(cluster.left) + "–" +
           std::to_string(cluster.right) + ", y " + std::to_string(cluster.top) + "–" + std::to_string(cluster.bottom) +
           "; worst " + io::formatted("%.4g", cluster.worst.error) + " at (" + std::to_string(cluster.worst.x) + ", " +
           std::to_string(cluster.worst.y) + ")";
}

// The error map with a box, in image pixels, around each cluster of failing pixels; the SVG stretches with
// the image, so the boxes stay on their pixels at any displayed size. Each box is drawn `box_margin` pixels
// outside its cluster, so that a cluster of one pixel is seen and the box does not hide what it boxes.
constexpr int box_margin = 2;

std::string error_map_figure(const SceneReport& r) {
    std::ostringstream html;
    html << "<figure><div class=\"frame\"><img src=\"" << image_path(r, "error") << "\" alt=\"error map\" width=\""
         << r.width << "\" height=\"" << r.height << "\">";
    if (!r.clusters.empty()) {
        html << "<svg viewBox=\"0 0 " << r.width << " " << r.height << "\" preserveAspectRatio=\"none\">";
        for (const compare::FailingCluster& cluster : r.clusters) {
            html << "<rect x=\"" << cluster.left - box_margin << "\" y=\"" << cluster.top - box_margin << "\" width=\""
                 << cluster.right - cluster.left + 1 + 2 * box_margin << "\" height=\""
                 << cluster.bottom - cluster.top + 1 + 2 * box_margin << "\"><title>"
                 << html_escape(cluster_description(cluster) + ": " + probe_command(r, cluster.worst))
                 << "</title></rect>";
        }
        html << "</svg>";
    }
    html << "</div><figcaption>error map";
    if (!r.clusters.empty()) {
        html << ", " << count_of(static_cast<long>(r.clusters.size()), "cluster") << " of failing pixels boxed";
    }
    html << "</figcaption></figure>\n";
    return html.str();
}

std::string metrics_table(const SceneReport& r) {
    const compare::Thresholds& t = r.tolerances.sse;
    std::ostringstream html;
    html << "<table>"
         << "<tr><th>max</th><td>" << io::formatted("%.4g", r.metrics.max_error) << " at (" << r.metrics.max_x << ", "
         << r.metrics.max_y << ") "
         << "RGB"[std::clamp(r.metrics.max_channel, 0, 2)] << "</td></tr>"
         << "<tr><th>over " << io::formatted("%.4g", t.fail) << "</th><td>" << r.metrics.fail_pixels << " ("
         << percent(r.metrics.fail_pixels, r.metrics.pixel_count) << ")</td></tr>"
         << "<tr><th>allowed</th><td>&le;&nbsp;" << io::formatted("%.4g", t.fail_percent) << "% over, max &le;&nbsp;"
         << io::formatted("%.4g", t.hard_fail) << "</td></tr>"
         << "<tr><th>mean, RMS</th><td>" << io::formatted("%.3g", r.metrics.mean_error) << ", "
         << io::formatted("%.3g", r.metrics.rms_error) << "</td></tr>"
         << "<tr><th>PSNR</th><td>" << io::formatted("%.1f dB", r.metrics.psnr) << "</td></tr>"
         << "<tr><th>render</th><td>reference " << io::formatted("%.3f s", r.reference_seconds) << ", "
         << html_escape(r.judged) << " " << io::formatted("%.3f s", r.sse_seconds) << ": "
         << io::formatted("%.1f&times;", r.reference_seconds / r.sse_seconds)
         << " <small>(tracing only: loading the scene and compiling it excluded)</small></td></tr>"
         << "<tr><th>causes</th><td>of the pixels over " << io::formatted("%.4g", t.warn) << ": ";
    for (int c = 0; c < accuracy::cause_count; ++c) {
        html << (c > 0 ? ", " : "") << accuracy::cause_name(static_cast<accuracy::Cause>(c)) << " "
             << r.attribution.counts[static_cast<std::size_t>(c)];
    }
    if (!r.attribution_failure.empty()) {
        html << "<br><b>fails: " << html_escape(r.attribution_failure) << "</b>";
    }
    html << "</td></tr></table>\n";
    return html.str();
}

std::string facts(const SceneReport& r) {
    std::ostringstream html;
    html << "<div class=\"facts\">" << metrics_table(r);
    if (r.povray) {
        html << "<p>POV-Ray " << io::formatted("%.3f s", r.povray->seconds)
             << " (one thread, with start-up): " << percent(r.povray->within_two_levels, r.povray->metrics.pixel_count)
             << " of pixels within 2/255 of the reference, max "
             << io::formatted("%.0f/255", r.povray->metrics.max_error * 255.0) << "</p>";
    }
    if (!r.tolerances.why.empty()) {
        html << "<details class=\"why\"><summary>why these thresholds</summary>" << html_escape(r.tolerances.why)
             << "</details>";
    }
    html << "<p class=\"label\">approve the reference render as the golden image (from the repository root):</p>"
         << copyable(approve_command(r));
    if (!r.clusters.empty()) {
        html << "<details><summary>" << count_of(static_cast<long>(r.clusters.size()), "failing cluster")
             << ", largest first</summary><ol>";
        for (const compare::FailingCluster& cluster : r.clusters) {
            html << "<li>" << cluster_description(cluster) << copyable(probe_command(r, cluster.worst)) << "</li>";
        }
        html << "</ol></details>";
    }
    html << "<details><summary>worst " << r.worst.size() << " pixels</summary><ol>";
    for (const compare::PixelError& pixel : r.worst) {
        html << "<li>(" << pixel.x << ", " << pixel.y << ") " << io::formatted("%.4g", pixel.error)
             << copyable(probe_command(r, pixel)) << "</li>";
    }
    html << "</ol></details></div>\n";
    return html.str();
}

std::string scene_section(const SceneReport& r) {
    const char* verdict = compare::to_string(r.verdict);
    std::ostringstream html;
    html << "<section class=\"scene " << verdict << "\" data-status=\"" << verdict << "\" data-name=\""
         << html_escape(r.name) << "\">\n<header><h2>" << html_escape(r.name) << "</h2><span class=\"badge " << verdict
         << "\">" << verdict << "</span><span>" << r.width << "&times;" << r.height << "</span><span>"
         << count_of(r.metrics.fail_pixels, "pixel") << " over " << io::formatted("%.4g", r.tolerances.sse.fail) << " ("
         << percent(r.metrics.fail_pixels, r.metrics.pixel_count) << "), max "
         << io::formatted("%.4g", r.metrics.max_error) << "</span></header>\n<div class=\"panels\">\n"
         << flip_figure(r) << error_map_figure(r)
         << figure(r, "mask", "mask: white over " + io::formatted("%.4g", r.tolerances.sse.fail));
    if (r.povray) {
        html << figure(r, "povray", "POV-Ray") << figure(r, "povray_error", "POV-Ray against the reference (8-bit)");
    }
    html << facts(r) << "</div>\n</section>\n";
    return html.str();
}

std::string summary(const std::vector<SceneReport>& reports) {
    long failing = 0, pixels = 0;
    int per_verdict[3] = {0, 0, 0};
    for (const SceneReport& r : reports) {
        failing += r.metrics.fail_pixels;
        pixels += r.metrics.pixel_count;
        ++per_verdict[static_cast<int>(r.verdict)];
    }
    std::ostringstream html;
    html << "<div class=\"summary\"><p>" << reports.size() << " scenes: ";
    for (compare::Verdict verdict : {compare::Verdict::fail, compare::Verdict::warn, compare::Verdict::pass}) {
        html << "<span class=\"badge " << compare::to_string(verdict) << "\">" << per_verdict[static_cast<int>(verdict)]
             << " " << compare::to_string(verdict) << "</span> ";
    }
    html << "</p><p>pixels over their scene's fail threshold, in all: <b>" << failing << "</b> of " << pixels << " ("
         << percent(failing, pixels) << ")</p><p>unexplained pixels, in all: ";
    long unexplained = 0;
    for (const SceneReport& r : reports) {
        unexplained += r.attribution.counts[static_cast<std::size_t>(accuracy::Cause::unexplained)];
    }
    html << "<b>" << unexplained << "</b>";
    html << "</p></div>\n";
    return html.str();
}

std::string filter_controls(std::size_t scenes) {
    std::ostringstream html;
    html << "<form class=\"filter\" id=\"filter\"><span>show</span>";
    for (const char* verdict : {"FAIL", "WARN", "PASS"}) {
        html << "<label><input type=\"checkbox\" name=\"status\" value=\"" << verdict << "\" checked> " << verdict
             << "</label>";
    }
    html << "<label>name <input type=\"search\" id=\"name-filter\" placeholder=\"part of a scene's name\"></label>"
         << "<output id=\"shown\">" << scenes << " of " << scenes << " scenes shown</output></form>\n";
    return html.str();
}

std::string legend(const compare::HeatMapScale& scale) {
    std::ostringstream html;
    html << "<div class=\"legend\"><div><span class=\"zero\"></span> 0: identical</div><div class=\"bar\"><img src=\""
         << legend_file << "\" alt=\"error map legend\"><div class=\"ticks\">";
    for (const compare::LegendTick& tick : compare::legend_ticks(scale)) {
        html << "<span style=\"left:" << io::formatted("%.2f", 100.0 * tick.position) << "%\">"
             << (tick.position == 1 ? "&ge; " : "") << short_number(tick.error) << "</span>";
    }
    html << "</div></div><p>Error map: each pixel's largest channel difference, "
         << (scale.is_logarithmic() ? "on a logarithmic scale (each decade an equal stretch of the colours)"
                                    : "on a linear scale")
         << ". Boxes: clusters of pixels over the scene's fail threshold (hover for the size and the worst "
            "pixel's probe command). Mask: white where a pixel is over that threshold, the reference dimmed "
            "elsewhere.</p></div>\n";
    return html.str();
}

constexpr const char* style = R"(<style>
*{box-sizing:border-box}
body{font:14px/1.4 sans-serif;margin:0 auto;padding:.5em 1em;max-width:1280px;background:#fafafa;color:#222}
h1{font-size:1.35em;margin:.3em 0}
[hidden]{display:none!important}
.summary{display:flex;flex-wrap:wrap;gap:0 2em;background:#fff;border:1px solid #ccc;padding:0 1em}
.summary p{margin:.5em 0}
.badge{font-weight:bold;padding:0 .4em;border-radius:3px;color:#fff;white-space:nowrap}
.badge.FAIL{background:#c00}.badge.WARN{background:#b60}.badge.PASS{background:#080}
.filter{display:flex;flex-wrap:wrap;gap:.4em 1em;align-items:center;margin:.6em 0}
.filter output{color:#555}
.legend{display:flex;flex-wrap:wrap;gap:0 1.5em;align-items:center;font-size:90%}
.legend p{flex:1 1 30em;margin:.3em 0;color:#444}
.legend .zero{display:inline-block;width:1em;height:1em;background:#000;vertical-align:middle}
.legend .bar{padding:0 1.5em}
.legend .bar img{display:block;width:400px;max-width:100%;height:14px}
.ticks{position:relative;height:1.3em}
.ticks span{position:absolute;transform:translateX(-50%);white-space:nowrap}
.scene{background:#fff;border:1px solid #ccc;border-left:6px solid #080;padding:.4em .75em;margin:.75em 0}
.scene.WARN{border-left-color:#b60}.scene.FAIL{border-left-color:#c00}
.scene header{display:flex;flex-wrap:wrap;gap:.2em 1em;align-items:baseline}
.scene h2{font-size:1.2em;margin:0}
.panels{display:flex;flex-wrap:wrap;gap:.75em;margin-top:.4em}
figure{margin:0;flex:0 1 288px;min-width:0}
figure img{display:block;width:100%;height:auto}
figcaption{font-size:85%;color:#555}
.frame{position:relative}
.frame svg{position:absolute;left:0;top:0;width:100%;height:100%}
.frame rect{fill:transparent;stroke:#0ff;stroke-width:1.5px;vector-effect:non-scaling-stroke;pointer-events:all}
.flip .frame{cursor:pointer}
.flip .sse,.flip .showing-sse,.flip:hover .reference,.flip:hover .showing-reference,.flip.pinned .reference,.flip.pinned .showing-reference{display:none}
.flip:hover .sse,.flip.pinned .sse{display:block}
.flip:hover .showing-sse,.flip.pinned .showing-sse{display:inline}
.facts{flex:1 1 18em;min-width:0;font-size:92%}
.facts table{border-collapse:collapse}
.facts th{text-align:left;font-weight:normal;color:#555;padding-right:.6em;vertical-align:top;white-space:nowrap}
.facts p{margin:.3em 0}
.facts ol{padding-left:1.5em;margin:.2em 0}
.why{color:#555;font-size:90%}
.label{color:#555}
.note{color:#777;font-style:italic}
.command{display:flex;gap:.3em;align-items:flex-start;margin:.15em 0}
.command code{flex:1;min-width:0;background:#f0f0f0;padding:0 .3em;overflow-wrap:anywhere}
button.copy{font-size:80%;padding:0 .4em}
</style>
)";

// Filter by status and name, flip on click, copy a command; what hover does is CSS alone.
constexpr const char* script = R"(<script>
const filter = document.getElementById('filter');
const scenes = document.querySelectorAll('section.scene');
function applyFilter() {
  const statuses = new Set([...filter.querySelectorAll('input[name=status]:checked')].map(box => box.value));
  const name = document.getElementById('name-filter').value.trim().toLowerCase();
  let shown = 0;
  for (const scene of scenes) {
    scene.hidden = !(statuses.has(scene.dataset.status) && scene.dataset.name.toLowerCase().includes(name));
    shown += scene.hidden ? 0 : 1;
  }
  document.getElementById('shown').textContent = shown + ' of ' + scenes.length + ' scenes shown';
}
filter.addEventListener('input', applyFilter);
filter.addEventListener('submit', event => event.preventDefault());
document.addEventListener('click', event => {
  const flip = event.target.closest('.flip');
  if (flip) {
    flip.classList.toggle('pinned');
    return;
  }
  const button = event.target.closest('button.copy');
  if (!button) return;
  const code = button.previousElementSibling;
  const selectIt = () => {
    const range = document.createRange();
    range.selectNodeContents(code);
    getSelection().removeAllRanges();
    getSelection().addRange(range);
    button.textContent = 'selected';
  };
  if (navigator.clipboard) {
    navigator.clipboard.writeText(code.textContent).then(() => { button.textContent = 'copied'; }, selectIt);
  } else {
    selectIt();
  }
});
</script>
)";

}  // namespace

std::string percent(long count, long total) {
    return io::formatted("%.4f%%", 100.0 * static_cast<double>(count) / static_cast<double>(std::max(total, 1L)));
}

std::string report_page(std::vector<SceneReport> reports, const compare::HeatMapScale& scale, bool with_povray,
                        const std::string& thresholds_source, const std::string& judged) {
    std::stable_sort(reports.begin(), reports.end(), [](const SceneReport& a, const SceneReport& b) {
        return a.verdict != b.verdict ? a.verdict > b.verdict : a.name < b.name;
    });
    std::ostringstream html;
    html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
         << "<meta name=\"viewport\" content=\"width=device-width\"><title>twinray diff</title>\n"
         << style << "</head><body>\n<h1>twinray diff: reference&lt;double&gt; against " << html_escape(judged)
         << (with_povray ? " (and POV-Ray)" : "") << "</h1>\n"
         << summary(reports) << filter_controls(reports.size()) << legend(scale)
         << "<p class=\"label\">Images are compared as stored (clamped to [0, 1]); thresholds per scene: "
         << html_escape(thresholds_source) << ".</p>\n";
    for (const SceneReport& report : reports) {
        html << scene_section(report);
    }
    html << script << "</body></html>\n";
    return html.str();
}

}  // namespace twinray::cli
