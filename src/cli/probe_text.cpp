#include "cli/probe_text.h"
#include "io/formatted.h"

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <map>
#include <utility>
#include <vector>

namespace twinray::cli::probe {
namespace {

std::string format_vector(const Vec3d& v, const char* component = "%.7g") {
    return "(" + io::formatted(component, v[0]) + ", " + io::formatted(component, v[1]) + ", " +
           io::formatted(component, v[2]) + ")";
}

std::string describe_light(const LightVisibility& light) {
    std::string n_dot_l = "N.L " + io::formatted("%.4g", light.n_dot_l);
    if (light.faces_away) {
        return "faces away (" + n_dot_l + ")";
    }
    std::string state = light.transmittance == 0 ? "blocked" : light.transmittance == 1 ? "visible" : "partly";
    return state + ", " + io::formatted("%.6g", light.transmittance) + " (" + n_dot_l + ")";
}

// ---------------------------------------------------------------------------------------------------
// Side by side: the two trees aligned ray by ray (children matched by kind), one row per field.

struct AlignedRay {
    int first = -1;  // node in the reference tree, -1: that tracer did not trace this ray
    int second = -1;
};

int child_of_kind(const RayTree& tree, int node, RayKind kind) {
    if (node < 0) {
        return -1;
    }
    for (int child : tree.children(node)) {
        if (tree.nodes[static_cast<std::size_t>(child)].kind == kind) {
            return child;
        }
    }
    return -1;
}

void align(const RayTree& a, const RayTree& b, int i, int j, std::vector<AlignedRay>& rays) {
    rays.push_back({i, j});
    for (RayKind kind : {RayKind::refracted, RayKind::reflected}) {
        int x = child_of_kind(a, i, kind);
        int y = child_of_kind(b, j, kind);
        if (x >= 0 || y >= 0) {
            align(a, b, x, y, rays);
        }
    }
}

std::vector<AlignedRay> align(const RayTree& a, const RayTree* b) {
    std::vector<AlignedRay> rays;
    static const RayTree empty;
    const RayTree& other = b != nullptr ? *b : empty;
    if (!a.nodes.empty() || !other.nodes.empty()) {
        align(a, other, a.nodes.empty() ? -1 : 0, other.nodes.empty() ? -1 : 0, rays);
    }
    return rays;
}

// The row a divergence is shown on.
std::string row_of(const std::string& what) {
    if (what == "object" || what == "entering") {
        return "hit";
    }
    return what;
}

// The value of one row for one node, as text ("" where the node has no such field).
std::string row_text(const scene::Scene& scene, const RayNode& node, const std::string& row) {
    if (row == "origin")
        return format_vector(node.origin);
    if (row == "direction")
        return format_vector(node.direction);
    if (row == "hit") {
        if (!node.hit)
            return "miss (background)";
        return object_name(scene, node) + (node.triangle >= 0 ? " triangle " + std::to_string(node.triangle) : "") +
               " (" + material_name(scene, node) + "), " + (node.entering ? "entering" : "leaving");
    }
    if (row == "local colour")
        return format_vector(node.local, "%.6f");
    if (row == "total colour")
        return format_vector(node.total, "%.6f");
    if (row == "ray")
        return std::string(ray_kind_name(node.kind)) + " ray, depth " + std::to_string(node.depth);
    if (!node.hit)
        return "";
    if (row == "t")
        return io::formatted("%.9g", node.t);
    if (row == "point")
        return format_vector(node.point);
    if (row == "normal")
        return format_vector(node.normal);
    if (row.rfind("lights[", 0) == 0) {
        std::size_t light = static_cast<std::size_t>(std::stoi(row.substr(7)));
        return light < node.lights.size() ? describe_light(node.lights[light]) : "";
    }
    return "";
}

std::vector<std::string> rows_of(std::size_t light_count) {
    std::vector<std::string> rows = {"origin", "direction", "hit", "t", "point", "normal"};
    for (std::size_t l = 0; l < light_count; ++l) {
        rows.push_back("lights[" + std::to_string(l) + "]");
    }
    rows.push_back("local colour");
    rows.push_back("total colour");
    return rows;
}

std::string amount_text(const Divergence& d) {
    if (d.threshold == 0) {
        return "";
    }
    std::string unit = d.what == "t"                                 ? " of S, across the surface (|dt| |cos|)"
                       : d.what == "origin"                          ? " of S"
                       : d.what == "direction" || d.what == "normal" ? " rad"
                       : d.what.find("colour") != std::string::npos  ? " in a channel"
                                                                     : "";
    return io::formatted("%.3g", d.amount) + unit + " > " + io::formatted("%.3g", d.threshold);
}

std::string pad(std::string text, std::size_t width) {
    if (text.size() < width) {
        text.append(width - text.size(), ' ');
    }
    return text + "  ";
}

void print_heading(const std::string& scene_path, const Target& target, const Findings& findings) {
    if (target.is_pixel) {
        std::printf("probe: %s, pixel %d,%d of %d x %d\n", scene_path.c_str(), target.x, target.y, target.width,
                    target.height);
    } else {
        std::printf("probe: %s, ray from %s towards %s (normalised)\n", scene_path.c_str(),
                    format_vector(target.origin, "%.9g").c_str(), format_vector(target.direction, "%.9g").c_str());
    }
    const DivergenceThresholds& limits = findings.limits;
    std::printf(
        "divergence: t across the surface (|dt| |cos|) %g of S = |origin| + t_parent + t; normal and direction\n"
        "  %g rad; shadow transmittance %g; colour %.4f (1/255) in a channel; any change of hit or miss, object,\n"
        "  entering, a light facing away or blocked, or a ray traced by one tracer only (docs/probe.md)\n",
        limits.position, limits.angle, limits.transmittance, limits.color);
    if (!findings.judged) {
        std::printf("note: %s; showing the reference's tree only\n", findings.judged_note.c_str());
    }
}

// Every ray of both trees, aligned, one row per field; the divergences marked on their rows.
void print_trees(const scene::Scene& scene, const Findings& findings) {
    const TracedTree& reference = findings.reference;
    const TracedTree* judged = findings.judged ? &*findings.judged : nullptr;
    const std::vector<Divergence>& divergences = findings.divergences;
    // Divergences by (reference node, judged node, row), the first one apart.
    std::map<std::pair<std::pair<int, int>, std::string>, std::size_t> marks;
    for (std::size_t k = 0; k < divergences.size(); ++k) {
        marks.emplace(
            std::make_pair(std::make_pair(divergences[k].first, divergences[k].second), row_of(divergences[k].what)),
            k);
    }
    constexpr std::size_t label_width = 14;
    constexpr std::size_t column_width = 46;
    std::printf("\n%s%s%s\n", pad("", label_width).c_str(), pad(reference.label, column_width).c_str(),
                judged != nullptr ? judged->label.c_str() : "");
    std::size_t light_count = scene.lights.size();
    for (const AlignedRay& ray : align(reference.tree, judged != nullptr ? &judged->tree : nullptr)) {
        const RayNode* p = node_at(&reference.tree, ray.first);
        const RayNode* q = node_at(judged != nullptr ? &judged->tree : nullptr, ray.second);
        const RayNode& any = p != nullptr ? *p : *q;
        std::string indices = "reference #" + (p != nullptr ? std::to_string(ray.first) : std::string("-"));
        if (judged != nullptr) {
            indices += ", " + judged->name + " #" + (q != nullptr ? std::to_string(ray.second) : std::string("-"));
        }
        std::string title = std::string(static_cast<std::size_t>(2 * (any.depth - 1)), ' ') + "-- depth " +
                            std::to_string(any.depth) + ": " + ray_kind_name(any.kind) + " ray (" + indices + ")";
        auto mark = [&](const std::string& row) -> std::string {
            auto found = marks.find({{ray.first, ray.second}, row});
            if (found == marks.end()) {
                return "";
            }
            return found->second == 0 ? "  <== FIRST DIVERGENCE" : "  <-- differs";
        };
        std::printf("\n%s%s\n", title.c_str(), mark("ray").c_str());
        if (p == nullptr || q == nullptr) {
            if (judged != nullptr) {
                std::printf("%s%s%s\n", pad("", label_width).c_str(),
                            pad(p != nullptr ? "" : "(not traced)", column_width).c_str(),
                            q != nullptr ? "" : "(not traced)");
            }
        }
        for (const std::string& row : rows_of(light_count)) {
            std::string left = p != nullptr ? row_text(scene, *p, row) : "";
            std::string right = q != nullptr ? row_text(scene, *q, row) : "";
            if (left.empty() && right.empty()) {
                continue;
            }
            std::string line = pad(row, label_width) + (judged != nullptr ? pad(left, column_width) + right : left);
            std::printf("%s%s\n", line.c_str(), mark(row).c_str());
        }
    }
    std::printf("\n");
}

// The verdict: no divergence, or the first one with both values and by how much.
void print_verdict(const scene::Scene& scene, const Findings& findings) {
    const std::vector<Divergence>& divergences = findings.divergences;
    if (divergences.empty()) {
        std::printf("no divergence: the two trees agree within the thresholds\n");
        return;
    }
    const Divergence& first = divergences.front();
    const RayNode* p = node_at(&findings.reference.tree, first.first);
    const std::string& name = findings.judged->name;
    const RayNode* q = node_at(&findings.judged->tree, first.second);
    const RayNode& any = p != nullptr ? *p : *q;
    std::printf("first divergence: depth %d, %s ray (reference #%d, %s #%d): %s\n", any.depth, ray_kind_name(any.kind),
                first.first, name.c_str(), first.second, first.what.c_str());
    if (first.what == "ray") {
        std::printf("  traced by %s only\n", p != nullptr ? "the reference" : name.c_str());
    } else {
        std::string row = row_of(first.what);
        std::printf("  reference: %s\n  %s %s\n", row_text(scene, *p, row).c_str(), pad(name + ":", 10).c_str(),
                    row_text(scene, *q, row).c_str());
        if (std::string amount = amount_text(first); !amount.empty()) {
            std::printf("  by %s\n", amount.c_str());
        }
    }
    if (divergences.size() > 1) {
        std::printf("%zu further difference%s marked \"<-- differs\" above\n", divergences.size() - 1,
                    divergences.size() == 2 ? "" : "s");
    }
}

// The secondary rays the depth control left out of one tree (scene/depth_control.h), the largest first.
void print_dropped(const TracedTree& traced) {
    const std::vector<DroppedRay>& dropped = traced.tree.dropped;
    if (dropped.empty()) {
        return;
    }
    double bound = 0;
    bool for_budget = false;
    for (const DroppedRay& ray : dropped) {
        bound += ray.bound;
        for_budget = for_budget || ray.for_budget;
    }
    std::printf("left out by %s: %zu secondary ray%s, which could have added at most %.3g per channel%s\n",
                traced.label.c_str(), dropped.size(), dropped.size() == 1 ? "" : "s", bound,
                for_budget ? "; the ray budget ran out" : "");
    std::vector<DroppedRay> largest = dropped;
    std::stable_sort(largest.begin(), largest.end(),
                     [](const DroppedRay& a, const DroppedRay& b) { return a.bound > b.bound; });
    constexpr std::size_t shown = 8;
    for (std::size_t i = 0; i < std::min(shown, largest.size()); ++i) {
        const DroppedRay& ray = largest[i];
        std::printf("  depth %d %s ray of #%d: weight %.3g, at most %.3g (%s)\n", ray.depth, ray_kind_name(ray.kind),
                    ray.parent, ray.weight, ray.bound, ray.for_budget ? "budget" : "cutoff");
    }
    if (largest.size() > shown) {
        std::printf("  ... and %zu more\n", largest.size() - shown);
    }
}

// Why the trees differ (accuracy/attribution.h), the ray's deviation and its band also in units u of the judged
// tracer's roundoff (2⁻²⁴ for float).
void print_cause(const accuracy::PixelCause& cause, double unit_roundoff) {
    std::printf("why: %s", accuracy::cause_name(cause.cause));
    if (!cause.what.empty()) {
        std::printf(" (%s", cause.what.c_str());
        if (cause.depth > 0) {
            std::printf(" at depth %d: the ray is %.2g rad = %.0f u off the reference's, band %.2g rad = %.0f u",
                        cause.depth, cause.deviation, cause.deviation / unit_roundoff, cause.band,
                        cause.band / unit_roundoff);
        }
        std::printf(")");
    }
    std::printf("; docs/conformance.md, \"Why a pixel differs\"\n");
}

}  // namespace

void print_text(const scene::Scene& scene, const std::string& scene_path, const Target& target,
                const Findings& findings) {
    print_heading(scene_path, target, findings);
    print_trees(scene, findings);
    print_dropped(findings.reference);
    if (findings.judged) {
        print_dropped(*findings.judged);
        print_verdict(scene, findings);
        print_cause(findings.cause, findings.judged->unit_roundoff);
    }
}

}  // namespace twinray::cli::probe
