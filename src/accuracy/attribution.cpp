#include "accuracy/attribution.h"

#include "compare/image_compare.h"
#include "scene/placement.h"
#include "sse/tracer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <variant>

namespace twinray::accuracy {
namespace {

// The band at one ray of the reference's tree: how far the SSE tracer's ray may be off it after float
// rounding at every ray above it (radians between directions; distance between origins), and, where the
// ray hits, how far apart the two hit points and normals may be.
struct Band {
    double angle = 0;
    double offset = 0;
    double point = 0;
    double normal = 0;
};

using ray_tree_detail::angle_between;
using ray_tree_detail::max_abs;
using ray_tree_detail::max_abs_difference;
using RefRay = reference::Ray<double>;
using RefVec = reference::Vec3<double>;

// Float's unit roundoff, and the margin of the conformance bound (docs/conformance.md): each ray, normal
// and intersection rounds by a few u of the size of its numbers; 64 u covers them all.
constexpr double unit_roundoff = 0x1p-24;
constexpr double rounding = 64 * unit_roundoff;
constexpr double infinity = std::numeric_limits<double>::infinity();

const RayNode& node_of(const RayTree& tree, int index) {
    return tree.nodes[static_cast<std::size_t>(index)];
}

RefVec to_ref(const Vec3d& v) {
    return {v[0], v[1], v[2]};
}

double dot3(const Vec3d& a, const Vec3d& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

double curvature_radius(const scene::Object& primitive, const Vec3d& point) {
    return std::visit(
        [&](const auto& shape) {
            if constexpr (std::is_same_v<std::decay_t<decltype(shape)>, scene::Csg>) {
                return infinity;  // never a leaf: its children are
            } else {
                return scene::curvature_radius(shape, point);
            }
        },
        primitive.shape);
}

// A radius of curvature in an object's space seen through its transform: shrunk by the most the transform can bend
// it, as a transformed primitive's curvature_radius is.
double placed_radius(double object_radius, const scene::Transform& to_world) {
    const double shrink = math::frobenius_norm(to_world.inverse);
    return object_radius / (shrink * shrink * math::frobenius_norm(to_world.linear));
}

// Calls visit(primitive) for each primitive of the object.
template <typename Visit>
void for_each_primitive(const scene::Object& object, Visit&& visit) {
    if (const auto* csg = std::get_if<scene::Csg>(&object.shape)) {
        for (const scene::Object& child : csg->children) {
            for_each_primitive(child, visit);
        }
        return;
    }
    visit(object);
}

// What carrying a ray into a placed object's space (a transformed primitive, an instance) costs it, seen from the
// world (docs/numerics.md, "Transforms"). o − t, L⁻¹·(o − t) and L⁻¹·d in float, L⁻¹ itself rounded, put each
// component of o' off by γ(6) of (|L⁻¹|·|o − t|), so |o' error| ≤ γ(6)·‖L⁻¹‖_F·√3·|o − t|∞, and d' likewise; L brings
// that back multiplied by ‖L‖_F: κ·γ(6)·√3 (10.4 u) in direction and times |o − t|∞ in origin, held by 12 u.
constexpr double trip_rounding = 12 * unit_roundoff;

// What the bands need of a leaf. What turns its normal as its hit point moves: its primitive, whose radius of curvature
// at a point each primitive type gives (scene::curvature_radius); a mesh's shading radius; or on an instance of a solid
// shape, the part's primitive in the shape's space. And where the leaf lies in a space of its own, what the trip there
// costs a ray: κ of its transform (0 where it has none; on an instance of a solid shape, times the largest of its
// parts' own), the transform's translation, and the leaf's box in the world (where a shadow ray may pass it).
struct LeafFacts {
    const scene::Object* primitive = nullptr;
    double mesh_radius = infinity;
    const scene::SolidInstance* instance = nullptr;
    const scene::SolidShape* shape = nullptr;  // the instance's
    double condition = 0;
    Vec3d translation{};  // of its transform
    scene::Bounds bounds{};

    double radius_at(const Vec3d& point, int part) const {
        if (instance == nullptr || part < 0) {
            return primitive == nullptr ? mesh_radius : curvature_radius(*primitive, point);
        }
        const scene::Transform to_world = instance->placement.transform();
        double radius = infinity;
        for_each_primitive(shape->tree, [&](const scene::Object& candidate) {
            if (candidate.leaf == part) {
                radius = placed_radius(curvature_radius(candidate, to_world.point_to_object(point)), to_world);
            }
        });
        return radius;
    }

    void place(const scene::Transform& to_world, const scene::Bounds& placed, double inner_condition = 1) {
        condition = scene::condition_number(to_world) * inner_condition;
        translation = to_world.translation;
        bounds = placed;
    }
};

// A transformed primitive's transform (scene::Transformed); null for any other primitive.
const scene::Transform* own_transform(const scene::Object& primitive) {
    return std::visit(
        [](const auto& shape) -> const scene::Transform* {
            if constexpr (requires { shape.to_world(); }) {
                return &shape.to_world();
            } else {
                return nullptr;
            }
        },
        primitive.shape);
}

// The largest κ of a primitive's own transform (1 for none), over the primitives of an object.
double largest_own_condition(const scene::Object& object) {
    double largest = 1;
    for_each_primitive(object, [&](const scene::Object& primitive) {
        if (const scene::Transform* to_world = own_transform(primitive)) {
            largest = std::max(largest, scene::condition_number(*to_world));
        }
    });
    return largest;
}

// A smooth mesh shades with normals interpolated along its edges: they turn by the angle between two
// vertex normals over the edge's length, so its radius is the least edge length over that angle. A flat
// mesh's normal does not turn within a triangle.
double shading_radius(const scene::MeshData& mesh) {
    double radius = infinity;
    if (!mesh.smooth) {
        return radius;
    }
    for (const std::array<std::uint32_t, 3>& triangle : mesh.triangles) {
        for (int i = 0; i < 3; ++i) {
            std::uint32_t a = triangle[static_cast<std::size_t>(i)],
                          b = triangle[static_cast<std::size_t>((i + 1) % 3)];
            double turn = angle_between(mesh.normals[a], mesh.normals[b]);
            if (turn > 0) {
                radius = std::min(radius, reference::length(to_ref(mesh.vertices[b] - mesh.vertices[a])) / turn);
            }
        }
    }
    return radius;
}

std::vector<LeafFacts> leaf_facts(const scene::Scene& scene) {
    std::vector<LeafFacts> by_leaf(scene.leaf_paths.size());
    for (const scene::Object& object : scene.objects) {
        for_each_primitive(object, [&](const scene::Object& primitive) {
            LeafFacts& facts = by_leaf[static_cast<std::size_t>(primitive.leaf)];
            facts.primitive = &primitive;
            if (const scene::Transform* to_world = own_transform(primitive)) {
                facts.place(*to_world, scene::bounds(primitive));
            }
        });
    }
    std::vector<scene::Bounds> solid_bounds;
    for (const scene::SolidShape& shape : scene.solid_shapes) {
        solid_bounds.push_back(scene::bounds(shape.tree));
    }
    for (const scene::SolidInstance& instance : scene.solid_instances) {
        LeafFacts& facts = by_leaf[static_cast<std::size_t>(instance.leaf)];
        const auto shape = static_cast<std::size_t>(instance.placement.shape);
        facts.instance = &instance;
        facts.shape = &scene.solid_shapes[shape];
        const scene::Transform to_world = instance.placement.transform();
        facts.place(to_world, scene::placed_bounds(solid_bounds[shape], to_world),
                    largest_own_condition(facts.shape->tree));
    }
    std::vector<double> shape_radius;
    std::vector<scene::Bounds> mesh_bounds;
    for (const scene::MeshShape& shape : scene.mesh_shapes) {
        shape_radius.push_back(shading_radius(*shape.data));
        mesh_bounds.push_back(scene::vertex_bounds(*shape.data));
    }
    for (const scene::Mesh& mesh : scene.meshes) {
        double& radius = by_leaf[static_cast<std::size_t>(mesh.leaf)].mesh_radius;
        if (!mesh.placement) {
            radius = shading_radius(*mesh.data);
            continue;
        }
        const auto shape = static_cast<std::size_t>(mesh.placement->shape);
        const scene::Transform to_world = mesh.placement->transform();
        radius = placed_radius(shape_radius[shape], to_world);
        by_leaf[static_cast<std::size_t>(mesh.leaf)].place(to_world,
                                                           scene::placed_bounds(mesh_bounds[shape], to_world));
    }
    return by_leaf;
}

// The band of a ray as the leaf it meets sees it: wider by the trip into the leaf's space, where it has one.
Band seen_by(const Band& band, const LeafFacts& leaf, const RayNode& ray) {
    if (leaf.condition == 0) {
        return band;
    }
    const double slack = leaf.condition * trip_rounding;
    return {band.angle + slack, band.offset + slack * max_abs_difference(ray.origin, leaf.translation), band.point,
            band.normal};
}

// The band of a ray whose two versions `p` and `q` meet other leaves, or one of them none, as both leaves see it.
Band seen_by_either(const Band& band, const std::vector<LeafFacts>& facts, const RayNode& p, const RayNode& q) {
    Band seen = band;
    for (const RayNode* node : {&p, &q}) {
        if (node->hit) {
            const Band by_node = seen_by(band, facts[static_cast<std::size_t>(node->leaf)], *node);
            seen.angle = std::max(seen.angle, by_node.angle);
            seen.offset = std::max(seen.offset, by_node.offset);
        }
    }
    return seen;
}

// Where a ray with `band` meets a surface: its hit point slides across the ray and along the surface (a
// grazing ray far along it: 1/|cos θ|, as in the conformance bound), and the normal turns by that over the
// radius of curvature.
void add_hit(Band& band, const RayNode& node, const LeafFacts& leaf) {
    const Band seen = seen_by(band, leaf, node);
    double cosine = std::fabs(dot3(node.normal, node.direction));
    band.point = (seen.offset + node.t * seen.angle) / cosine + rounding * max_abs(node.point);
    band.normal = band.point / leaf.radius_at(node.point, node.part) + rounding;
}

Band band_along(const scene::Scene& scene, const std::vector<LeafFacts>& facts, const RayTree& tree, int index) {
    std::vector<int> path;
    for (int i = index; i >= 0; i = node_of(tree, i).parent) {
        path.push_back(i);
    }
    std::reverse(path.begin(), path.end());
    Band band{rounding, rounding * max_abs(node_of(tree, path.front()).origin), 0, 0};
    for (std::size_t k = 0; k < path.size(); ++k) {
        const RayNode& a = node_of(tree, path[k]);
        if (!a.hit) {
            break;
        }
        add_hit(band, a, facts[static_cast<std::size_t>(a.leaf)]);
        if (k + 1 == path.size()) {
            break;
        }
        // A reflected ray turns by the incoming error plus twice the normal's; a refracted one by
        // η·cos θi / cos θt times the incoming error (Snell's law differentiated), and as much again for the
        // normal's turn.
        const RayNode& child = node_of(tree, path[k + 1]);
        double gain = 1;
        if (child.kind == RayKind::refracted) {
            double ior = scene.material_of_leaf(a.leaf, a.part).ior;
            double eta = a.entering ? 1 / ior : ior;
            gain = eta * std::fabs(dot3(a.normal, a.direction)) / std::fabs(dot3(child.direction, a.normal));
        }
        band.angle = gain * band.angle + (1 + gain) * band.normal + rounding;
        band.offset = band.point;
    }
    return band;
}

bool same_hit(const std::optional<reference::Hit<double>>& hit, const RayNode& node) {
    if (hit.has_value() != node.hit) {
        return false;
    }
    return !hit || (hit->leaf == node.leaf && hit->part == node.part && hit->entering == node.entering);
}

// Two unit vectors across d.
std::array<RefVec, 2> across(const RefVec& d) {
    RefVec helper = std::fabs(d.x) < 0.9 ? RefVec(1, 0, 0) : RefVec(0, 1, 0);
    RefVec u = reference::normalize(reference::cross(d, helper));
    return {u, reference::cross(d, u)};
}

// Whether the reference, given a ray within the band of the SSE tracer's (that ray first, then tilted and
// shifted by the band across it), makes a hit for which `agrees` holds.
template <typename Agrees>
bool replay_agrees(const reference::Tracer<double>& reference, const RayNode& actual, const Band& band,
                   Agrees&& agrees) {
    RefVec origin = to_ref(actual.origin);
    RefVec direction = to_ref(actual.direction);
    if (agrees(reference.intersect(RefRay{origin, direction}))) {
        return true;
    }
    for (const RefVec& side : across(direction)) {
        for (double sign : {-1.0, 1.0}) {
            RefVec tilted = reference::normalize(direction + (sign * std::tan(band.angle)) * side);
            RefVec shifted = origin + (sign * band.offset) * side;
            if (agrees(reference.intersect(RefRay{origin, tilted})) ||
                agrees(reference.intersect(RefRay{shifted, direction}))) {
                return true;
            }
        }
    }
    return false;
}

// How far the trip into a placed leaf's space may move a shadow ray from `origin` to the light at `position` where the
// ray passes the leaf: the trip's offset, and its turn over the ray's length up to where it leaves the leaf's box. The
// most over the leaves whose box, widened by that and by `pad`, the ray passes; the ray tree does not record which
// leaf blocked a shadow ray.
double occluder_trip(const std::vector<LeafFacts>& facts, const Vec3d& origin, const Vec3d& position, double pad) {
    const RefRay segment{to_ref(origin), to_ref(position) - to_ref(origin)};  // the origin at t = 0, the light at 1
    const double length = reference::length(segment.direction);
    double most = 0;
    for (const LeafFacts& leaf : facts) {
        const double per_unit = leaf.condition * trip_rounding;
        const double offset = per_unit * max_abs_difference(origin, leaf.translation);
        // Turned over the whole ray: the widest box the move needs, which holds the box that leaving sooner needs.
        const double widest = offset + per_unit * length;
        if (!(widest > most)) {
            continue;
        }
        const scene::Bounds box = scene::around(leaf.bounds.low, leaf.bounds.high, pad + widest);
        const auto span = reference::span_of(reference::BoxShape<double>{to_ref(box.low), to_ref(box.high)}, segment);
        if (span && span->exit.t >= 0 && span->enter.t <= 1) {
            most = std::max(most, offset + per_unit * length * std::min(span->exit.t, 1.0));
        }
    }
    return most;
}

// A light seen otherwise by the two tracers. Facing away in one tree only: N·L is within what the band
// lets the normal and the point move it. Blocked in one tree only: the reference, casting shadow rays from
// the SSE tracer's shadow origin or within the band of it along the surface, finds it blocked or open as the SSE
// tracer did; past a placed leaf, the ray moved across as a whole by what the trip into its space may move it
// (occluder_trip), too.
bool light_flip_explained(const scene::Scene& scene, const std::vector<LeafFacts>& facts,
                          const reference::Tracer<double>& reference, const RayNode& expected, const RayNode& actual,
                          std::size_t light, const Band& band) {
    const LightVisibility& mine = expected.lights[light];
    const LightVisibility& theirs = actual.lights[light];
    RefVec position = to_ref(scene.lights[light].position);
    if (mine.faces_away != theirs.faces_away) {
        double distance = reference::length(position - to_ref(expected.point));
        return std::fabs(mine.n_dot_l) <= band.normal + band.point / distance + rounding;
    }
    bool blocked = theirs.transmittance == 0;
    RefVec origin = to_ref(theirs.shadow_origin);
    if ((reference.shadow_transmittance(origin, position) == 0) == blocked) {
        return true;
    }
    // The origin slides along the surface, as the hit point does (add_hit): moved across the shadow ray instead, it
    // sank under the surface it starts from, which then blocked it. The whole ray moves by `trip` across itself (a
    // side along the surface is at least |N·L| across the ray, and N·L > 0 where a shadow ray is cast).
    const RefVec direction = reference::normalize(position - origin);
    const std::array<RefVec, 2> along_surface = across(to_ref(actual.normal));
    auto agrees_moved = [&](double trip) {
        for (const RefVec& side : along_surface) {
            const double across_ray = reference::length(side - reference::dot(side, direction) * direction);
            for (double sign : {-1.0, 1.0}) {
                const RefVec trip_move = (sign * trip / across_ray) * side;
                if ((reference.shadow_transmittance(origin + (sign * band.point) * side + trip_move,
                                                    position + trip_move) == 0) == blocked) {
                    return true;
                }
            }
        }
        return false;
    };
    if (agrees_moved(0)) {
        return true;
    }
    const double trip = occluder_trip(facts, theirs.shadow_origin, scene.lights[light].position, band.point);
    return trip > 0 && agrees_moved(trip);
}

// Refracted in one tree, totally reflected in the other: sin²θt = η²(1 − cos²θi) is within what the band
// lets the ray and the normal move it from 1.
bool refraction_flip_explained(const scene::Scene& scene, const RayNode& expected, const Band& band) {
    double ior = scene.material_of_leaf(expected.leaf, expected.part).ior;
    double eta = expected.entering ? 1 / ior : ior;
    double cosine = std::fabs(dot3(expected.direction, expected.normal));
    double sin2 = eta * eta * (1 - cosine * cosine);
    double moved = 2 * eta * eta * (band.angle + band.normal) + rounding;
    return std::fabs(sin2 - 1) <= moved;
}

// The local colours of one hit differ: by no more than inputs within the band can move
// ambient + Σ s·(diffuse·C·Lc·N·L + phong·Lc·(R·L)^n), plus rounding. N·L moves by the normal's turn and the
// light direction's (the point's shift over the light's distance); R·L by twice the normal's turn, the ray's
// and the light direction's; s by what the two shadow rays measured (a larger change is a light flip).
bool local_drift_explained(const scene::Scene& scene, const RayNode& expected, const RayNode& actual,
                           const Band& band) {
    if (!expected.hit || angle_between(expected.normal, actual.normal) > band.normal + rounding ||
        max_abs_difference(expected.point, actual.point) > band.point) {
        return false;
    }
    const scene::Material& m = scene.material_of_leaf(expected.leaf, expected.part);
    double colour = std::max({m.color.x, m.color.y, m.color.z});
    double allowed = rounding * (1 + max_abs(expected.local));
    for (std::size_t l = 0; l < std::min(expected.lights.size(), actual.lights.size()); ++l) {
        const LightVisibility& mine = expected.lights[l];
        const LightVisibility& theirs = actual.lights[l];
        const scene::Vec3& light_colour = scene.lights[l].color;
        double strength = std::max({light_colour.x, light_colour.y, light_colour.z});
        double turn = band.point / reference::length(to_ref(scene.lights[l].position) - to_ref(expected.point));
        double d_lambert = band.normal + turn + rounding;
        double d_mirror = 2 * band.normal + band.angle + turn + rounding;
        double d_transmittance = std::fabs(mine.transmittance - theirs.transmittance);
        double transmittance = std::max(mine.transmittance, theirs.transmittance);
        allowed += strength * (d_transmittance * (m.diffuse * colour + m.phong) +
                               transmittance * (m.diffuse * colour * d_lambert + m.phong * m.phong_size * d_mirror));
    }
    return max_abs_difference(expected.local, actual.local) <= allowed;
}

// The node of `to` that the path of ray kinds leading to `index` in `from` reaches; -1 if `to` lacks it.
int twin(const RayTree& from, const RayTree& to, int index) {
    std::vector<RayKind> kinds;
    for (int i = index; node_of(from, i).parent >= 0; i = node_of(from, i).parent) {
        kinds.push_back(node_of(from, i).kind);
    }
    int j = 0;
    for (auto kind = kinds.rbegin(); kind != kinds.rend(); ++kind) {
        int next = -1;
        for (int child : to.children(j)) {
            if (node_of(to, child).kind == *kind) {
                next = child;
            }
        }
        if (next < 0) {
            return -1;
        }
        j = next;
    }
    return j;
}

// Whether a node's total colour is what the shading formula makes of its own local colour and its children's
// totals: local + transmission·refracted + reflection·reflected, the transmission added to the reflection on
// total internal reflection (no refracted child, and none left out by the depth control). Rounding aside,
// a tree whose colours do not add up was not shaded by the model.
bool colours_add_up(const scene::Scene& scene, const RayTree& tree, int index) {
    const RayNode& node = node_of(tree, index);
    if (!node.hit) {
        return true;
    }
    const scene::Material& m = scene.material_of_leaf(node.leaf, node.part);
    bool refracted = false, refracted_left_out = false;
    Vec3d sum = node.local;
    double size = max_abs(node.local);
    std::vector<int> children = tree.children(index);
    for (int child : children) {
        refracted = refracted || node_of(tree, child).kind == RayKind::refracted;
    }
    for (const DroppedRay& dropped : tree.dropped) {
        refracted_left_out = refracted_left_out || (dropped.parent == index && dropped.kind == RayKind::refracted);
    }
    bool total_internal = m.transmission > 0 && !refracted && !refracted_left_out;
    for (int child : children) {
        const RayNode& c = node_of(tree, child);
        double coefficient =
            c.kind == RayKind::refracted ? m.transmission : m.reflection + (total_internal ? m.transmission : 0.0);
        sum = sum + coefficient * c.total;
        size += coefficient * max_abs(c.total);
    }
    return max_abs_difference(sum, node.total) <= rounding * (1 + size);
}

// Whether one ray's two versions, hitting the same surface, stay within the band at that ray: direction and
// origin, t across the surface, the normal, and (`with_colour`) the local colour within what those inputs
// can move it. The ray of a light flip is held to its geometry only: the flip changes its colour.
bool within_band(const scene::Scene& scene, const RayNode& p, const RayNode& q, const Band& band, bool with_colour) {
    if (angle_between(p.direction, q.direction) > band.angle ||
        max_abs_difference(p.origin, q.origin) > band.offset + rounding * max_abs(p.origin)) {
        return false;
    }
    if (!p.hit) {
        return true;
    }
    if (std::fabs(p.t - q.t) * std::fabs(dot3(p.normal, p.direction)) > band.point) {
        return false;
    }
    return with_colour ? local_drift_explained(scene, p, q, band) : angle_between(p.normal, q.normal) <= band.normal;
}

// A discrete difference (render/ray_tree.h marks them with threshold 0): a ray traced in one tree only, hit
// or miss, another object, entering or leaving, a light facing away or blocked in one tree only.
bool is_flip(const Divergence& d) {
    return d.threshold == 0;
}

PixelCause judge_flip(const scene::Scene& scene, const std::vector<LeafFacts>& facts,
                      const reference::Tracer<double>& reference, const RayTree& expected, const RayTree& actual,
                      const Divergence& flip) {
    PixelCause cause{Cause::unexplained, flip.what, 0, 0, 0};
    // A ray traced in one tree only is judged at its parent, where the decision to trace it was made.
    int i = flip.first, j = flip.second;
    if (flip.what == "ray") {
        bool in_expected = flip.first >= 0;
        const RayTree& with = in_expected ? expected : actual;
        int parent = node_of(with, in_expected ? flip.first : flip.second).parent;
        if (parent < 0) {
            return cause;
        }
        i = in_expected ? parent : twin(actual, expected, parent);
        j = in_expected ? twin(expected, actual, parent) : parent;
    }
    if (i < 0 || j < 0) {
        return cause;
    }
    const RayNode& p = node_of(expected, i);
    const RayNode& q = node_of(actual, j);
    Band band = band_along(scene, facts, expected, i);
    cause.depth = p.depth;
    cause.deviation = angle_between(p.direction, q.direction);
    cause.band = band.angle;
    if (cause.deviation > band.angle ||
        max_abs_difference(p.origin, q.origin) > band.offset + rounding * max_abs(p.origin)) {
        return cause;
    }
    const std::string& what = flip.what;
    bool explained = false;
    if (what == "hit" || what == "object" || what == "entering") {
        cause.cause = Cause::silhouette;
        explained = replay_agrees(reference, q, seen_by_either(band, facts, p, q),
                                  [&](const auto& hit) { return same_hit(hit, q); });
    } else if (what == "ray") {
        cause.cause = Cause::refraction;
        explained = p.hit && scene.material_of_leaf(p.leaf, p.part).transmission > 0 &&
                    refraction_flip_explained(scene, p, band);
    } else if (what.rfind("lights[", 0) == 0) {
        cause.cause = Cause::shadow;
        std::size_t light = static_cast<std::size_t>(std::stoul(what.substr(7)));
        explained = light < p.lights.size() && light < q.lights.size() &&
                    light_flip_explained(scene, facts, reference, p, q, light, band);
    }
    if (!explained) {
        cause.cause = Cause::unexplained;
    }
    return cause;
}

PixelCause attribute_with(const scene::Scene& scene, const std::vector<LeafFacts>& facts,
                          const reference::Tracer<double>& reference, const RayTree& expected, const RayTree& actual) {
    std::vector<Divergence> divergences = find_divergences(expected, actual);
    auto flip = std::find_if(divergences.begin(), divergences.end(), is_flip);
    for (int j = 0; j < static_cast<int>(actual.nodes.size()); ++j) {
        if (!colours_add_up(scene, actual, j)) {
            return {Cause::unexplained, "colours that do not add up", node_of(actual, j).depth, 0, 0};
        }
    }
    // Every ray traced before the first flip, in both trees alike, must stay within its band: the probe's
    // thresholds are far above rounding, the bands are not.
    const int count = static_cast<int>(expected.nodes.size());
    int flip_node = flip == divergences.end() || flip->first < 0 ? count : flip->first;
    for (int i = 0; i <= std::min(flip_node, count - 1); ++i) {
        int j = twin(expected, actual, i);
        if (j < 0) {
            continue;
        }
        const RayNode& p = node_of(expected, i);
        const RayNode& q = node_of(actual, j);
        if (p.hit != q.hit || (p.hit && (p.leaf != q.leaf || p.part != q.part))) {
            continue;  // judged as the flip
        }
        Band band = band_along(scene, facts, expected, i);
        if (!within_band(scene, p, q, band, i < flip_node)) {
            // The other face at an edge turns the normal: the reference, given a ray within the band, meets the
            // face the SSE tracer met.
            bool ray_in_band = angle_between(p.direction, q.direction) <= band.angle &&
                               max_abs_difference(p.origin, q.origin) <= band.offset + rounding * max_abs(p.origin);
            bool edge =
                p.hit && ray_in_band && angle_between(p.normal, q.normal) > band.normal &&
                replay_agrees(reference, q, seen_by_either(band, facts, p, q), [&](const auto& hit) {
                    return hit && same_hit(hit, q) &&
                           angle_between(Vec3d{hit->normal.x, hit->normal.y, hit->normal.z}, q.normal) <= band.normal;
                });
            return {edge ? Cause::silhouette : Cause::unexplained, edge ? "normal" : "drift beyond the band", p.depth,
                    angle_between(p.direction, q.direction), band.angle};
        }
    }
    if (flip == divergences.end()) {
        return {Cause::drift, divergences.empty() ? "" : divergences.front().what, 0, 0, 0};
    }
    return judge_flip(scene, facts, reference, expected, actual, *flip);
}

}  // namespace

const char* cause_name(Cause cause) {
    switch (cause) {
        case Cause::silhouette: return "silhouette";
        case Cause::shadow: return "shadow";
        case Cause::refraction: return "refraction";
        case Cause::drift: return "drift";
        case Cause::unexplained: return "unexplained";
    }
    return "?";
}

PixelCause attribute(const scene::Scene& scene, const reference::Tracer<double>& reference, const RayTree& expected,
                     const RayTree& actual) {
    return attribute_with(scene, leaf_facts(scene), reference, expected, actual);
}

Attribution attribute_pixels(const scene::Scene& scene, const Image& reference_image, const Image& actual_image,
                             const tracing::AnyTracer& actual, double threshold) {
    const int width = reference_image.width(), height = reference_image.height();
    reference::Tracer<double> reference(scene);
    std::vector<LeafFacts> facts = leaf_facts(scene);
    Attribution attribution;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            double error = compare::largest_channel_difference(reference_image.at(x, y), actual_image.at(x, y));
            if (!(error > threshold)) {
                continue;
            }
            RayTree expected, traced;
            reference.trace(reference.primary_ray(x, y, width, height), 1, nullptr, &expected);
            actual.trace_primary(x, y, width, height, traced);
            PixelCause cause = attribute_with(scene, facts, reference, expected, traced);
            ++attribution.counts[static_cast<std::size_t>(cause.cause)];
            if (cause.cause == Cause::unexplained) {
                attribution.unexplained.push_back({x, y, error, cause});
            }
        }
    }
    std::stable_sort(attribution.unexplained.begin(), attribution.unexplained.end(),
                     [](const AttributedPixel& a, const AttributedPixel& b) { return a.error > b.error; });
    if (attribution.unexplained.size() > max_unexplained_listed) {
        attribution.unexplained.resize(max_unexplained_listed);
    }
    return attribution;
}

std::string attribution_failure(const Attribution& attribution, long pixel_count, const ClassBudgets& budgets) {
    auto count = [&](Cause cause) { return attribution.counts[static_cast<std::size_t>(cause)]; };
    if (long unexplained = count(Cause::unexplained); unexplained > 0) {
        return std::to_string(unexplained) + " unexplained pixel" + (unexplained == 1 ? "" : "s");
    }
    const std::pair<Cause, double> budgeted[] = {{Cause::silhouette, budgets.silhouette_percent},
                                                 {Cause::shadow, budgets.shadow_percent},
                                                 {Cause::refraction, budgets.refraction_percent}};
    for (const auto& [cause, percent] : budgeted) {
        double share = 100.0 * static_cast<double>(count(cause)) / static_cast<double>(std::max(pixel_count, 1L));
        if (share > percent) {
            char text[160];
            std::snprintf(text, sizeof text, "%s pixels %.3g%% of the image, over their budget of %.3g%%",
                          cause_name(cause), share, percent);
            return text;
        }
    }
    return "";
}

}  // namespace twinray::accuracy
