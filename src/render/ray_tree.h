// One ray's tree as a tracer traced it, and where two such trees first part (`twinray probe`).
//
// Both tracers' per-ray trace() fill a RayTree on request: every ray (primary, refracted, reflected)
// in depth-first order with what it hit, each light's visibility and its colours. Plain data in double
// whatever the tracer's own precision, so trees of different tracers compare directly. Recording is
// off unless a tree is passed: the tracers then only test a null pointer.
#pragma once

#include "math/vec3.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace twinray {

using Vec3d = math::Vec3<double>;

// A tracer's vector (any precision) as recorded: every tree is in double.
template <typename T>
Vec3d recorded(const math::Vec3<T>& v) {
    return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}

// Why a ray was traced. A node's children are traced in this order: refracted, then reflected.
enum class RayKind { primary, refracted, reflected };

inline const char* ray_kind_name(RayKind kind) {
    switch (kind) {
        case RayKind::primary: return "primary";
        case RayKind::refracted: return "refracted";
        case RayKind::reflected: return "reflected";
    }
    return "?";
}

// One light as seen from a hit point.
struct LightVisibility {
    double n_dot_l = 0;  // N·L with L the unit vector to the light; ≤ 0: faces away, no shadow ray
    bool faces_away = true;
    double transmittance = 0;  // of the shadow ray: 1 unobstructed, 0 blocked (0 when facing away)
    Vec3d shadow_origin{};     // the shadow ray, when traced
    Vec3d shadow_direction{};
};

struct RayNode {
    RayKind kind = RayKind::primary;
    int depth = 1;    // 1 for the primary ray
    int parent = -1;  // index in RayTree::nodes; -1 for the first ray
    Vec3d origin{};
    Vec3d direction{};  // unit
    bool hit = false;
    // When hit: the first surface (the tracer's intersect()).
    int leaf = -1;      // Scene::leaf_paths
    int triangle = -1;  // for a mesh, the triangle's index in it
    int part = -1;      // on an instance of a solid shape, the shape's primitive
    double t = 0;
    Vec3d point{};
    Vec3d normal{};  // unit, facing the ray
    bool entering = false;
    std::vector<LightVisibility> lights;  // one per scene light, in file order (empty on a miss)
    Vec3d local{};                        // ambient + lights; the background on a miss
    Vec3d total{};                        // what the ray sees: local + transmission·refracted + reflection·reflected
};

// A secondary ray the depth control left out (scene/depth_control.h): its parent traced it not.
struct DroppedRay {
    int parent = -1;  // index in RayTree::nodes
    RayKind kind = RayKind::reflected;
    int depth = 2;
    double weight = 0;        // product of the coefficients on its path
    double bound = 0;         // weight · the radiance bound at its depth: the most it could have added
    bool for_budget = false;  // left out because the pixel's ray budget ran out, not by the cutoff
};

// Depth-first (pre-order): a node comes before its children, children in the order they are traced.
struct RayTree {
    std::vector<RayNode> nodes;
    std::vector<DroppedRay> dropped;  // in the order the tracer decided

    // Appends the node of a ray about to be traced and returns its index; the tracer fills in the rest.
    int add(RayKind kind, int depth, int parent, Vec3d origin, Vec3d direction) {
        RayNode node;
        node.kind = kind;
        node.depth = depth;
        node.parent = parent;
        node.origin = origin;
        node.direction = direction;
        nodes.push_back(node);
        return static_cast<int>(nodes.size()) - 1;
    }

    // What the ray of `node` hit (a node without this call is a miss).
    void set_hit(int node, int leaf, int triangle, int part, double t, Vec3d point, Vec3d normal, bool entering) {
        RayNode& n = nodes[static_cast<std::size_t>(node)];
        n.hit = true;
        n.leaf = leaf;
        n.triangle = triangle;
        n.part = part;
        n.t = t;
        n.point = point;
        n.normal = normal;
        n.entering = entering;
    }

    // A light the surface faces away from (N·L ≤ 0): no shadow ray.
    void add_light_facing_away(int node, double n_dot_l) {
        nodes[static_cast<std::size_t>(node)].lights.push_back({n_dot_l, true, 0, {}, {}});
    }

    // A light whose shadow ray, from `origin` along `direction`, found `transmittance`.
    void add_light(int node, double n_dot_l, double transmittance, Vec3d origin, Vec3d direction) {
        nodes[static_cast<std::size_t>(node)].lights.push_back({n_dot_l, false, transmittance, origin, direction});
    }

    void set_local_color(int node, Vec3d color) { nodes[static_cast<std::size_t>(node)].local = color; }

    // On a miss the background is both the local and the total colour.
    void set_total_color(int node, Vec3d color) {
        RayNode& n = nodes[static_cast<std::size_t>(node)];
        n.total = color;
        if (!n.hit) {
            n.local = color;
        }
    }

    void add_dropped(int parent, RayKind kind, int depth, double weight, double bound, bool for_budget) {
        dropped.push_back({parent, kind, depth, weight, bound, for_budget});
    }

    std::vector<int> children(int node) const {
        std::vector<int> found;
        for (std::size_t i = static_cast<std::size_t>(node) + 1; i < nodes.size(); ++i) {
            if (nodes[i].parent == node) {
                found.push_back(static_cast<int>(i));
            }
        }
        return found;
    }
};

// What counts as two tracers disagreeing on one ray (docs/probe.md: the reasons and the measurements).
// Besides these numbers, any discrete difference is a divergence: hit or miss, the object hit, entering
// or leaving, a light facing away or blocked in one tree only, a ray traced in one tree only.
//
// t is compared across the surface: |Δt|·|cos θ| (θ between the ray and the normal) over the scale
// S = |origin|∞ + t_parent + t. A ray meeting a surface at a grazing angle turns a tiny difference
// between the two rays into a long shift along them (1/|cos θ|, as in the conformance bound); times
// |cos θ| it is how far apart the two rays cross the surface. S is the size of the numbers involved:
// single precision rounds a point by about ε·S. A secondary ray's origin is its parent's hit point, so
// only the primary ray's origin is compared. Differences inherited from above grow with every bounce
// (about 1e-7 on primary rays; from depth 3 on, near 1e-2 at the 99.99th percentile on our scenes),
// hence thresholds far above rounding: what they catch is a formula that gives another answer, not drift.
struct DivergenceThresholds {
    double position = 1e-2;       // |Δt|·|cos θ| over S; the primary ray's |Δorigin|∞ over S
    double angle = 1e-2;          // radians between normals, between ray directions
    double transmittance = 1e-3;  // |Δ| of a shadow ray's transmittance
    double color = 1.0 / 255.0;   // largest |Δ| in one channel: one 8-bit level
};

// Where two trees differ. `first`/`second` are node indices in each tree, -1 when the ray exists in
// one tree only. `amount` is the measured difference in the unit of `threshold` (0 for a discrete one).
struct Divergence {
    int first = -1;
    int second = -1;
    std::string what;  // "ray", "hit", "object", "entering", "origin", "direction", "t", "normal",
                       // "lights[N]", "local colour", "total colour"
    double amount = 0;
    double threshold = 0;
};

namespace ray_tree_detail {

inline double max_abs(const Vec3d& v) {
    return std::max({std::fabs(v[0]), std::fabs(v[1]), std::fabs(v[2])});
}

inline double max_abs_difference(const Vec3d& a, const Vec3d& b) {
    return std::max({std::fabs(a[0] - b[0]), std::fabs(a[1] - b[1]), std::fabs(a[2] - b[2])});
}

// The angle between two unit vectors, accurate for small angles too (atan2 of |a×b| and a·b).
inline double angle_between(const Vec3d& a, const Vec3d& b) {
    Vec3d c{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

class Comparison {
public:
    Comparison(const RayTree& a, const RayTree& b, const DivergenceThresholds& limits)
        : a_(a), b_(b), limits_(limits) {}

    // Depth-first, in the order the rays were traced: a node's own ray, hit and lights, then its
    // children, then its total colour (which sums the children). A node whose hit differs in kind
    // (hit or miss, object) is not compared further down: its subtree follows a different path.
    void compare(int i, int j) {
        const RayNode& p = a_.nodes[static_cast<std::size_t>(i)];
        const RayNode& q = b_.nodes[static_cast<std::size_t>(j)];
        double scale = max_abs(p.origin) + (p.parent >= 0 ? a_.nodes[static_cast<std::size_t>(p.parent)].t : 0.0) +
                       (p.hit ? p.t : 0.0);
        if (p.parent < 0) {  // a secondary ray starts at its parent's hit point, compared there
            note(i, j, "origin", relative(max_abs_difference(p.origin, q.origin), scale), limits_.position);
        }
        note(i, j, "direction", angle_between(p.direction, q.direction), limits_.angle);
        if (p.hit != q.hit) {
            found_.push_back({i, j, "hit", 0, 0});
            return;
        }
        if (p.hit) {
            if (p.leaf != q.leaf || p.part != q.part) {
                found_.push_back({i, j, "object", 0, 0});
                return;
            }
            if (p.entering != q.entering) {
                found_.push_back({i, j, "entering", 0, 0});
            }
            double cosine =
                std::fabs(p.normal[0] * p.direction[0] + p.normal[1] * p.direction[1] + p.normal[2] * p.direction[2]);
            note(i, j, "t", relative(std::fabs(p.t - q.t) * cosine, scale), limits_.position);
            note(i, j, "normal", angle_between(p.normal, q.normal), limits_.angle);
            for (std::size_t l = 0; l < std::min(p.lights.size(), q.lights.size()); ++l) {
                std::string what = "lights[" + std::to_string(l) + "]";
                const LightVisibility& u = p.lights[l];
                const LightVisibility& v = q.lights[l];
                if (u.faces_away != v.faces_away || (u.transmittance == 0) != (v.transmittance == 0)) {
                    found_.push_back({i, j, what, std::fabs(u.transmittance - v.transmittance), 0});
                } else {
                    note(i, j, what, std::fabs(u.transmittance - v.transmittance), limits_.transmittance);
                }
            }
        }
        note(i, j, "local colour", max_abs_difference(p.local, q.local), limits_.color);
        std::vector<int> ours = a_.children(i);
        std::vector<int> theirs = b_.children(j);
        for (RayKind kind : {RayKind::refracted, RayKind::reflected}) {
            int x = child_of_kind(a_, ours, kind);
            int y = child_of_kind(b_, theirs, kind);
            if (x >= 0 && y >= 0) {
                compare(x, y);
            } else if (x >= 0 || y >= 0) {
                found_.push_back({x, y, "ray", 0, 0});
            }
        }
        note(i, j, "total colour", max_abs_difference(p.total, q.total), limits_.color);
    }

    std::vector<Divergence> found() && { return std::move(found_); }

private:
    static int child_of_kind(const RayTree& tree, const std::vector<int>& children, RayKind kind) {
        for (int child : children) {
            if (tree.nodes[static_cast<std::size_t>(child)].kind == kind) {
                return child;
            }
        }
        return -1;
    }

    static double relative(double difference, double scale) { return difference == 0 ? 0 : difference / scale; }

    // NaN counts as over the threshold: a NaN in one tree is a divergence.
    void note(int i, int j, const std::string& what, double amount, double threshold) {
        if (!(amount <= threshold)) {
            found_.push_back({i, j, what, amount, threshold});
        }
    }

    const RayTree& a_;
    const RayTree& b_;
    const DivergenceThresholds& limits_;
    std::vector<Divergence> found_;
};

}  // namespace ray_tree_detail

// Every difference over the thresholds, in depth-first order (so the first is where the trees part).
inline std::vector<Divergence> find_divergences(const RayTree& a, const RayTree& b,
                                                const DivergenceThresholds& thresholds = {}) {
    if (a.nodes.empty() || b.nodes.empty()) {
        if (a.nodes.empty() != b.nodes.empty()) {
            return {{a.nodes.empty() ? -1 : 0, b.nodes.empty() ? -1 : 0, "ray", 0, 0}};
        }
        return {};
    }
    ray_tree_detail::Comparison comparison(a, b, thresholds);
    comparison.compare(0, 0);
    return std::move(comparison).found();
}

inline std::optional<Divergence> first_divergence(const RayTree& a, const RayTree& b,
                                                  const DivergenceThresholds& thresholds = {}) {
    std::vector<Divergence> all = find_divergences(a, b, thresholds);
    if (all.empty()) {
        return std::nullopt;
    }
    return all.front();
}

}  // namespace twinray
