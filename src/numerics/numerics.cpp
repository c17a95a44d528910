#include "numerics/numerics.h"

#include "scene/geometry.h"

#include "reference/tracer.h"
#include "sse/tracer.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <optional>

namespace twinray::numerics {

std::unique_ptr<AnyTracer> make_tracer(const scene::Scene& scene, TracerKind kind) {
    return tracing::make_tracer(tracer_name(kind), scene);
}

namespace {

void collect_leaves(const scene::Object& object, std::vector<const scene::Object*>& leaves) {
    if (const auto* csg = std::get_if<scene::Csg>(&object.shape)) {
        for (const scene::Object& child : csg->children) {
            collect_leaves(child, leaves);
        }
    } else {
        leaves.push_back(&object);
    }
}

// "plane", "sphere", ...: the scene format's name of the primitive's type.
const char* primitive_name(const scene::Object& primitive) {
    constexpr const char* names[] = {
        "plane", "sphere", "cylinder", "box", "transformed sphere", "transformed cylinder", "transformed box", "csg"};
    static_assert(std::size(names) == scene::PrimitiveTypes::size + 1);
    return names[primitive.shape.index()];
}

// The first t > 0 at which the line crosses the primitive's surface (+∞ if none): what the tracer should
// have found for a ray leaving that primitive.
long double first_crossing(const scene::Object& primitive, const Vec3d& origin, const Vec3d& direction) {
    ExactSpan span = exact_span(primitive, origin, direction);
    if (!span.valid) {
        return std::numeric_limits<long double>::infinity();
    }
    if (span.enter > 0) {
        return span.enter;
    }
    return span.exit > 0 ? span.exit : std::numeric_limits<long double>::infinity();
}

// A ray that left `node`'s surface re-hits it by error: the tracer finds that same primitive at less than
// half the distance where the exact line first crosses it (a grazing ray that legitimately crosses the
// primitive again close by is found where the exact line crosses it, and is not counted).
bool is_self_hit(const RayNode& node, const scene::Object& primitive, const Vec3d& origin, const Vec3d& direction,
                 const FirstHit& next) {
    return next.hit && next.leaf == node.leaf &&
           next.t < 0.5 * static_cast<double>(first_crossing(primitive, origin, direction));
}

}  // namespace

const char* tracer_name(TracerKind kind) {
    switch (kind) {
        case TracerKind::reference_double: return "reference";
        case TracerKind::reference_float: return "reference-float";
        case TracerKind::sse: return "sse";
    }
    return "?";
}

std::vector<ScaleCase> scale_cases() {
    std::vector<ScaleCase> cases;
    for (int exponent = -4; exponent <= 6; ++exponent) {
        cases.push_back({std::pow(10.0, exponent), 0.0, 1.0});
    }
    for (int exponent = 1; exponent <= 6; ++exponent) {
        cases.push_back({1.0, std::pow(10.0, exponent), 1.0});
    }
    for (int exponent = 2; exponent <= 4; ++exponent) {
        cases.push_back({1.0, 0.0, std::pow(10.0, exponent)});
    }
    return cases;
}

std::vector<double> footprint_shifts() {
    std::vector<double> shifts;
    for (int exponent = 0; exponent <= 7; ++exponent) {
        for (double mantissa : {1.0, 2.0, 5.0}) {
            shifts.push_back(mantissa * std::pow(10.0, exponent));
        }
    }
    return shifts;
}

scene::Scene transformed(const scene::Scene& scene, double scale, double shift, double camera_distance) {
    scene::Scene result = scene;
    for (int axis = 0; axis < 3; ++axis) {
        result.camera.eye[axis] =
            scene.camera.look_at[axis] + camera_distance * (scene.camera.eye[axis] - scene.camera.look_at[axis]);
    }
    double half_angle = scene.camera.fov_deg * std::numbers::pi / 360;
    result.camera.fov_deg = std::atan(std::tan(half_angle) / camera_distance) * 360 / std::numbers::pi;
    return scene::moved(result, scale, {shift, shift, shift});
}

scene::Scene rounded_to_float(const scene::Scene& scene) {
    scene::Scene result = scene;
    for (scene::Object& object : result.objects) {
        scene::round_to_float(object);
    }
    return result;
}

scene::Scene held_geometry(const scene::Scene& scene, TracerKind kind) {
    switch (kind) {
        case TracerKind::reference_double: return scene;
        case TracerKind::reference_float: return rounded_to_float(scene);
        case TracerKind::sse: {
            scene::Vec3 origin = sse::origin_of(scene);
            return scene::moved(rounded_to_float(scene::moved(scene, 1, -origin)), 1, origin);
        }
    }
    return scene;
}

std::vector<const scene::Object*> leaf_objects(const scene::Scene& scene) {
    std::vector<const scene::Object*> leaves;
    for (const scene::Object& object : scene.objects) {
        collect_leaves(object, leaves);
    }
    return leaves;
}

Measurement measure(const scene::Scene& scene, TracerKind kind, int grid, double size) {
    std::unique_ptr<AnyTracer> tracer = make_tracer(scene, kind);
    std::vector<const scene::Object*> leaves = leaf_objects(scene);
    scene::Scene held = held_geometry(scene, kind);
    std::vector<const scene::Object*> held_leaves = leaf_objects(held);
    Measurement m;
    for (int y = 0; y < grid; ++y) {
        for (int x = 0; x < grid; ++x) {
            RayTree tree;
            tracer->trace_primary(x, y, grid, grid, tree);
            ++m.rays;
            const RayNode& primary = tree.nodes.front();
            if (primary.hit) {
                ++m.hits;
                double error = static_cast<double>(distance_to_surface(*leaves[static_cast<std::size_t>(primary.leaf)],
                                                                       primary.point)) /
                               size;
                m.max_error = std::isfinite(error) ? std::max(m.max_error, error) : error;
            }
            for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
                const RayNode& node = tree.nodes[i];
                if (!node.hit) {
                    continue;
                }
                const scene::Object& primitive = *held_leaves[static_cast<std::size_t>(node.leaf)];
                for (const LightVisibility& light : node.lights) {
                    if (!light.faces_away) {
                        ++m.secondary;
                        FirstHit next = tracer->intersect(light.shadow_origin, light.shadow_direction);
                        m.acne += is_self_hit(node, primitive, light.shadow_origin, light.shadow_direction, next);
                    }
                }
                for (int child_index : tree.children(static_cast<int>(i))) {
                    const RayNode& child = tree.nodes[static_cast<std::size_t>(child_index)];
                    ++m.secondary;
                    FirstHit next{child.hit, child.leaf, child.t, child.point, child.normal};
                    m.acne += is_self_hit(node, primitive, child.origin, child.direction, next);
                    bool into_solid = child.kind == RayKind::refracted && node.entering;
                    m.leaks += into_solid && (!child.hit || child.entering);
                }
            }
        }
    }
    return m;
}

std::vector<FootprintRatio> footprint_ratios(const scene::Scene& scene, TracerKind kind, int width) {
    std::unique_ptr<AnyTracer> tracer = make_tracer(scene, kind);
    std::vector<const scene::Object*> leaves = leaf_objects(scene);
    int height = std::max(1, static_cast<int>(std::lround(static_cast<double>(width) * scene.height / scene.width)));
    double pixel_per_distance = 2 * std::tan(scene.camera.fov_deg * std::numbers::pi / 360) / width;
    std::map<std::string, double> worst;
    for (const scene::Object* leaf : leaves) {
        worst.emplace(primitive_name(*leaf), 0.0);
    }
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            FirstHit hit = tracer->primary_hit(x, y, width, height);
            if (!hit.hit) {
                continue;
            }
            const scene::Object& leaf = *leaves[static_cast<std::size_t>(hit.leaf)];
            double error = static_cast<double>(distance_to_surface(leaf, hit.point));
            double& ratio = worst[primitive_name(leaf)];
            double footprint_ratio = error / (hit.t * pixel_per_distance);
            ratio = std::isfinite(footprint_ratio) ? std::max(ratio, footprint_ratio) : footprint_ratio;
        }
    }
    std::vector<FootprintRatio> ratios;
    for (const auto& [primitive, ratio] : worst) {
        ratios.push_back({primitive, ratio});
    }
    return ratios;
}

}  // namespace twinray::numerics
