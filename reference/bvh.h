// A bounding volume hierarchy over the reference tracer's top-level objects, kept simple so the oracle can
// judge large scenes: binary, split at the median of the objects' centres along their widest axis, built on
// an explicit stack. It only skips objects a ray cannot meet, so the tracer answers exactly as without it
// (tests/bvh_test.cpp); objects without finite bounds (planes, some CSG) are tested by every ray.
#pragma once

#include "math/rounding.h"
#include "reference/ray.h"
#include "scene/geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace twinray::reference {

// With Accel::automatic (render/render.h) the tracer builds its BVH over its top-level objects where its
// bounded objects hold more than bvh_crossover primitives (a CSG object counts as its primitives), the count
// from which it measured faster (docs/performance.md, "The BVH"); and a mesh's over its triangles past as many.
constexpr std::size_t bvh_crossover = 8;

template <typename T>
class ObjectBvh {
public:
    ObjectBvh() = default;

    // One box per object (scene::bounds, ±∞ where unbounded), in object order.
    explicit ObjectBvh(const std::vector<scene::Bounds>& bounds) {
        std::vector<std::uint32_t> order;
        std::vector<scene::Bounds> boxes(bounds.size());
        std::vector<scene::Vec3> centres(bounds.size());
        for (std::uint32_t i = 0; i < bounds.size(); ++i) {
            if (!is_finite(bounds[i])) {
                unbounded_.push_back(i);
                continue;
            }
            order.push_back(i);
            double pad =
                padding * std::max(scene::largest_coordinate(bounds[i].low), scene::largest_coordinate(bounds[i].high));
            boxes[i] = scene::around(bounds[i].low, bounds[i].high, pad + 1e-30);
            centres[i] = 0.5 * (bounds[i].low + bounds[i].high);
        }
        if (order.empty()) {
            return;
        }
        struct Task {
            std::uint32_t node, begin, end;
        };
        nodes_.emplace_back();
        std::vector<Task> tasks{{0, 0, static_cast<std::uint32_t>(order.size())}};
        while (!tasks.empty()) {
            Task task = tasks.back();
            tasks.pop_back();
            scene::Bounds box = boxes[order[task.begin]];
            scene::Bounds spread{centres[order[task.begin]], centres[order[task.begin]]};
            for (std::uint32_t i = task.begin; i < task.end; ++i) {
                box = scene::around(min(box.low, boxes[order[i]].low), max(box.high, boxes[order[i]].high), 0);
                spread = scene::around(min(spread.low, centres[order[i]]), max(spread.high, centres[order[i]]), 0);
            }
            Node& node = nodes_[task.node];
            for (int axis = 0; axis < 3; ++axis) {
                node.low[axis] = math::rounded_down<T>(box.low[axis]);
                node.high[axis] = math::rounded_up<T>(box.high[axis]);
            }
            scene::Vec3 extent = spread.high - spread.low;
            int axis = extent[1] > extent[0] ? (extent[2] > extent[1] ? 2 : 1) : (extent[2] > extent[0] ? 2 : 0);
            // A leaf: few objects, or centres all at one point (no split separates them).
            if (task.end - task.begin <= max_leaf_objects || !(extent[axis] > 0)) {
                node.first = static_cast<std::uint32_t>(objects_.size());
                node.count = task.end - task.begin;
                objects_.insert(objects_.end(), order.begin() + task.begin, order.begin() + task.end);
                continue;
            }
            // Stable: the tree depends on the scene alone. Halving bounds the depth by log₂ of the objects.
            std::stable_sort(order.begin() + task.begin, order.begin() + task.end,
                             [&](std::uint32_t a, std::uint32_t b) { return centres[a][axis] < centres[b][axis]; });
            std::uint32_t middle = task.begin + (task.end - task.begin) / 2;
            std::uint32_t left = static_cast<std::uint32_t>(nodes_.size());
            node.first = left;
            node.count = 0;
            node.axis = static_cast<std::uint32_t>(axis);
            nodes_.emplace_back();
            nodes_.emplace_back();
            tasks.push_back({left + 1, middle, task.end});
            tasks.push_back({left, task.begin, middle});
        }
    }

    bool empty() const { return nodes_.empty(); }
    // Whether an object with these bounds goes into the tree (else every ray tests it).
    static bool is_finite(const scene::Bounds& bounds) {
        for (int axis = 0; axis < 3; ++axis) {
            if (!std::isfinite(bounds.low[axis]) || !std::isfinite(bounds.high[axis])) {
                return false;
            }
        }
        return true;
    }
    // Objects without finite bounds, ascending: every ray tests them.
    const std::vector<std::uint32_t>& unbounded() const { return unbounded_; }

    // Calls visit(object) for every bounded object of every leaf whose box the ray meets within
    // [0, limit()]; limit() (the nearest hit so far) is read again at every node. The nearer child first.
    template <typename Limit, typename Visit>
    void for_each_met(const Ray<T>& ray, Limit&& limit, Visit&& visit) const {
        if (nodes_.empty()) {
            return;
        }
        // The ray's origin padded as the boxes are: towards each face by δ, so every box is δ larger for it.
        T delta = T(padding) * max_abs_component(ray.origin) + std::numeric_limits<T>::min();
        Vec3<T> low_face_origin = ray.origin + Vec3<T>{delta, delta, delta};
        Vec3<T> high_face_origin = ray.origin - Vec3<T>{delta, delta, delta};
        Vec3<T> inverse{T(1) / ray.direction.x, T(1) / ray.direction.y, T(1) / ray.direction.z};
        std::uint32_t stack[2 * max_depth];
        int size = 0;
        stack[size++] = 0;
        while (size > 0) {
            const Node& node = nodes_[stack[--size]];
            if (!meets(node, low_face_origin, high_face_origin, inverse, limit())) {
                continue;
            }
            if (node.count > 0) {
                for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
                    visit(objects_[i]);
                }
                continue;
            }
            bool left_first = ray.direction[static_cast<int>(node.axis)] >= T(0);
            stack[size++] = left_first ? node.first + 1 : node.first;
            stack[size++] = left_first ? node.first : node.first + 1;
        }
    }

    // Boxes are padded by this share of their largest coordinate and rays' origins by this share of theirs:
    // 2048 ulps of T, far beyond the rounding of a kernel's hit point (a few ulps of the distances). A triangle's
    // t is held within half of it of its box (triangle.h, held_to_box), where its formula's rounding does not keep it.
    static constexpr double padding = 2048.0 * static_cast<double>(std::numeric_limits<T>::epsilon());

private:
    static constexpr std::uint32_t max_leaf_objects = 4;
    // Halving splits: a leaf is at most ⌈log₂ objects⌉ deep, under 33 for any count.
    static constexpr int max_depth = 33;

    struct Node {
        T low[3], high[3];
        std::uint32_t first = 0;  // leaf: its first object in objects_; inner node: its left child (right: +1)
        std::uint32_t count = 0;  // objects of a leaf; 0 for an inner node
        std::uint32_t axis = 0;   // inner node: the axis its children are split along
    };

    static scene::Vec3 min(const scene::Vec3& a, const scene::Vec3& b) {
        return {std::min(a[0], b[0]), std::min(a[1], b[1]), std::min(a[2], b[2])};
    }
    static scene::Vec3 max(const scene::Vec3& a, const scene::Vec3& b) {
        return {std::max(a[0], b[0]), std::max(a[1], b[1]), std::max(a[2], b[2])};
    }
    // Slabs; a NaN (an origin exactly on a padded face, parallel to it) is passed over by std::min and
    // std::max, which keeps the box: conservative.
    static bool meets(const Node& node, const Vec3<T>& low_face_origin, const Vec3<T>& high_face_origin,
                      const Vec3<T>& inverse, T limit) {
        T near = T(0);
        T far = limit;
        for (int axis = 0; axis < 3; ++axis) {
            T t_low = (node.low[axis] - low_face_origin[axis]) * inverse[axis];
            T t_high = (node.high[axis] - high_face_origin[axis]) * inverse[axis];
            near = std::max(near, std::min(t_low, t_high));
            far = std::min(far, std::max(t_low, t_high));
        }
        return near <= far;
    }

    std::vector<Node> nodes_;
    std::vector<std::uint32_t> objects_;  // the leaves' objects, leaf after leaf
    std::vector<std::uint32_t> unbounded_;
};

}  // namespace twinray::reference
