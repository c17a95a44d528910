#include "cli/probe_command.h"

#include "cli/exit_codes.h"
#include "reference/tracer.h"
#include "render/ray_tree.h"
#include "scene/loader.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace twinray::cli {
namespace {

using Json = nlohmann::ordered_json;

struct ProbeArguments {
    std::string scene_path;
    std::string pixel;
    std::string ray;
    int width = 0;
    int height = 0;
    bool json = false;
};

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// What to probe: a pixel (its primary ray, as each tracer's render makes it) or a ray given by hand.
struct Target {
    bool is_pixel = false;
    int x = 0, y = 0;
    int width = 0, height = 0;  // of the image the pixel belongs to
    Vec3d origin{};
    Vec3d direction{};  // normalised
};

std::vector<std::string> split_commas(const std::string& text) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        std::size_t comma = text.find(',', start);
        parts.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (comma == std::string::npos) {
            return parts;
        }
        start = comma + 1;
    }
}

// The whole token must be the number (from_chars: no locale, no leading space; a leading '+' is allowed).
template <typename Number>
std::optional<Number> parse_number(std::string token) {
    if (!token.empty() && token.front() == '+') {
        token.erase(0, 1);
    }
    Number value{};
    const char* end = token.data() + token.size();
    auto [stop, error] = std::from_chars(token.data(), end, value);
    if (token.empty() || error != std::errc() || stop != end) {
        return std::nullopt;
    }
    return value;
}

void parse_pixel(const std::string& text, Target& target) {
    std::vector<std::string> parts = split_commas(text);
    std::optional<int> x = parts.size() == 2 ? parse_number<int>(parts[0]) : std::nullopt;
    std::optional<int> y = parts.size() == 2 ? parse_number<int>(parts[1]) : std::nullopt;
    if (!x || !y) {
        throw UsageError("--pixel wants X,Y: two integers, counted from 0 at the top-left; got \"" + text + "\"");
    }
    target.is_pixel = true;
    target.x = *x;
    target.y = *y;
}

void parse_ray(const std::string& text, Target& target) {
    std::vector<std::string> parts = split_commas(text);
    std::vector<double> values;
    for (const std::string& part : parts) {
        if (std::optional<double> value = parse_number<double>(part)) {
            values.push_back(*value);
        }
    }
    if (parts.size() != 6 || values.size() != 6) {
        throw UsageError("--ray wants ox,oy,oz,dx,dy,dz: six numbers, the origin then the direction; got \"" + text +
                         "\"");
    }
    for (double value : values) {
        if (!std::isfinite(value)) {
            throw UsageError("--ray: every component must be a finite number; got \"" + text + "\"");
        }
    }
    for (int axis = 0; axis < 3; ++axis) {
        if (std::fabs(values[static_cast<std::size_t>(axis)]) > FLT_MAX) {
            throw UsageError(
                "--ray: the origin is beyond single precision (|component| > 3.4e38), which the sse tracer uses");
        }
    }
    // Normalised after scaling by the largest component, so that neither tiny nor huge values overflow.
    double largest = std::max({std::fabs(values[3]), std::fabs(values[4]), std::fabs(values[5])});
    if (largest == 0) {
        throw UsageError("--ray: the direction (dx,dy,dz) must not be zero");
    }
    Vec3d d{values[3] / largest, values[4] / largest, values[5] / largest};
    double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    target.origin = {values[0], values[1], values[2]};
    target.direction = {d[0] / length, d[1] / length, d[2] / length};
}

Target parse_target(const ProbeArguments& arguments) {
    Target target;
    if (arguments.pixel.empty() == arguments.ray.empty()) {
        throw UsageError("give exactly one of --pixel X,Y or --ray ox,oy,oz,dx,dy,dz");
    }
    if (!arguments.pixel.empty()) {
        parse_pixel(arguments.pixel, target);
    } else {
        if (arguments.width != 0 || arguments.height != 0) {
            throw UsageError("--width and --height size the image of --pixel; they mean nothing with --ray");
        }
        parse_ray(arguments.ray, target);
    }
    return target;
}

// One tracer's tree of the probed ray.
struct Probe {
    std::string tracer;  // "reference" or "sse", the JSON key
    std::string label;   // for people
    RayTree tree;
};

Probe probe_reference(const scene::Scene& scene, const Target& target) {
    using R = reference::Ray<double>;
    reference::Tracer<double> tracer(scene);
    R ray = target.is_pixel ? tracer.primary_ray(target.x, target.y, target.width, target.height)
                            : R{{target.origin[0], target.origin[1], target.origin[2]},
                                {target.direction[0], target.direction[1], target.direction[2]}};
    Probe probe{"reference", "reference<double>", {}};
    tracer.trace(ray, 1, nullptr, &probe.tree);
    return probe;
}

// The ray given by hand reaches the sse tracer rounded to float, its direction normalised in double.
Probe probe_sse(const scene::Scene& scene, const Target& target) {
    sse::Tracer tracer(scene);
    auto f = [](double v) { return static_cast<float>(v); };
    sse::Ray ray = target.is_pixel ? tracer.primary_ray(target.x, target.y, target.width, target.height)
                                   : sse::Ray{{f(target.origin[0]), f(target.origin[1]), f(target.origin[2])},
                                              {f(target.direction[0]), f(target.direction[1]), f(target.direction[2])}};
    Probe probe{"sse", "sse (float, SSE4.1)", {}};
    tracer.trace(ray, 1, nullptr, &probe.tree);
    return probe;
}

// ---------------------------------------------------------------------------------------------------
// Formatting shared by text and JSON

std::string format(const char* pattern, double value) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, pattern, value);
    return buffer;
}

std::string format_vector(const Vec3d& v, const char* component = "%.7g") {
    return "(" + format(component, v[0]) + ", " + format(component, v[1]) + ", " + format(component, v[2]) + ")";
}

std::string object_name(const scene::Scene& scene, int leaf) {
    if (leaf < 0 || static_cast<std::size_t>(leaf) >= scene.leaf_paths.size()) {
        return "leaf " + std::to_string(leaf) + " (unknown)";
    }
    return scene.leaf_paths[static_cast<std::size_t>(leaf)];
}

std::string material_name(const scene::Scene& scene, int leaf) {
    if (leaf < 0 || static_cast<std::size_t>(leaf) >= scene.leaf_materials.size()) {
        return "?";
    }
    return scene.material_names[static_cast<std::size_t>(scene.leaf_materials[static_cast<std::size_t>(leaf)])];
}

std::string describe_light(const LightVisibility& light) {
    std::string n_dot_l = "N.L " + format("%.4g", light.n_dot_l);
    if (light.faces_away) {
        return "faces away (" + n_dot_l + ")";
    }
    std::string state = light.transmittance == 0 ? "blocked" : light.transmittance == 1 ? "visible" : "partly";
    return state + ", " + format("%.6g", light.transmittance) + " (" + n_dot_l + ")";
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
        return object_name(scene, node.leaf) + " (" + material_name(scene, node.leaf) + "), " +
               (node.entering ? "entering" : "leaving");
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
        return format("%.9g", node.t);
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

const RayNode* node_at(const RayTree* tree, int index) {
    return tree != nullptr && index >= 0 ? &tree->nodes[static_cast<std::size_t>(index)] : nullptr;
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
    return format("%.3g", d.amount) + unit + " > " + format("%.3g", d.threshold);
}

std::string pad(std::string text, std::size_t width) {
    if (text.size() < width) {
        text.append(width - text.size(), ' ');
    }
    return text + "  ";
}

void print_text(const scene::Scene& scene, const std::string& scene_path, const Target& target, const Probe& reference,
                const Probe* sse, const std::string& sse_note, const std::vector<Divergence>& divergences,
                const DivergenceThresholds& limits) {
    if (target.is_pixel) {
        std::printf("probe: %s, pixel %d,%d of %d x %d\n", scene_path.c_str(), target.x, target.y, target.width,
                    target.height);
    } else {
        std::printf("probe: %s, ray from %s towards %s (normalised)\n", scene_path.c_str(),
                    format_vector(target.origin, "%.9g").c_str(), format_vector(target.direction, "%.9g").c_str());
    }
    std::printf(
        "divergence: t across the surface (|dt| |cos|) %g of S = |origin| + t_parent + t; normal and direction\n"
        "  %g rad; shadow transmittance %g; colour %.4f (1/255) in a channel; any change of hit or miss, object,\n"
        "  entering, a light facing away or blocked, or a ray traced by one tracer only (docs/probe.md)\n",
        limits.position, limits.angle, limits.transmittance, limits.color);
    if (sse == nullptr) {
        std::printf("note: %s; showing the reference's tree only\n", sse_note.c_str());
    }
    // Divergences by (reference node, sse node, row), the first one apart.
    std::map<std::pair<std::pair<int, int>, std::string>, std::size_t> marks;
    for (std::size_t k = 0; k < divergences.size(); ++k) {
        marks.emplace(
            std::make_pair(std::make_pair(divergences[k].first, divergences[k].second), row_of(divergences[k].what)),
            k);
    }
    constexpr std::size_t label_width = 14;
    constexpr std::size_t column_width = 46;
    std::printf("\n%s%s%s\n", pad("", label_width).c_str(), pad(reference.label, column_width).c_str(),
                sse != nullptr ? sse->label.c_str() : "");
    std::size_t light_count = scene.lights.size();
    for (const AlignedRay& ray : align(reference.tree, sse != nullptr ? &sse->tree : nullptr)) {
        const RayNode* p = node_at(&reference.tree, ray.first);
        const RayNode* q = node_at(sse != nullptr ? &sse->tree : nullptr, ray.second);
        const RayNode& any = p != nullptr ? *p : *q;
        std::string indices = "reference #" + (p != nullptr ? std::to_string(ray.first) : std::string("-"));
        if (sse != nullptr) {
            indices += ", sse #" + (q != nullptr ? std::to_string(ray.second) : std::string("-"));
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
            if (sse != nullptr) {
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
            std::string line = pad(row, label_width) + (sse != nullptr ? pad(left, column_width) + right : left);
            std::printf("%s%s\n", line.c_str(), mark(row).c_str());
        }
    }
    std::printf("\n");
    if (sse == nullptr) {
        return;
    }
    if (divergences.empty()) {
        std::printf("no divergence: the two trees agree within the thresholds\n");
        return;
    }
    const Divergence& first = divergences.front();
    const RayNode* p = node_at(&reference.tree, first.first);
    const RayNode* q = node_at(&sse->tree, first.second);
    const RayNode& any = p != nullptr ? *p : *q;
    std::printf("first divergence: depth %d, %s ray (reference #%d, sse #%d): %s\n", any.depth, ray_kind_name(any.kind),
                first.first, first.second, first.what.c_str());
    if (first.what == "ray") {
        std::printf("  traced by %s only\n", p != nullptr ? "the reference" : "sse");
    } else {
        std::string row = row_of(first.what);
        std::printf("  reference: %s\n  sse:       %s\n", row_text(scene, *p, row).c_str(),
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

// ---------------------------------------------------------------------------------------------------
// JSON

Json to_json(const Vec3d& v) {
    return Json::array({v[0], v[1], v[2]});
}

Json first_hit_json(const scene::Scene& scene, const RayTree& tree) {
    if (tree.nodes.empty() || !tree.nodes.front().hit) {
        return Json{{"hit", false}};
    }
    const RayNode& node = tree.nodes.front();
    return Json{{"hit", true},
                {"t", node.t},
                {"point", to_json(node.point)},
                {"normal", to_json(node.normal)},
                {"object", object_name(scene, node.leaf)},
                {"material", material_name(scene, node.leaf)},
                {"entering", node.entering}};
}

Json light_json(const LightVisibility& light, std::size_t index) {
    Json json{{"light", "lights[" + std::to_string(index) + "]"},
              {"n_dot_l", light.n_dot_l},
              {"faces_away", light.faces_away}};
    if (!light.faces_away) {
        json["transmittance"] = light.transmittance;
        json["shadow_origin"] = to_json(light.shadow_origin);
        json["shadow_direction"] = to_json(light.shadow_direction);
    }
    return json;
}

Json node_json(const scene::Scene& scene, const RayTree& tree, int index) {
    const RayNode& node = tree.nodes[static_cast<std::size_t>(index)];
    Json json{{"index", index},        {"kind", ray_kind_name(node.kind)}, {"depth", node.depth},
              {"parent", node.parent}, {"origin", to_json(node.origin)},   {"direction", to_json(node.direction)},
              {"hit", node.hit}};
    if (node.hit) {
        json["object"] = object_name(scene, node.leaf);
        json["material"] = material_name(scene, node.leaf);
        json["t"] = node.t;
        json["point"] = to_json(node.point);
        json["normal"] = to_json(node.normal);
        json["entering"] = node.entering;
        Json lights = Json::array();
        for (std::size_t l = 0; l < node.lights.size(); ++l) {
            lights.push_back(light_json(node.lights[l], l));
        }
        json["lights"] = lights;
    }
    json["local"] = to_json(node.local);
    json["total"] = to_json(node.total);
    Json children = Json::array();
    for (int child : tree.children(index)) {
        children.push_back(child);
    }
    json["children"] = children;
    return json;
}

Json tracer_json(const scene::Scene& scene, const Probe& probe) {
    Json nodes = Json::array();
    for (std::size_t i = 0; i < probe.tree.nodes.size(); ++i) {
        nodes.push_back(node_json(scene, probe.tree, static_cast<int>(i)));
    }
    return Json{{"tracer", probe.label},
                {"hit", first_hit_json(scene, probe.tree)},
                {"color", probe.tree.nodes.empty() ? Json() : to_json(probe.tree.nodes.front().total)},
                {"tree", nodes}};
}

// The value a divergence is about, for one node.
Json divergence_value(const scene::Scene& scene, const RayNode* node, const std::string& what) {
    if (node == nullptr) {
        return nullptr;
    }
    if (what == "origin")
        return to_json(node->origin);
    if (what == "direction")
        return to_json(node->direction);
    if (what == "hit")
        return node->hit;
    if (what == "object")
        return node->hit ? Json(object_name(scene, node->leaf)) : Json();
    if (what == "entering")
        return node->entering;
    if (what == "t")
        return node->t;
    if (what == "normal")
        return to_json(node->normal);
    if (what == "local colour")
        return to_json(node->local);
    if (what == "total colour")
        return to_json(node->total);
    if (what == "ray")
        return ray_kind_name(node->kind);
    if (what.rfind("lights[", 0) == 0) {
        std::size_t light = static_cast<std::size_t>(std::stoi(what.substr(7)));
        return light < node->lights.size() ? light_json(node->lights[light], light) : Json();
    }
    return nullptr;
}

Json divergence_json(const scene::Scene& scene, const Divergence& d, const RayTree& a, const RayTree& b) {
    const RayNode* p = node_at(&a, d.first);
    const RayNode* q = node_at(&b, d.second);
    const RayNode& any = p != nullptr ? *p : *q;
    Json json{{"reference_node", d.first},
              {"sse_node", d.second},
              {"depth", any.depth},
              {"kind", ray_kind_name(any.kind)},
              {"what", d.what}};
    if (d.threshold > 0) {
        json["amount"] = d.amount;
        json["threshold"] = d.threshold;
    }
    json["reference"] = divergence_value(scene, p, d.what);
    json["sse"] = divergence_value(scene, q, d.what);
    return json;
}

void print_json(const scene::Scene& scene, const std::string& scene_path, const Target& target, const Probe& reference,
                const Probe* sse, const std::string& sse_note, const std::vector<Divergence>& divergences,
                const DivergenceThresholds& limits) {
    Json json{{"scene", scene_path}};
    if (target.is_pixel) {
        json["pixel"] = {target.x, target.y};
        json["image_size"] = {target.width, target.height};
    } else {
        json["ray"] = {{"origin", to_json(target.origin)}, {"direction", to_json(target.direction)}};
    }
    // Keyed like a divergence's "what" (a light's is "transmittance"); t: |dt|·|cos θ| over S.
    json["thresholds"] = {{"origin", limits.position},
                          {"direction", limits.angle},
                          {"t", limits.position},
                          {"normal", limits.angle},
                          {"transmittance", limits.transmittance},
                          {"local colour", limits.color},
                          {"total colour", limits.color}};
    json["reference"] = tracer_json(scene, reference);
    json["sse"] = sse != nullptr ? tracer_json(scene, *sse) : Json();
    if (sse == nullptr) {
        json["sse_unavailable"] = sse_note;
    }
    Json all = Json::array();
    if (sse != nullptr) {
        for (const Divergence& d : divergences) {
            all.push_back(divergence_json(scene, d, reference.tree, sse->tree));
        }
    }
    json["divergence"] = divergences.empty() ? Json() : all.front();
    json["divergences"] = all;
    std::cout << json.dump(2) << "\n";
}

int run_probe(const ProbeArguments& arguments) {
    Target target;
    try {
        target = parse_target(arguments);
    } catch (const UsageError& error) {
        std::cerr << "twinray probe: " << error.what() << "\n";
        return exit_usage;
    }
    scene::Scene scene;
    try {
        scene = scene::load_scene(arguments.scene_path);
    } catch (const scene::SceneError& error) {
        std::cerr << "twinray probe: invalid scene: " << error.what() << "\n";
        return exit_invalid_scene;
    }
    if (target.is_pixel) {
        try {
            scene::ImageSize size = scene::resolve_image_size(scene, arguments.width, arguments.height);
            target.width = size.width;
            target.height = size.height;
        } catch (const std::invalid_argument& error) {
            std::cerr << "twinray probe: " << error.what() << "\n";
            return exit_usage;
        }
        if (target.x < 0 || target.x >= target.width || target.y < 0 || target.y >= target.height) {
            std::cerr << "twinray probe: pixel " << target.x << "," << target.y << " is outside the " << target.width
                      << " x " << target.height << " image (x from 0 to " << target.width - 1 << ", y from 0 to "
                      << target.height - 1 << ")\n";
            return exit_usage;
        }
    }
    Probe reference = probe_reference(scene, target);
    std::optional<Probe> sse;
    std::string sse_note;
    if (sse::cpu_supports_sse41()) {
        sse = probe_sse(scene, target);
    } else {
        sse_note = "sse not run: " + sse::missing_sse41_message();
    }
    DivergenceThresholds limits;
    std::vector<Divergence> divergences =
        sse ? find_divergences(reference.tree, sse->tree, limits) : std::vector<Divergence>{};
    const Probe* other = sse ? &*sse : nullptr;
    if (arguments.json) {
        print_json(scene, arguments.scene_path, target, reference, other, sse_note, divergences, limits);
    } else {
        print_text(scene, arguments.scene_path, target, reference, other, sse_note, divergences, limits);
    }
    return exit_success;
}

}  // namespace

void add_probe_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<ProbeArguments>();
    CLI::App* command = app.add_subcommand(
        "probe",
        "Trace one pixel (or ray) with both tracers and print the two ray trees side by side, marking "
        "where they first diverge");
    command->add_option("scene", arguments->scene_path, "Scene file (twinray-scene/1 JSON)")->required();
    command->add_option("--pixel", arguments->pixel,
                        "X,Y: the pixel's primary ray, as render traces it (0,0 top-left)");
    command->add_option("--ray", arguments->ray,
                        "ox,oy,oz,dx,dy,dz: a ray given by hand; the direction is normalised, so t is a distance");
    command
        ->add_option("--width", arguments->width,
                     "Image width for --pixel, as render; alone, the height follows the scene's aspect ratio")
        ->check(CLI::Range(1, 16384));
    command
        ->add_option("--height", arguments->height,
                     "Image height for --pixel, as render; alone, the width follows the scene's aspect ratio")
        ->check(CLI::Range(1, 16384));
    command->add_flag("--json", arguments->json, "Print one JSON object (docs/probe.md) instead of the table");
    command->callback([arguments, &run] { run = [arguments] { return run_probe(*arguments); }; });
}

}  // namespace twinray::cli
