#include "sse/tracer.h"

#include "sse/compiled_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

// Why packets of four rays (one ray per lane, each primitive broadcast) and not one ray against four
// primitives (one primitive per lane): both run the same intersection formulas, and we measured both
// (docs/performance.md). Testing one ray against four primitives left the lanes of small scenes half
// empty (complete1 has 2 planes, 4 spheres, 1 cylinder) and, above all, left shading scalar, and
// shading is most of a Whitted ray's work: normals, light vectors, shadow-ray set-up, Phong, Snell. With
// four rays per lane set, intersection, shadows and shading all run four-wide, and secondary rays
// continue as packets under a mask of the lanes that spawn them.

namespace twinray::sse {
namespace {

// Tag bits of a nearest hit: the crossing's tag (face, flipped) plus whether the ray enters there.
constexpr std::int32_t tag_entering = 0x20;

// Rays in a lane mask (a popcount without relying on the POPCNT instruction, which SSE4.1 lacks).
inline std::uint64_t lane_count(vbool4 mask) {
    constexpr std::uint8_t bits[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
    return bits[movemask(mask)];
}

struct Vec4 {
    vfloat4 x, y, z;

    vfloat4 operator[](int axis) const { return axis == 0 ? x : axis == 1 ? y : z; }
};

inline Vec4 operator+(const Vec4& a, const Vec4& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec4 operator-(const Vec4& a, const Vec4& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec4 operator*(vfloat4 s, const Vec4& a) {
    return {s * a.x, s * a.y, s * a.z};
}
inline Vec4 operator*(const Vec4& a, const Vec4& b) {
    return {a.x * b.x, a.y * b.y, a.z * b.z};
}
inline Vec4 operator-(const Vec4& a) {
    return {-a.x, -a.y, -a.z};
}
template <typename P>
inline vfloat4 dot(const Vec4& a, const Vec4& b) {
    const vfloat4 left[3] = {a.x, a.y, a.z}, right[3] = {b.x, b.y, b.z};
    return dot3<P>(left, right);
}
// Where only a sign is needed (spawn_origin's side of the surface), whatever the knobs.
inline vfloat4 dot(const Vec4& a, const Vec4& b) {
    return dot<ExactKernels>(a, b);
}
inline Vec4 broadcast(Vec3 v) {
    return {vfloat4(v.x), vfloat4(v.y), vfloat4(v.z)};
}
inline Vec4 select(vbool4 mask, const Vec4& a, const Vec4& b) {
    return {select(mask, a.x, b.x), select(mask, a.y, b.y), select(mask, a.z, b.z)};
}
// 1/|a| by the knobs' inverse_sqrt; exact, as the scalar normalize: one IEEE division shared by the
// three components.
template <typename P>
inline Vec4 normalize(const Vec4& a) {
    return inverse_sqrt<P>(dot<P>(a, a)) * a;
}

using Color4 = Vec4;

inline vfloat4 from_lanes(const float lanes[4]) {
    return vfloat4(_mm_setr_ps(lanes[0], lanes[1], lanes[2], lanes[3]));
}

// The nearest crossing so far, per lane (per ray).
struct Nearest4 {
    vfloat4 t{infinity};
    vint4 leaf{-1};
    vint4 tag{0};
};

// A primitive's first crossing after t = 0 is its enter if that lies ahead, else its exit. Smaller t
// wins; at equal t the smaller leaf, i.e. the object earlier in the file.
inline void keep_nearest(Nearest4& nearest, const Span4& span, std::int32_t leaf_id) {
    vfloat4 zero(0.0f);
    vint4 leaf(leaf_id);
    vbool4 entering = span.enter > zero;
    vfloat4 t = select(entering, span.enter, span.exit);
    vint4 tag = select(entering, span.enter_face | vint4(tag_entering), span.exit_face);
    vbool4 nearer = span.valid & (t > zero) & ((t < nearest.t) | ((t == nearest.t) & (leaf < nearest.leaf)));
    nearest.t = select(nearer, t, nearest.t);
    nearest.leaf = select(nearer, leaf, nearest.leaf);
    nearest.tag = select(nearer, tag, nearest.tag);
}

// Primitives that no ray of the packet meets are skipped before any use of their span: in a coherent
// packet that is most of them.
template <typename P, typename Primitive, typename Visit>
void for_each_primitive(const PrimitiveList<Primitive>& list, const RayPacket& rays, Visit&& visit) {
    for (std::size_t i = 0; i < list.items.size(); ++i) {
        Span4 span = spans<P>(list.items[i], rays);
        if (any(span.valid)) {
            visit(span, list.ids[i], list.transmission[i]);
        }
    }
}

// Calls visit(span, id, transmission) for every primitive of every type present that some ray meets.
template <typename P, typename Visit>
void for_each_span(const PrimitiveLists& lists, const RayPacket& rays, Visit&& visit) {
    for_each_primitive<P>(lists.planes, rays, visit);
    for_each_primitive<P>(lists.spheres, rays, visit);
    for_each_primitive<P>(lists.cylinders, rays, visit);
    for_each_primitive<P>(lists.boxes, rays, visit);
}

// A CSG object's span list for one lane of a packet: every leaf's span computed for the whole packet
// (four rays per instruction), then the tree folded bottom-up per ray in stack arrays.
template <typename P>
class CsgEvaluation {
public:
    CsgEvaluation(const CsgObject& object, const RayPacket& rays) : object_(object) {
        std::fill(valid_, valid_ + object.slot_leaf.size(), 0);  // leaves no ray meets are not visited
        for_each_span<P>(object.leaves, rays, [&](const Span4& span, std::int32_t slot, float) {
            span.enter.store(enter_[slot]);
            span.exit.store(exit_[slot]);
            span.enter_face.store(enter_face_[slot]);
            span.exit_face.store(exit_face_[slot]);
            valid_[slot] = movemask(span.valid);
        });
    }

    void evaluate(int lane, SpanArray& out) const { evaluate(lane, 0, out); }

private:
    void evaluate(int lane, int node_index, SpanArray& out) const {
        const CsgNodeF& node = object_.nodes[static_cast<std::size_t>(node_index)];
        if (node.slot >= 0) {
            out.clear();
            int slot = node.slot;
            if ((valid_[slot] >> lane) & 1) {
                std::int32_t leaf = object_.slot_leaf[static_cast<std::size_t>(slot)];
                float enter = enter_[slot][lane];
                float exit = exit_[slot][lane];
                out.push({enter, std::isinf(enter) ? -1 : leaf, enter_face_[slot][lane]},
                         {exit, std::isinf(exit) ? -1 : leaf, exit_face_[slot][lane]});
            }
            return;
        }
        const int* children = &object_.children_of[static_cast<std::size_t>(node.first_child)];
        SpanArray operand, scratch, other;
        SpanArray* accumulated = &out;
        SpanArray* combined = &other;
        evaluate(lane, children[0], *accumulated);
        for (int i = 1; i < node.child_count; ++i) {
            evaluate(lane, children[i], operand);
            csg_combine(node.op, *accumulated, operand, scratch, *combined);
            std::swap(accumulated, combined);
        }
        if (accumulated != &out) {
            out.assign(*accumulated);
        }
    }

    const CsgObject& object_;
    alignas(16) float enter_[scene::max_csg_leaves][4];
    alignas(16) float exit_[scene::max_csg_leaves][4];
    alignas(16) std::int32_t enter_face_[scene::max_csg_leaves][4];
    alignas(16) std::int32_t exit_face_[scene::max_csg_leaves][4];
    int valid_[scene::max_csg_leaves];
};

// The lanes whose ray meets the object's bound somewhere in (0, limit).
template <typename P>
inline int lanes_meeting_bound(const CsgObject& object, const RayPacket& rays, vfloat4 limit) {
    Span4 span = spans<P>(object.bound, rays);
    return movemask(rays.active & span.valid & (span.exit > vfloat4(0.0f)) & (span.enter < limit));
}

// The outward normal at a hit, not yet of unit length for spheres and cylinder sides (finish()
// normalises those four lanes at once).
Vec3 outward_direction(const LeafInfo& leaf, std::int32_t tag, Vec3 point, bool& needs_normalizing) {
    Vec3 normal;
    std::int32_t face = tag & tag_face_mask;
    needs_normalizing = false;
    switch (leaf.kind) {
        case LeafKind::plane: normal = leaf.direction; break;
        case LeafKind::sphere:
            normal = point - leaf.position;
            needs_normalizing = true;
            break;
        case LeafKind::box: {
            float sign = (face & 1) ? 1.0f : -1.0f;
            int axis = face >> 1;
            normal = {axis == 0 ? sign : 0.0f, axis == 1 ? sign : 0.0f, axis == 2 ? sign : 0.0f};
            break;
        }
        case LeafKind::cylinder:
            if (face == cylinder_side) {
                Vec3 w = point - leaf.position;
                normal = w - dot(w, leaf.direction) * leaf.direction;
                needs_normalizing = true;
            } else {
                normal = face == cylinder_top_cap ? leaf.direction : -leaf.direction;
            }
            break;
    }
    return (tag & tag_flipped) ? -normal : normal;
}

// γ(n) = n·u/(1 − n·u), u = ε/2: the bound on the relative error of n rounded float operations.
constexpr float rounding_bound(int n) {
    constexpr float u = std::numeric_limits<float>::epsilon() / 2;
    return static_cast<float>(n) * u / (1.0f - static_cast<float>(n) * u);
}

// Where a hit point is re-projected onto its primitive: p' = anchor + radius·n̂ with n̂ the unit outward
// normal as outward_direction turns it (radius 0 on flat faces, where the anchor is p' itself), only
// where p is farther than `own_rounding` from p' (measurably off the surface); and the offset its
// secondary rays start at: size_bound + point_factor·|p'|∞. The same formulas and bounds as the
// reference's surface_point (reference/sphere.h, plane.h, cylinder.h, box.h; the derivations are there),
// so both tracers leave surfaces alike.
struct SurfaceAnchor {
    Vec3 anchor;
    float radius = 0;
    float own_rounding = 0;
    float size_bound = 0;
    float point_factor = 0;
};

SurfaceAnchor surface_anchor(const LeafInfo& leaf, std::int32_t tag, Vec3 point) {
    std::int32_t face = tag & tag_face_mask;
    float turned = (tag & tag_flipped) ? -1.0f : 1.0f;  // outward_direction turned n̂: turn the radius too
    switch (leaf.kind) {
        case LeafKind::plane: {
            Vec3 projected = point + (leaf.offset - dot(leaf.direction, point)) * leaf.direction;
            float own_rounding =
                rounding_bound(2) * max_abs_component(point) + rounding_bound(1) * std::fabs(leaf.offset);
            return {projected, 0.0f, own_rounding, rounding_bound(2) * std::fabs(leaf.offset), rounding_bound(15)};
        }
        case LeafKind::sphere: {
            float own_rounding = rounding_bound(5) * leaf.radius + rounding_bound(2) * max_abs_component(point);
            return {leaf.position, turned * leaf.radius, own_rounding, rounding_bound(9) * leaf.radius,
                    rounding_bound(4)};
        }
        case LeafKind::box: {
            int axis = face >> 1;
            float coordinates[3] = {point.x, point.y, point.z};
            coordinates[axis] = (face & 1) ? leaf.far_corner[axis] : leaf.position[axis];
            return {{coordinates[0], coordinates[1], coordinates[2]}, 0.0f, 0.0f, 0.0f, rounding_bound(3)};
        }
        case LeafKind::cylinder: {
            float axial = dot(point - leaf.position, leaf.direction);
            float size_bound = rounding_bound(12) * (leaf.radius + leaf.height);
            float own_rounding =
                rounding_bound(5) * (leaf.radius + leaf.height) + rounding_bound(2) * max_abs_component(point);
            if (face == cylinder_side) {
                return {leaf.position + axial * leaf.direction, turned * leaf.radius, own_rounding, size_bound,
                        rounding_bound(4)};
            }
            float cap_axial = face == cylinder_top_cap ? leaf.height : 0.0f;
            return {point - (axial - cap_axial) * leaf.direction, 0.0f, own_rounding, size_bound, rounding_bound(4)};
        }
    }
    return {point};
}

struct Hit4 {
    vbool4 hit;  // active lanes whose ray met a surface
    vfloat4 t;
    Vec4 point;   // re-projected onto the primitive's surface
    Vec4 normal;  // unit, facing the ray
    vint4 leaf;
    vbool4 entering;
    vfloat4 spawn_offset;  // how far off the surface secondary rays start
};

// The material of each lane's hit, gathered once per hit.
struct Material4 {
    Color4 color;
    vfloat4 ambient, diffuse, phong, phong_size, reflection, transmission, ior;
};

// The reference's rule (docs/reference-tracer.md): start off the surface on the side the ray leaves to,
// by the hit's spawn_offset (SurfaceAnchor).
Vec4 spawn_origin(const Hit4& hit, const Vec4& direction) {
    vfloat4 side = select(dot(direction, hit.normal) >= vfloat4(0.0f), vfloat4(1.0f), vfloat4(-1.0f));
    return hit.point + (side * hit.spawn_offset) * hit.normal;
}

// Recording the ray tree (twinray probe) of lane 0, where the per-ray API runs its one ray. The tracing
// code calls these only when it has a tree (one null test); they are cold, out of the packets' way.
inline Vec3d lane0(const Vec4& v) {
    return {static_cast<double>(v.x.lane(0)), static_cast<double>(v.y.lane(0)), static_cast<double>(v.z.lane(0))};
}

// The node of lane 0's ray, or -1 when lane 0 is not active (then nothing below it is recorded).
[[gnu::cold]] int record_ray(RayTree& tree, RayKind kind, int depth, int parent, const RayPacket& rays,
                             const Hit4& hit) {
    if ((movemask(rays.active) & 1) == 0) {
        return -1;
    }
    int index = tree.add(kind, depth, parent, lane0({rays.origin[0], rays.origin[1], rays.origin[2]}),
                         lane0({rays.direction[0], rays.direction[1], rays.direction[2]}));
    RayNode& node = tree.nodes[static_cast<std::size_t>(index)];
    if (movemask(hit.hit) & 1) {
        alignas(16) std::int32_t leaf[4];
        hit.leaf.store(leaf);
        node.hit = true;
        node.leaf = leaf[0];
        node.t = static_cast<double>(hit.t.lane(0));
        node.point = lane0(hit.point);
        node.normal = lane0(hit.normal);
        node.entering = (movemask(hit.entering) & 1) != 0;
    }
    return index;
}

// Lane 0's light: facing away (not in `lit`: no shadow ray), else its shadow ray and transmittance.
template <typename P>
[[gnu::cold]] void record_light(RayTree& tree, int node, vfloat4 lambert, vbool4 lit, const Vec4& shadow_origin,
                                Vec3 light_position, vfloat4 transmittance) {
    if (node < 0) {
        return;
    }
    LightVisibility light{static_cast<double>(lambert.lane(0)), true, 0, {}, {}};
    if (movemask(lit) & 1) {
        light.faces_away = false;
        light.transmittance = static_cast<double>(transmittance.lane(0));
        light.shadow_origin = lane0(shadow_origin);
        light.shadow_direction = lane0(normalize<P>(broadcast(light_position) - shadow_origin));
    }
    tree.nodes[static_cast<std::size_t>(node)].lights.push_back(light);
}

[[gnu::cold]] void record_light_facing_away(RayTree& tree, int node, vfloat4 lambert) {
    if (node >= 0) {
        tree.nodes[static_cast<std::size_t>(node)].lights.push_back(
            {static_cast<double>(lambert.lane(0)), true, 0, {}, {}});
    }
}

[[gnu::cold]] void record_local_color(RayTree& tree, int node, const Color4& color) {
    if (node >= 0) {
        tree.nodes[static_cast<std::size_t>(node)].local = lane0(color);
    }
}

// On a miss the background is both the local and the total colour.
[[gnu::cold]] void record_total_color(RayTree& tree, int node, const Color4& color) {
    if (node >= 0) {
        RayNode& n = tree.nodes[static_cast<std::size_t>(node)];
        n.total = lane0(color);
        if (!n.hit) {
            n.local = n.total;
        }
    }
}

template <typename P>
class PacketTracer {
public:
    explicit PacketTracer(const CompiledScene& scene) : scene_(scene) {}

    // `candidates` are the top-level primitives that can be hit: all of them, or for primary rays the
    // ones a tile can see (TileCulling).
    Hit4 intersect(RayPacket& rays, const PrimitiveLists& candidates) const {
        if (scene_.any_box_test) {
            rays.template compute_inverse_direction<P>();
        }
        Nearest4 nearest;
        for_each_span<P>(candidates, rays,
                         [&](const Span4& span, std::int32_t leaf, float) { keep_nearest(nearest, span, leaf); });
        if (!scene_.csg_objects.empty()) {
            nearest_csg_crossings(rays, nearest);
        }
        return finish(rays, nearest);
    }

    Hit4 intersect(RayPacket& rays) const { return intersect(rays, scene_.primitives); }

    // `tree`, if given, records lane 0's ray as a `kind` child of node `parent`, and all it spawns.
    Color4 trace(RayPacket& rays, int depth, std::uint64_t& ray_count, RayTree* tree = nullptr,
                 RayKind kind = RayKind::primary, int parent = -1) const {
        return trace(rays, scene_.primitives, depth, ray_count, tree, kind, parent);
    }

    Color4 trace(RayPacket& rays, const PrimitiveLists& candidates, int depth, std::uint64_t& ray_count,
                 RayTree* tree = nullptr, RayKind kind = RayKind::primary, int parent = -1) const {
        ray_count += lane_count(rays.active);
        Hit4 hit = intersect(rays, candidates);
        int node = tree != nullptr ? record_ray(*tree, kind, depth, parent, rays, hit) : -1;
        Color4 background = broadcast(scene_.background);
        if (none(hit.hit)) {
            if (tree != nullptr) {
                record_total_color(*tree, node, background);
            }
            return background;
        }
        Color4 color = select(hit.hit, shade(rays, hit, depth, ray_count, tree, node), background);
        if (tree != nullptr) {
            record_total_color(*tree, node, color);
        }
        return color;
    }

private:
    // Per lane: CSG objects whose bound the ray meets before its nearest hit so far.
    void nearest_csg_crossings(const RayPacket& rays, Nearest4& nearest) const {
        alignas(16) float t[4];
        alignas(16) std::int32_t leaf[4], tag[4];
        nearest.t.store(t);
        nearest.leaf.store(leaf);
        nearest.tag.store(tag);
        for (const CsgObject& object : scene_.csg_objects) {
            int lanes = lanes_meeting_bound<P>(object, rays, vfloat4::load(t));
            if (lanes == 0) {
                continue;
            }
            CsgEvaluation<P> evaluation(object, rays);
            for (int lane = 0; lane < 4; ++lane) {
                if (((lanes >> lane) & 1) == 0) {
                    continue;
                }
                SpanArray spans;
                evaluation.evaluate(lane, spans);
                for (int i = 0; i < spans.count; ++i) {
                    bool entering = spans.enter[i].t > 0.0f;
                    const Crossing& crossing = entering ? spans.enter[i] : spans.exit[i];
                    if (!(crossing.t > 0.0f)) {
                        continue;
                    }
                    if (crossing.leaf >= 0 &&
                        (crossing.t < t[lane] || (crossing.t == t[lane] && crossing.leaf < leaf[lane]))) {
                        t[lane] = crossing.t;
                        leaf[lane] = crossing.leaf;
                        tag[lane] = crossing.tag | (entering ? tag_entering : 0);
                    }
                    break;
                }
            }
        }
        nearest.t = vfloat4::load(t);
        nearest.leaf = vint4::load(leaf);
        nearest.tag = vint4::load(tag);
    }

    Hit4 finish(const RayPacket& rays, const Nearest4& nearest) const {
        Hit4 hit;
        hit.hit = rays.active & !(nearest.leaf == vint4(-1));
        if (none(hit.hit)) {
            return hit;
        }
        hit.t = nearest.t;
        Vec4 direction{rays.direction[0], rays.direction[1], rays.direction[2]};
        hit.point = Vec4{rays.origin[0], rays.origin[1], rays.origin[2]} + hit.t * direction;
        hit.leaf = nearest.leaf;
        hit.entering = {
            _mm_castsi128_ps(_mm_cmpeq_epi32((nearest.tag & vint4(tag_entering)).m, vint4(tag_entering).m))};
        alignas(16) float point[3][4], normal[3][4], anchor[3][4], radius[4], own_rounding[4], size_bound[4],
            point_factor[4];
        alignas(16) std::int32_t leaf[4], tag[4], curved[4];
        hit.point.x.store(point[0]);
        hit.point.y.store(point[1]);
        hit.point.z.store(point[2]);
        nearest.leaf.store(leaf);
        nearest.tag.store(tag);
        int lanes = movemask(hit.hit);
        for (int lane = 0; lane < 4; ++lane) {
            Vec3 outward{0.0f, 0.0f, 1.0f};
            bool needs_normalizing = false;
            SurfaceAnchor surface;
            if ((lanes >> lane) & 1) {
                const LeafInfo& info = scene_.leaves[static_cast<std::size_t>(leaf[lane])];
                Vec3 p{point[0][lane], point[1][lane], point[2][lane]};
                outward = outward_direction(info, tag[lane], p, needs_normalizing);
                surface = surface_anchor(info, tag[lane], p);
            }
            normal[0][lane] = outward.x;
            normal[1][lane] = outward.y;
            normal[2][lane] = outward.z;
            curved[lane] = needs_normalizing ? -1 : 0;
            anchor[0][lane] = surface.anchor.x;
            anchor[1][lane] = surface.anchor.y;
            anchor[2][lane] = surface.anchor.z;
            radius[lane] = surface.radius;
            own_rounding[lane] = surface.own_rounding;
            size_bound[lane] = surface.size_bound;
            point_factor[lane] = surface.point_factor;
        }
        Vec4 outward{vfloat4::load(normal[0]), vfloat4::load(normal[1]), vfloat4::load(normal[2])};
        vbool4 normalize_lanes{_mm_castsi128_ps(vint4::load(curved).m)};
        if (any(normalize_lanes)) {
            // As the reference's radial_normal: a radial vector of exactly zero (a primitive smaller than
            // the ulp where it stands) has no direction; the ray's reverse stands in for it, not a NaN.
            vbool4 degenerate = dot<P>(outward, outward) == vfloat4(0.0f);
            outward = select(normalize_lanes, normalize<P>(select(degenerate, -direction, outward)), outward);
        }
        // Re-projected onto the surface where measurably off it: p is |n̂·(p − anchor)| from the anchor
        // along n̂ and p' is |radius| (0 on flat faces, whose anchor is p' itself).
        Vec4 anchors{vfloat4::load(anchor[0]), vfloat4::load(anchor[1]), vfloat4::load(anchor[2])};
        vfloat4 radii = vfloat4::load(radius);
        vfloat4 off_surface = abs(abs(dot<P>(outward, hit.point - anchors)) - abs(radii));
        hit.point = select(off_surface > vfloat4::load(own_rounding), anchors + radii * outward, hit.point);
        vfloat4 largest = max(abs(hit.point.x), max(abs(hit.point.y), abs(hit.point.z)));
        hit.spawn_offset = vfloat4::load(size_bound) + vfloat4::load(point_factor) * largest;
        hit.normal = select(dot<P>(outward, direction) > vfloat4(0.0f), -outward, outward);
        return hit;
    }

    Material4 gather_material(const Hit4& hit) const {
        alignas(16) std::int32_t leaf[4];
        hit.leaf.store(leaf);
        int lanes = movemask(hit.hit);
        float values[10][4] = {};
        for (int lane = 0; lane < 4; ++lane) {
            if (((lanes >> lane) & 1) == 0) {
                continue;
            }
            const LeafInfo& info = scene_.leaves[static_cast<std::size_t>(leaf[lane])];
            const MaterialF& m = scene_.materials[static_cast<std::size_t>(info.material)];
            const float fields[10] = {m.color.x, m.color.y,    m.color.z,    m.ambient,      m.diffuse,
                                      m.phong,   m.phong_size, m.reflection, m.transmission, m.ior};
            for (int field = 0; field < 10; ++field) {
                values[field][lane] = fields[field];
            }
        }
        return {{from_lanes(values[0]), from_lanes(values[1]), from_lanes(values[2])},
                from_lanes(values[3]),
                from_lanes(values[4]),
                from_lanes(values[5]),
                from_lanes(values[6]),
                from_lanes(values[7]),
                from_lanes(values[8]),
                from_lanes(values[9])};
    }

    // Per lane, the product of the transmission of every surface crossed strictly between origin and
    // light; lanes outside `lanes` get 0.
    vfloat4 shadow_transmittance(const Vec4& origin, Vec3 light_position, vbool4 lanes) const {
        Vec4 to_light = broadcast(light_position) - origin;
        vfloat4 squared_distance = dot<P>(to_light, to_light);
        vfloat4 inverse_distance = inverse_sqrt<P>(squared_distance);
        vfloat4 distance = P::fast_rsqrt ? squared_distance * inverse_distance : sqrt(squared_distance);
        Vec4 direction = inverse_distance * to_light;
        const vfloat4 origins[3] = {origin.x, origin.y, origin.z};
        const vfloat4 directions[3] = {direction.x, direction.y, direction.z};
        RayPacket rays(origins, directions, lanes);
        if (scene_.any_box_test) {
            rays.template compute_inverse_direction<P>();
        }
        vfloat4 zero(0.0f), one(1.0f);
        vfloat4 transmittance = select(lanes, one, zero);
        vbool4 open = lanes;  // lanes not yet fully blocked
        auto crossings_between = [&](const Span4& span, vbool4& enter_between, vbool4& exit_between) {
            enter_between = span.valid & (span.enter > zero) & (span.enter < distance);
            exit_between = span.valid & (span.exit > zero) & (span.exit < distance);
        };
        if (!scene_.any_transparency) {
            for_each_span<P>(scene_.primitives, rays, [&](const Span4& span, std::int32_t, float) {
                if (none(open)) {
                    return;
                }
                vbool4 enter_between, exit_between;
                crossings_between(span, enter_between, exit_between);
                open = open & !(enter_between | exit_between);
            });
        } else {
            for_each_span<P>(scene_.primitives, rays, [&](const Span4& span, std::int32_t, float transmission) {
                vbool4 enter_between, exit_between;
                crossings_between(span, enter_between, exit_between);
                vfloat4 surface(transmission);
                transmittance =
                    transmittance * select(enter_between, surface, one) * select(exit_between, surface, one);
            });
            open = open & (transmittance > zero);
        }
        transmittance = select(open, transmittance, zero);
        if (scene_.csg_objects.empty() || none(open)) {
            return transmittance;
        }
        alignas(16) float product[4];
        transmittance.store(product);
        for (const CsgObject& object : scene_.csg_objects) {
            int met = lanes_meeting_bound<P>(object, rays, distance) & movemask(open);
            if (met == 0) {
                continue;
            }
            CsgEvaluation<P> evaluation(object, rays);
            alignas(16) float limit[4];
            distance.store(limit);
            for (int lane = 0; lane < 4; ++lane) {
                if (((met >> lane) & 1) == 0 || product[lane] == 0.0f) {
                    continue;
                }
                SpanArray spans;
                evaluation.evaluate(lane, spans);
                for (int i = 0; i < spans.count; ++i) {
                    for (const Crossing* crossing : {&spans.enter[i], &spans.exit[i]}) {
                        if (crossing->leaf >= 0 && crossing->t > 0.0f && crossing->t < limit[lane]) {
                            product[lane] *= material_transmission(crossing->leaf);
                        }
                    }
                }
            }
        }
        return vfloat4::load(product);
    }

    float material_transmission(std::int32_t leaf) const {
        const LeafInfo& info = scene_.leaves[static_cast<std::size_t>(leaf)];
        return scene_.materials[static_cast<std::size_t>(info.material)].transmission;
    }

    // max(0, R·L)^phong_size per lane; the power is scalar (SSE has none), computed only where needed.
    static vfloat4 phong_power(vfloat4 cosine, vfloat4 exponent, vbool4 lanes) {
        alignas(16) float base[4], power[4], result[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        max(vfloat4(0.0f), cosine).store(base);
        exponent.store(power);
        int mask = movemask(lanes);
        for (int lane = 0; lane < 4; ++lane) {
            if ((mask >> lane) & 1) {
                result[lane] = std::pow(base[lane], power[lane]);
            }
        }
        return vfloat4::load(result);
    }

    // I = ambient·C·ambient_light + Σ_lights shadow·(diffuse·C·Lc·(N·L) + phong·Lc·max(0, R·L)^phong_size)
    //   + reflection·I(reflected) + transmission·I(refracted)          (SCENES.md, "Shading")
    // `node`: lane 0's ray in `tree`, if recording.
    Color4 shade(const RayPacket& rays, const Hit4& hit, int depth, std::uint64_t& ray_count, RayTree* tree,
                 int node) const {
        Material4 m = gather_material(hit);
        vfloat4 zero(0.0f);
        Vec4 direction{rays.direction[0], rays.direction[1], rays.direction[2]};
        Color4 color = m.ambient * (m.color * broadcast(scene_.ambient_light));
        Vec4 mirror = direction - (vfloat4(2.0f) * dot<P>(direction, hit.normal)) * hit.normal;
        vbool4 has_phong = hit.hit & (m.phong > zero);
        for (const LightF& light : scene_.lights) {
            Vec4 to_light = normalize<P>(broadcast(light.position) - hit.point);
            vfloat4 lambert = dot<P>(hit.normal, to_light);
            vbool4 lit = hit.hit & (lambert > zero);
            if (none(lit)) {
                if (tree != nullptr) {
                    record_light_facing_away(*tree, node, lambert);
                }
                continue;
            }
            ray_count += lane_count(lit);
            vfloat4 shadow = shadow_transmittance(spawn_origin(hit, to_light), light.position, lit);
            if (tree != nullptr) {
                record_light<P>(*tree, node, lambert, lit, spawn_origin(hit, to_light), light.position, shadow);
            }
            vbool4 reached = lit & (shadow > zero);
            if (none(reached)) {
                continue;
            }
            Color4 light_color = broadcast(light.color);
            Color4 diffuse = (m.diffuse * lambert) * (m.color * light_color);
            vfloat4 highlight = zero;
            if (any(has_phong & reached)) {
                highlight = m.phong * phong_power(dot<P>(mirror, to_light), m.phong_size, has_phong & reached);
            }
            color = select(reached, color + shadow * (diffuse + highlight * light_color), color);
        }
        if (tree != nullptr) {
            record_local_color(*tree, node, color);
        }
        if (depth >= scene_.max_depth) {
            return color;
        }
        vfloat4 reflection = select(hit.hit, m.reflection, zero);
        vbool4 transparent = hit.hit & (m.transmission > zero);
        if (scene_.any_transparency && any(transparent)) {
            vfloat4 eta = select(hit.entering, reciprocal<P>(m.ior), m.ior);
            vfloat4 cos_incident = -dot<P>(direction, hit.normal);
            vfloat4 sin2_transmitted = eta * eta * (vfloat4(1.0f) - cos_incident * cos_incident);
            vbool4 total_internal = transparent & (sin2_transmitted > vfloat4(1.0f));
            vbool4 refracting = transparent & !total_internal;
            reflection = reflection + select(total_internal, m.transmission, zero);
            if (any(refracting)) {
                vfloat4 cos_transmitted = sqrt(max(vfloat4(1.0f) - sin2_transmitted, zero));
                Vec4 refracted = normalize<P>(eta * direction + (eta * cos_incident - cos_transmitted) * hit.normal);
                color = color + select(refracting, m.transmission, zero) * trace_secondary(hit, refracted, refracting,
                                                                                           depth, ray_count, tree,
                                                                                           RayKind::refracted, node);
            }
        }
        vbool4 reflecting = reflection > zero;
        if (any(reflecting)) {
            color = color + reflection * trace_secondary(hit, mirror, reflecting, depth, ray_count, tree,
                                                         RayKind::reflected, node);
        }
        return color;
    }

    Color4 trace_secondary(const Hit4& hit, const Vec4& direction, vbool4 lanes, int depth, std::uint64_t& ray_count,
                           RayTree* tree, RayKind kind, int parent) const {
        Vec4 origin = spawn_origin(hit, direction);
        const vfloat4 origins[3] = {origin.x, origin.y, origin.z};
        const vfloat4 directions[3] = {direction.x, direction.y, direction.z};
        RayPacket rays(origins, directions, lanes);
        Color4 color = trace(rays, depth + 1, ray_count, tree, kind, parent);
        return select(lanes, color, Color4{vfloat4(0.0f), vfloat4(0.0f), vfloat4(0.0f)});
    }

    const CompiledScene& scene_;
};

// A single ray through the packet path: all four lanes carry it, only lane 0 is active.
RayPacket single_ray_packet(const Ray& ray) {
    const Ray rays[4] = {ray, ray, ray, ray};
    return RayPacket(rays, vbool4{_mm_castsi128_ps(_mm_setr_epi32(-1, 0, 0, 0))});
}

// The reference's camera (reference/tracer.cpp) in float, set up once per image size: the pixel
// centre (px, py) maps to u = (px·2/W − 1)·tan(fov/2) and v = (1 − py·2/H)·tan(fov/2)·H/W, with the
// two divisions hoisted out of the per-pixel work.
struct CameraPacket {
    Vec4 eye, forward, right, up;
    vfloat4 u_per_pixel, v_per_pixel, half_width, half_height;

    CameraPacket(const CompiledScene& s, int width, int height)
        : eye(broadcast(s.eye)),
          forward(broadcast(s.forward)),
          right(broadcast(s.right)),
          up(broadcast(s.up)),
          u_per_pixel(2.0f / static_cast<float>(width)),
          v_per_pixel(2.0f / static_cast<float>(height)),
          half_width(s.half_width),
          half_height(s.half_width * static_cast<float>(height) / static_cast<float>(width)) {}

    // The 2 × 2 pixels whose top-left is (x, y): lane i is pixel (x + i % 2, y + i / 2). Every lane is
    // computed alone, so a pixel's ray is the same in any packet.
    template <typename P>
    RayPacket rays(int x, int y, vbool4 active) const {
        vfloat4 px = vfloat4(static_cast<float>(x)) + vfloat4(_mm_setr_ps(0.5f, 1.5f, 0.5f, 1.5f));
        vfloat4 py = vfloat4(static_cast<float>(y)) + vfloat4(_mm_setr_ps(0.5f, 0.5f, 1.5f, 1.5f));
        vfloat4 u = (px * u_per_pixel - vfloat4(1.0f)) * half_width;
        vfloat4 v = (vfloat4(1.0f) - py * v_per_pixel) * half_height;
        Vec4 direction = normalize<P>(forward + u * right + v * up);
        const vfloat4 origins[3] = {eye.x, eye.y, eye.z};
        const vfloat4 directions[3] = {direction.x, direction.y, direction.z};
        return RayPacket(origins, directions, active);
    }
};

// Primary rays of one tile all start at the eye and pass through the tile's rectangle on the image
// plane: a pyramid. A primitive whose bounding sphere lies wholly outside one of its four side planes
// cannot be hit by any of them, so the tile's packets test only the rest. This is exact, not an
// approximation: the planes are moved out by a margin far beyond float rounding (1e-4 of the distance),
// so no primitive a ray could hit is ever dropped, and the image is the same as without culling.
// Secondary and shadow rays go everywhere and test every primitive.
class TileCulling {
public:
    TileCulling(const CompiledScene& scene, int width, int height) : scene_(scene), width_(width), height_(height) {}

    // The primitives visible in the pixels [x0, x1) × [y0, y1), written into `visible` (reused
    // storage: no allocation once it has grown).
    void select(int x0, int y0, int x1, int y1, PrimitiveLists& visible) const {
        std::array<Direction, 4> corners = {corner(x0, y0), corner(x1, y0), corner(x1, y1), corner(x0, y1)};
        std::array<Direction, 4> normals;
        Direction centre{0, 0, 0};  // inside the pyramid: orients each side plane's normal inward
        for (const Direction& c : corners) {
            for (int axis = 0; axis < 3; ++axis)
                centre[axis] += c[axis];
        }
        for (int i = 0; i < 4; ++i) {
            normals[i] = cross(corners[i], corners[(i + 1) % 4]);
            double length = std::sqrt(dot(normals[i], normals[i]));
            double inward = dot(normals[i], centre) < 0 ? -1.0 : 1.0;
            for (double& c : normals[i])
                c *= inward / length;
        }
        keep_visible(scene_.primitives.planes, normals, visible.planes);
        keep_visible(scene_.primitives.spheres, normals, visible.spheres);
        keep_visible(scene_.primitives.cylinders, normals, visible.cylinders);
        keep_visible(scene_.primitives.boxes, normals, visible.boxes);
    }

private:
    using Direction = std::array<double, 3>;

    static double dot(const Direction& a, const Direction& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
    static Direction cross(const Direction& a, const Direction& b) {
        return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    }

    // The direction through pixel corner (x, y) of the image plane (pixel edges, not centres).
    Direction corner(int x, int y) const {
        double half_height = static_cast<double>(scene_.half_width) * height_ / width_;
        double u = (2.0 * x / width_ - 1.0) * scene_.half_width;
        double v = (1.0 - 2.0 * y / height_) * half_height;
        const Vec3& f = scene_.forward;
        const Vec3& r = scene_.right;
        const Vec3& up = scene_.up;
        return {f.x + u * r.x + v * up.x, f.y + u * r.y + v * up.y, f.z + u * r.z + v * up.z};
    }

    template <typename Primitive>
    void keep_visible(const PrimitiveList<Primitive>& all, const std::array<Direction, 4>& normals,
                      PrimitiveList<Primitive>& visible) const {
        visible.clear();
        for (std::size_t i = 0; i < all.items.size(); ++i) {
            const scene::Vec3& center = all.bound_centers[i];
            double radius = all.bound_radii[i];
            Direction offset{center[0] - scene_.eye.x, center[1] - scene_.eye.y, center[2] - scene_.eye.z};
            double margin = radius + 1e-4 * (std::sqrt(dot(offset, offset)) + radius);
            bool outside = false;
            for (const Direction& normal : normals) {
                outside = outside || dot(normal, offset) < -margin;
            }
            if (!outside) {
                visible.push_back_from(all, i);
            }
        }
    }

    const CompiledScene& scene_;
    int width_, height_;
};

constexpr int tile = 16;

// Hands out the image's 16 × 16 tiles to the worker threads and calls
// work(x0, y0, x1, y1, visible) for the pixels [x0, x1) × [y0, y1) with the primitives the tile can see
// (TileCulling); sums what it returns. The denormal mode is set per tile, on whichever thread runs it,
// and restored after: the workers are the shared render loop's, and the calling thread is one of them.
template <typename TileWork>
std::uint64_t for_each_tile(const CompiledScene& scene, scene::ImageSize size, const RenderOptions& options,
                            bool flush_denormals, TileWork&& work) {
    TileCulling culling(scene, size.width, size.height);
    int tiles_x = (size.width + tile - 1) / tile;
    int tiles_y = (size.height + tile - 1) / tile;
    return parallel_for(
        tiles_x * tiles_y, options.threads,
        [&](int index) {
            ScopedFlushDenormals denormals(flush_denormals);
            int x0 = (index % tiles_x) * tile;
            int y0 = (index / tiles_x) * tile;
            int x1 = std::min(x0 + tile, size.width);
            int y1 = std::min(y0 + tile, size.height);
            thread_local PrimitiveLists visible;
            culling.select(x0, y0, x1, y1, visible);
            return work(x0, y0, x1, y1, static_cast<const PrimitiveLists&>(visible));
        },
        options.progress, options.cancel);
}

// Calls per_packet(x, y, active) for each 2 × 2 packet of the pixels [x0, x1) × [y0, y1), (x, y) its
// top-left pixel; lanes past the edge are inactive.
template <typename PerPacket>
void for_each_packet(int x0, int y0, int x1, int y1, PerPacket&& per_packet) {
    for (int y = y0; y < y1; y += 2) {
        for (int x = x0; x < x1; x += 2) {
            vbool4 active{_mm_castsi128_ps(
                _mm_setr_epi32(-1, x + 1 < x1 ? -1 : 0, y + 1 < y1 ? -1 : 0, x + 1 < x1 && y + 1 < y1 ? -1 : 0))};
            per_packet(x, y, active);
        }
    }
}

int knob_bits(const Precision& precision) {
    return (precision.fast_rcp ? 1 : 0) | (precision.fast_rsqrt ? 2 : 0) | (precision.dpps ? 4 : 0) |
           (precision.textbook_quadratic ? 8 : 0);
}

// The kernels compiled in, one instantiation each: exact, each knob alone, and the three that buy speed
// together (rcp, rsqrt, textbook; dpps costs time in a packet tracer, docs/performance.md). Calls
// visit(policy) with the policy type of `precision`'s knobs; every other combination is refused.
template <typename Visit>
decltype(auto) with_kernels(const Precision& precision, Visit&& visit) {
    switch (knob_bits(precision)) {
        case 0: return visit(ExactKernels{});
        case 1: return visit(Kernels<true, false, false, false>{});
        case 2: return visit(Kernels<false, true, false, false>{});
        case 4: return visit(Kernels<false, false, true, false>{});
        case 8: return visit(Kernels<false, false, false, true>{});
        case 11: return visit(Kernels<true, true, false, true>{});
        default:
            throw std::invalid_argument("the SSE tracer is not built for the knobs " + precision_name(precision) +
                                        "; built: " + built_precisions());
    }
}

}  // namespace

bool precision_is_built(const Precision& precision) {
    int knobs = knob_bits(precision);
    return knobs == 0 || knobs == 1 || knobs == 2 || knobs == 4 || knobs == 8 || knobs == 11;
}

std::string built_precisions() {
    return "exact, rcp, rsqrt, dpps, textbook, rcp+rsqrt+textbook (each also with ftz)";
}

std::string precision_name(const Precision& precision) {
    std::string name;
    auto add = [&](bool on, const char* knob) {
        if (on) {
            name += (name.empty() ? "" : "+") + std::string(knob);
        }
    };
    add(precision.fast_rcp, "rcp");
    add(precision.fast_rsqrt, "rsqrt");
    add(precision.dpps, "dpps");
    add(precision.textbook_quadratic, "textbook");
    add(precision.flush_denormals, "ftz");
    return name.empty() ? "exact" : name;
}

Tracer::Tracer(const scene::Scene& scene, const Precision& precision)
    : scene_(std::make_unique<CompiledScene>(compile(scene))), precision_(precision) {
    with_kernels(precision, [](auto) {});  // refuses a combination that is not built
}

Tracer::~Tracer() = default;

bool is_traceable(const Ray& ray) {
    const Vec3& o = ray.origin;
    const Vec3& d = ray.direction;
    bool finite = std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z) && std::isfinite(d.x) &&
                  std::isfinite(d.y) && std::isfinite(d.z);
    return finite && std::fabs(dot(d, d) - 1.0f) <= 1e-3f;
}

std::optional<Hit> Tracer::intersect(const Ray& ray) const {
    if (!is_traceable(ray)) {
        return std::nullopt;
    }
    ScopedFlushDenormals denormals(precision_.flush_denormals);
    Hit4 hit4 = with_kernels(precision_, [&](auto kernels) {
        RayPacket rays = single_ray_packet(ray);
        return PacketTracer<decltype(kernels)>(*scene_).intersect(rays);
    });
    if (!(movemask(hit4.hit) & 1)) {
        return std::nullopt;
    }
    Hit hit;
    hit.t = hit4.t.lane(0);
    hit.point = {hit4.point.x.lane(0), hit4.point.y.lane(0), hit4.point.z.lane(0)};
    hit.normal = {hit4.normal.x.lane(0), hit4.normal.y.lane(0), hit4.normal.z.lane(0)};
    alignas(16) std::int32_t leaf[4];
    hit4.leaf.store(leaf);
    hit.leaf = leaf[0];
    hit.entering = (movemask(hit4.entering) & 1) != 0;
    hit.spawn_offset = hit4.spawn_offset.lane(0);
    return hit;
}

Color Tracer::trace(const Ray& ray, int depth, std::uint64_t* rays, RayTree* tree) const {
    if (!is_traceable(ray)) {
        return scene_->background;
    }
    ScopedFlushDenormals denormals(precision_.flush_denormals);
    std::uint64_t count = 0;
    Color4 color = with_kernels(precision_, [&](auto kernels) {
        RayPacket packet = single_ray_packet(ray);
        return PacketTracer<decltype(kernels)>(*scene_).trace(packet, depth, count, tree);
    });
    if (rays != nullptr) {
        *rays += count;
    }
    return {color.x.lane(0), color.y.lane(0), color.z.lane(0)};
}

Ray Tracer::primary_ray(int x, int y, int width, int height) const {
    RayPacket packet = with_kernels(precision_, [&](auto kernels) {
        return CameraPacket(*scene_, width, height)
            .template rays<decltype(kernels)>(x, y, vbool4{_mm_castsi128_ps(_mm_setr_epi32(-1, 0, 0, 0))});
    });
    return {{packet.origin[0].lane(0), packet.origin[1].lane(0), packet.origin[2].lane(0)},
            {packet.direction[0].lane(0), packet.direction[1].lane(0), packet.direction[2].lane(0)}};
}

// Tiles of 16 × 16 pixels are handed to worker threads; within a tile, 2 × 2 pixels make a packet
// (coherent rays: they meet the same primitives). Each lane is computed alone, so the image is
// bit-identical for any thread count and equals the per-ray API's trace() of each pixel. A tile is
// rendered into a buffer of its own and copied into the image row by row when done: consecutive tiles
// run on different threads and share cache lines at their borders, which per-pixel writes would pass
// back and forth between the cores.
RenderResult render(const scene::Scene& scene, const RenderOptions& options) {
    return render(scene, options, {});
}

RenderResult render(const scene::Scene& scene, const RenderOptions& options, const Precision& precision) {
    scene::ImageSize size = scene::resolve_image_size(scene, options.width, options.height);
    Tracer tracer(scene, precision);
    Image image(size.width, size.height);
    std::uint64_t ray_count = with_kernels(precision, [&](auto kernels) {
        using P = decltype(kernels);
        PacketTracer<P> packets(tracer.compiled());
        CameraPacket camera(tracer.compiled(), size.width, size.height);
        return for_each_tile(
            tracer.compiled(), size, options, precision.flush_denormals,
            [&](int x0, int y0, int x1, int y1, const PrimitiveLists& visible) {
                std::uint64_t tile_rays = 0;
                Rgb pixels[tile][tile];
                for_each_packet(x0, y0, x1, y1, [&](int x, int y, vbool4 active) {
                    RayPacket packet = camera.template rays<P>(x, y, active);
                    Color4 color = packets.trace(packet, visible, 1, tile_rays);
                    alignas(16) float r[4], g[4], b[4];
                    color.x.store(r);
                    color.y.store(g);
                    color.z.store(b);
                    // Buffer rows and columns past the image's edge are written but never copied.
                    for (int lane = 0; lane < 4; ++lane) {
                        pixels[y - y0 + (lane >> 1)][x - x0 + (lane & 1)] = {r[lane], g[lane], b[lane]};
                    }
                });
                for (int y = y0; y < y1; ++y) {
                    std::copy(pixels[y - y0], pixels[y - y0] + (x1 - x0), &image.at(x0, y));
                }
                return tile_rays;
            });
    });
    return {std::move(image), ray_count};
}

FirstHits cast_primary_rays(const scene::Scene& scene, const RenderOptions& options, const Precision& precision) {
    scene::ImageSize size = scene::resolve_image_size(scene, options.width, options.height);
    Tracer tracer(scene, precision);
    std::uint64_t hits = with_kernels(precision, [&](auto kernels) {
        using P = decltype(kernels);
        PacketTracer<P> packets(tracer.compiled());
        CameraPacket camera(tracer.compiled(), size.width, size.height);
        return for_each_tile(tracer.compiled(), size, options, precision.flush_denormals,
                             [&](int x0, int y0, int x1, int y1, const PrimitiveLists& visible) {
                                 std::uint64_t tile_hits = 0;
                                 for_each_packet(x0, y0, x1, y1, [&](int x, int y, vbool4 active) {
                                     RayPacket packet = camera.template rays<P>(x, y, active);
                                     tile_hits += lane_count(packets.intersect(packet, visible).hit);
                                 });
                                 return tile_hits;
                             });
    });
    return {static_cast<std::uint64_t>(size.width) * static_cast<std::uint64_t>(size.height), hits};
}

}  // namespace twinray::sse
