#include "cli/probe_json.h"

#include <array>
#include <cstddef>
#include <optional>

namespace twinray::cli::probe {
namespace {

Json to_json(const Vec3d& v) {
    return Json::array({v[0], v[1], v[2]});
}

// A mesh hit's triangle index and barycentrics.
void add_triangle(const scene::Scene& scene, const RayNode& node, Json& json) {
    if (std::optional<std::array<double, 3>> weights = barycentrics(scene, node)) {
        json["triangle"] = node.triangle;
        json["barycentrics"] = Json::array({(*weights)[0], (*weights)[1], (*weights)[2]});
    }
}

Json first_hit_json(const scene::Scene& scene, const RayTree& tree) {
    if (tree.nodes.empty() || !tree.nodes.front().hit) {
        return Json{{"hit", false}};
    }
    const RayNode& node = tree.nodes.front();
    Json json{{"hit", true},
              {"t", node.t},
              {"point", to_json(node.point)},
              {"normal", to_json(node.normal)},
              {"object", object_name(scene, node)},
              {"material", material_name(scene, node)},
              {"entering", node.entering}};
    add_triangle(scene, node, json);
    return json;
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
        json["object"] = object_name(scene, node);
        add_triangle(scene, node, json);
        json["material"] = material_name(scene, node);
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

Json tracer_json(const scene::Scene& scene, const TracedTree& traced) {
    Json nodes = Json::array();
    for (std::size_t i = 0; i < traced.tree.nodes.size(); ++i) {
        nodes.push_back(node_json(scene, traced.tree, static_cast<int>(i)));
    }
    Json dropped = Json::array();
    for (const DroppedRay& ray : traced.tree.dropped) {
        dropped.push_back({{"parent", ray.parent},
                           {"kind", ray_kind_name(ray.kind)},
                           {"depth", ray.depth},
                           {"weight", ray.weight},
                           {"bound", ray.bound},
                           {"reason", ray.for_budget ? "budget" : "cutoff"}});
    }
    return Json{{"tracer", traced.label},
                {"hit", first_hit_json(scene, traced.tree)},
                {"color", traced.tree.nodes.empty() ? Json() : to_json(traced.tree.nodes.front().total)},
                {"tree", nodes},
                {"dropped", dropped}};
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
        return node->hit ? Json(object_name(scene, *node)) : Json();
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

}  // namespace

Json report_json(const scene::Scene& scene, const std::string& scene_path, const Target& target,
                 const Findings& findings) {
    Json json{{"scene", scene_path}};
    if (target.is_pixel) {
        json["pixel"] = {target.x, target.y};
        json["image_size"] = {target.width, target.height};
    } else {
        json["ray"] = {{"origin", to_json(target.origin)}, {"direction", to_json(target.direction)}};
    }
    // Keyed like a divergence's "what" (a light's is "transmittance"); t: |dt|·|cos θ| over S.
    const DivergenceThresholds& limits = findings.limits;
    json["thresholds"] = {{"origin", limits.position},
                          {"direction", limits.angle},
                          {"t", limits.position},
                          {"normal", limits.angle},
                          {"transmittance", limits.transmittance},
                          {"local colour", limits.color},
                          {"total colour", limits.color}};
    json["reference"] = tracer_json(scene, findings.reference);
    // The judged tracer keeps the key "sse" whichever it is (--tracer); its "tracer" says which.
    json["sse"] = findings.judged ? tracer_json(scene, *findings.judged) : Json();
    if (!findings.judged) {
        json["sse_unavailable"] = findings.judged_note;
    }
    Json all = Json::array();
    if (findings.judged) {
        for (const Divergence& d : findings.divergences) {
            all.push_back(divergence_json(scene, d, findings.reference.tree, findings.judged->tree));
        }
    }
    json["divergence"] = findings.divergences.empty() ? Json() : all.front();
    json["divergences"] = all;
    if (findings.judged) {
        json["cause"] = {{"class", accuracy::cause_name(findings.cause.cause)},
                         {"what", findings.cause.what},
                         {"depth", findings.cause.depth},
                         {"deviation", findings.cause.deviation},
                         {"band", findings.cause.band}};
    }
    return json;
}

}  // namespace twinray::cli::probe
