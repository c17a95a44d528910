#include "numerics/numerics.h"

#include "reference/tracer.h"
#include "sse/tracer.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <optional>

namespace twinray::numerics {
namespace {

using Real = long double;

struct Point {
    Real x, y, z;
};

Point to_point(const scene::Vec3& v) {
    return {v[0], v[1], v[2]};
}
Point operator-(Point a, Point b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
Point operator*(Real s, Point a) {
    return {s * a.x, s * a.y, s * a.z};
}
Real dot(Point a, Point b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
Real length(Point a) {
    return std::sqrt(dot(a, a));
}

// A cylinder's base, unit axis and height, in long double.
struct CylinderFrame {
    Point base, axis;
    Real height;
};
CylinderFrame frame_of(const scene::Cylinder& cylinder) {
    Point base = to_point(cylinder.base);
    Point along = to_point(cylinder.cap) - base;
    Real height = length(along);
    return {base, (1 / height) * along, height};
}

template <typename V>
Vec3d to_vec3d(const V& v) {
    return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}

template <typename H>
FirstHit first_hit(const std::optional<H>& hit) {
    if (!hit) {
        return {};
    }
    return {true, hit->leaf, static_cast<double>(hit->t), to_vec3d(hit->point), to_vec3d(hit->normal)};
}

// Either tracer behind AnyTracer: `Scalar` is its precision, `Ray` and `Vec` its own types.
template <typename Tracer, typename Ray, typename Vec, typename Scalar>
class TracerAdapter final : public AnyTracer {
public:
    explicit TracerAdapter(const scene::Scene& scene) : tracer_(scene) {}
    void trace_primary(int x, int y, int width, int height, RayTree& tree) const override {
        tracer_.trace(tracer_.primary_ray(x, y, width, height), 1, nullptr, &tree);
    }
    FirstHit primary_hit(int x, int y, int width, int height) const override {
        return first_hit(tracer_.intersect(tracer_.primary_ray(x, y, width, height)));
    }
    FirstHit intersect(const Vec3d& o, const Vec3d& d) const override {
        Vec origin{static_cast<Scalar>(o[0]), static_cast<Scalar>(o[1]), static_cast<Scalar>(o[2])};
        Vec direction{static_cast<Scalar>(d[0]), static_cast<Scalar>(d[1]), static_cast<Scalar>(d[2])};
        return first_hit(tracer_.intersect(Ray{origin, direction}));
    }

private:
    Tracer tracer_;
};

template <typename T>
using ReferenceTracer = TracerAdapter<reference::Tracer<T>, reference::Ray<T>, reference::Vec3<T>, T>;
using SseTracer = TracerAdapter<sse::Tracer, sse::Ray, sse::Vec3, float>;

}  // namespace

std::unique_ptr<AnyTracer> make_tracer(const scene::Scene& scene, TracerKind kind) {
    switch (kind) {
        case TracerKind::reference_double: return std::make_unique<ReferenceTracer<double>>(scene);
        case TracerKind::reference_float: return std::make_unique<ReferenceTracer<float>>(scene);
        case TracerKind::sse: return std::make_unique<SseTracer>(scene);
    }
    return nullptr;
}

namespace {

scene::Vec3 moved(const scene::Vec3& p, double scale, double shift) {
    return {p[0] * scale + shift, p[1] * scale + shift, p[2] * scale + shift};
}

void transform_object(scene::Object& object, double scale, double shift) {
    std::visit(
        [&](auto& shape) {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (std::is_same_v<S, scene::Plane>) {
                shape.offset = shape.offset * scale + shift * (shape.normal[0] + shape.normal[1] + shape.normal[2]);
            } else if constexpr (std::is_same_v<S, scene::Sphere>) {
                shape.center = moved(shape.center, scale, shift);
                shape.radius *= scale;
            } else if constexpr (std::is_same_v<S, scene::Cylinder>) {
                shape.base = moved(shape.base, scale, shift);
                shape.cap = moved(shape.cap, scale, shift);
                shape.radius *= scale;
            } else if constexpr (std::is_same_v<S, scene::Box>) {
                shape.min = moved(shape.min, scale, shift);
                shape.max = moved(shape.max, scale, shift);
            } else {
                for (scene::Object& child : shape.children) {
                    transform_object(child, scale, shift);
                }
            }
        },
        object.shape);
}

void collect_leaves(const scene::Object& object, std::vector<const scene::Object*>& leaves) {
    if (const auto* csg = std::get_if<scene::Csg>(&object.shape)) {
        for (const scene::Object& child : csg->children) {
            collect_leaves(child, leaves);
        }
    } else {
        leaves.push_back(&object);
    }
}

const char* primitive_name(const scene::Object& primitive) {
    constexpr const char* names[] = {"plane", "sphere", "cylinder", "box", "csg"};
    return names[primitive.shape.index()];
}

// The first t > 0 at which the line crosses the primitive's surface (+∞ if none): what the tracer should
// have found for a ray leaving that primitive.
Real first_crossing(const scene::Object& primitive, const Vec3d& origin, const Vec3d& direction) {
    ExactSpan span = exact_span(primitive, origin, direction);
    if (!span.valid) {
        return std::numeric_limits<Real>::infinity();
    }
    if (span.enter > 0) {
        return span.enter;
    }
    return span.exit > 0 ? span.exit : std::numeric_limits<Real>::infinity();
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
    scene::Vec3 eye;
    for (int axis = 0; axis < 3; ++axis) {
        eye[axis] =
            scene.camera.look_at[axis] + camera_distance * (scene.camera.eye[axis] - scene.camera.look_at[axis]);
    }
    double half_angle = scene.camera.fov_deg * std::numbers::pi / 360;
    result.camera.fov_deg = std::atan(std::tan(half_angle) / camera_distance) * 360 / std::numbers::pi;
    result.camera.eye = moved(eye, scale, shift);
    result.camera.look_at = moved(scene.camera.look_at, scale, shift);
    for (scene::Light& light : result.lights) {
        light.position = moved(light.position, scale, shift);
    }
    for (scene::Object& object : result.objects) {
        transform_object(object, scale, shift);
    }
    return result;
}

scene::Scene rounded_to_float(const scene::Scene& scene) {
    auto round_vec = [](scene::Vec3& v) {
        for (double& c : v)
            c = static_cast<float>(c);
    };
    std::function<void(scene::Object&)> round_object = [&](scene::Object& object) {
        std::visit(
            [&](auto& shape) {
                using S = std::decay_t<decltype(shape)>;
                if constexpr (std::is_same_v<S, scene::Plane>) {
                    round_vec(shape.normal);
                    shape.offset = static_cast<float>(shape.offset);
                } else if constexpr (std::is_same_v<S, scene::Sphere>) {
                    round_vec(shape.center);
                    shape.radius = static_cast<float>(shape.radius);
                } else if constexpr (std::is_same_v<S, scene::Cylinder>) {
                    round_vec(shape.base);
                    round_vec(shape.cap);
                    shape.radius = static_cast<float>(shape.radius);
                } else if constexpr (std::is_same_v<S, scene::Box>) {
                    round_vec(shape.min);
                    round_vec(shape.max);
                } else {
                    for (scene::Object& child : shape.children)
                        round_object(child);
                }
            },
            object.shape);
    };
    scene::Scene result = scene;
    for (scene::Object& object : result.objects) {
        round_object(object);
    }
    return result;
}

std::vector<const scene::Object*> leaf_objects(const scene::Scene& scene) {
    std::vector<const scene::Object*> leaves;
    for (const scene::Object& object : scene.objects) {
        collect_leaves(object, leaves);
    }
    return leaves;
}

ExactSpan exact_span(const scene::Object& primitive, const Vec3d& origin, const Vec3d& direction) {
    Point o{origin[0], origin[1], origin[2]};
    Point d{direction[0], direction[1], direction[2]};
    constexpr Real infinity = std::numeric_limits<Real>::infinity();
    // Roots of a·t² + 2·b·t + c = 0 without cancellation.
    auto roots = [](Real a, Real b, Real c, ExactSpan& span) {
        Real discriminant = b * b - a * c;
        if (!(discriminant >= 0) || a == 0) {
            return;
        }
        Real q = -b - std::copysign(std::sqrt(discriminant), b);
        Real t0 = q / a, t1 = q == 0 ? 0 : c / q;
        span = {true, std::min(t0, t1), std::max(t0, t1)};
    };
    return std::visit(
        [&](const auto& shape) -> ExactSpan {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (std::is_same_v<S, scene::Plane>) {
                Point n = to_point(shape.normal);
                Real approach = dot(n, d);
                Real height = shape.offset * length(n) - dot(n, o);
                if (approach == 0) {
                    return height > 0 ? ExactSpan{true, -infinity, infinity} : ExactSpan{};
                }
                Real t = height / approach;
                return approach > 0 ? ExactSpan{true, -infinity, t} : ExactSpan{true, t, infinity};
            } else if constexpr (std::is_same_v<S, scene::Sphere>) {
                Point f = o - to_point(shape.center);
                ExactSpan span;
                roots(dot(d, d), dot(f, d), dot(f, f) - Real(shape.radius) * shape.radius, span);
                return span;
            } else if constexpr (std::is_same_v<S, scene::Cylinder>) {
                auto [base, axis, height] = frame_of(shape);
                Point f = o - base;
                Point f_perp = f - dot(f, axis) * axis;
                Point d_perp = d - dot(d, axis) * axis;
                Real c = dot(f_perp, f_perp) - Real(shape.radius) * shape.radius;
                ExactSpan side;
                if (dot(d_perp, d_perp) == 0) {
                    side = c < 0 ? ExactSpan{true, -infinity, infinity} : ExactSpan{};
                } else {
                    roots(dot(d_perp, d_perp), dot(f_perp, d_perp), c, side);
                }
                Real axial = dot(f, axis), speed = dot(d, axis);
                if (speed == 0) {
                    return axial > 0 && axial < height ? side : ExactSpan{};
                }
                Real t_base = -axial / speed, t_cap = (height - axial) / speed;
                side.enter = std::max(side.enter, std::min(t_base, t_cap));
                side.exit = std::min(side.exit, std::max(t_base, t_cap));
                side.valid = side.valid && side.enter <= side.exit;
                return side;
            } else if constexpr (std::is_same_v<S, scene::Box>) {
                ExactSpan span{true, -infinity, infinity};
                for (int axis = 0; axis < 3; ++axis) {
                    Real o_axis = axis == 0 ? o.x : axis == 1 ? o.y : o.z;
                    Real d_axis = axis == 0 ? d.x : axis == 1 ? d.y : d.z;
                    if (d_axis == 0) {
                        span.valid = span.valid && o_axis > shape.min[axis] && o_axis < shape.max[axis];
                        continue;
                    }
                    Real t_min = (shape.min[axis] - o_axis) / d_axis, t_max = (shape.max[axis] - o_axis) / d_axis;
                    span.enter = std::max(span.enter, std::min(t_min, t_max));
                    span.exit = std::min(span.exit, std::max(t_min, t_max));
                }
                span.valid = span.valid && span.enter <= span.exit;
                return span;
            } else {
                return ExactSpan{};
            }
        },
        primitive.shape);
}

Vec3d exact_normal(const scene::Object& primitive, const Vec3d& point) {
    Point p{point[0], point[1], point[2]};
    auto unit = [](Point v) {
        Real l = length(v);
        return Vec3d{static_cast<double>(v.x / l), static_cast<double>(v.y / l), static_cast<double>(v.z / l)};
    };
    return std::visit(
        [&](const auto& shape) -> Vec3d {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (std::is_same_v<S, scene::Plane>) {
                return unit(to_point(shape.normal));
            } else if constexpr (std::is_same_v<S, scene::Sphere>) {
                return unit(p - to_point(shape.center));
            } else if constexpr (std::is_same_v<S, scene::Cylinder>) {
                auto [base, axis, height] = frame_of(shape);
                Point f = p - base;
                Real axial = dot(f, axis);
                Point radial = f - axial * axis;
                Real to_cap = std::min(std::fabs(axial), std::fabs(height - axial));
                return to_cap < std::fabs(length(radial) - shape.radius) ? unit(axis) : unit(radial);
            } else if constexpr (std::is_same_v<S, scene::Box>) {
                int nearest_axis = 0;
                Real nearest = std::numeric_limits<Real>::infinity();
                for (int axis = 0; axis < 3; ++axis) {
                    Real c = axis == 0 ? p.x : axis == 1 ? p.y : p.z;
                    Real gap = std::min(std::fabs(c - shape.min[axis]), std::fabs(c - shape.max[axis]));
                    if (gap < nearest) {
                        nearest = gap;
                        nearest_axis = axis;
                    }
                }
                Vec3d n{0, 0, 0};
                n[static_cast<std::size_t>(nearest_axis)] = 1;
                return n;
            } else {
                return {0, 0, 0};
            }
        },
        primitive.shape);
}

long double distance_to_surface(const scene::Object& primitive, const Vec3d& point) {
    Point p{point[0], point[1], point[2]};
    return std::visit(
        [&](const auto& shape) -> Real {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (std::is_same_v<S, scene::Plane>) {
                Point n = to_point(shape.normal);
                return std::fabs(dot(n, p) / length(n) - shape.offset);
            } else if constexpr (std::is_same_v<S, scene::Sphere>) {
                return std::fabs(length(p - to_point(shape.center)) - shape.radius);
            } else if constexpr (std::is_same_v<S, scene::Cylinder>) {
                auto [base, axis, height] = frame_of(shape);
                Point f = p - base;
                Real axial = dot(f, axis);
                Real radial = length(f - axial * axis);
                if (axial >= 0 && axial <= height && radial <= shape.radius) {
                    return std::min({axial, height - axial, shape.radius - radial});
                }
                Real outside_axially = std::max({-axial, axial - height, Real(0)});
                Real outside_radially = std::max(radial - shape.radius, Real(0));
                return std::hypot(outside_axially, outside_radially);
            } else if constexpr (std::is_same_v<S, scene::Box>) {
                Real inside = std::numeric_limits<Real>::infinity();
                Real outside_squared = 0;
                for (int axis = 0; axis < 3; ++axis) {
                    Real c = axis == 0 ? p.x : axis == 1 ? p.y : p.z;
                    Real below = shape.min[axis] - c;
                    Real above = c - shape.max[axis];
                    inside = std::min(inside, std::max(below, above) <= 0 ? -std::max(below, above) : Real(0));
                    Real out = std::max({below, above, Real(0)});
                    outside_squared += out * out;
                }
                return outside_squared > 0 ? std::sqrt(outside_squared) : inside;
            } else {
                return std::numeric_limits<Real>::quiet_NaN();
            }
        },
        primitive.shape);
}

Measurement measure(const scene::Scene& scene, TracerKind kind, int grid, double size) {
    std::unique_ptr<AnyTracer> tracer = make_tracer(scene, kind);
    std::vector<const scene::Object*> leaves = leaf_objects(scene);
    scene::Scene held = kind == TracerKind::reference_double ? scene : rounded_to_float(scene);
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
