#include "sse/bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace twinray::sse {
namespace {

constexpr int bin_count = 16;
constexpr std::uint32_t max_leaf_items = 4;
// The SAH's price of visiting a node, in primitive tests.
constexpr double node_cost = 2.0;
constexpr double infinity_d = std::numeric_limits<double>::infinity();

scene::Bounds empty_bounds() {
    return {{infinity_d, infinity_d, infinity_d}, {-infinity_d, -infinity_d, -infinity_d}};
}

void grow(scene::Bounds& bounds, const scene::Bounds& other) {
    for (int axis = 0; axis < 3; ++axis) {
        bounds.low[axis] = std::min(bounds.low[axis], other.low[axis]);
        bounds.high[axis] = std::max(bounds.high[axis], other.high[axis]);
    }
}

void grow(scene::Bounds& bounds, const scene::Vec3& point) {
    grow(bounds, scene::Bounds{point, point});
}

// Half the surface area: the SAH compares ratios, so the factor 2 is left out.
double half_area(const scene::Bounds& bounds) {
    scene::Vec3 size = bounds.high - bounds.low;
    if (!(size[0] >= 0 && size[1] >= 0 && size[2] >= 0)) {
        return 0;
    }
    return size[0] * size[1] + size[1] * size[2] + size[2] * size[0];
}

scene::Bounds padded(const scene::Bounds& bounds) {
    double pad =
        bvh_padding * std::max(scene::largest_coordinate(bounds.low), scene::largest_coordinate(bounds.high)) + 1e-30;
    return scene::around(bounds.low, bounds.high, pad);
}

// The float at or below `value` (above it: rounded_up), so that the float box holds the double one.
float rounded_down(double value) {
    double nearest = scene::rounded_to_float(value);
    float out = static_cast<float>(nearest);
    return nearest > value ? std::nextafter(out, -std::numeric_limits<float>::infinity()) : out;
}

float rounded_up(double value) {
    double nearest = scene::rounded_to_float(value);
    float out = static_cast<float>(nearest);
    return nearest < value ? std::nextafter(out, std::numeric_limits<float>::infinity()) : out;
}

int ceil_log2(std::uint32_t count) {
    int bits = 0;
    while ((std::uint64_t{1} << bits) < count) {
        ++bits;
    }
    return bits;
}

struct Split {
    int axis = -1;  // -1: make a leaf
    int bin = 0;    // items whose centroid falls in a bin below this one go left
    bool halve = false;
};

class Builder {
public:
    explicit Builder(const std::vector<BvhInput>& inputs) : inputs_(inputs), order_(inputs.size()) {
        std::iota(order_.begin(), order_.end(), std::uint32_t{0});
        boxes_.reserve(inputs.size());
        centroids_.reserve(inputs.size());
        for (const BvhInput& input : inputs) {
            boxes_.push_back(padded(input.bounds));
            centroids_.push_back(0.5 * (input.bounds.low + input.bounds.high));
        }
    }

    Bvh run() {
        Bvh bvh;
        if (inputs_.empty()) {
            return bvh;
        }
        bvh.nodes.reserve(2 * inputs_.size());
        bvh.items.reserve(inputs_.size());
        bvh.nodes.emplace_back();
        // Depth first, left child first, on an explicit stack: no recursion a degenerate scene could overflow.
        struct Task {
            std::uint32_t node, begin, end;
            int depth;
        };
        std::vector<Task> tasks{{0, 0, static_cast<std::uint32_t>(inputs_.size()), 0}};
        while (!tasks.empty()) {
            Task task = tasks.back();
            tasks.pop_back();
            scene::Bounds box = empty_bounds();
            for (std::uint32_t i = task.begin; i < task.end; ++i) {
                grow(box, boxes_[order_[i]]);
            }
            BvhNode& node = bvh.nodes[task.node];
            for (int axis = 0; axis < 3; ++axis) {
                node.low[axis] = rounded_down(box.low[axis]);
                node.high[axis] = rounded_up(box.high[axis]);
            }
            Split split = choose_split(task.begin, task.end, task.depth, box);
            if (split.axis < 0) {
                node.first = static_cast<std::uint32_t>(bvh.items.size());
                node.count = task.end - task.begin;
                for (std::uint32_t i = task.begin; i < task.end; ++i) {
                    bvh.items.push_back(inputs_[order_[i]].item);
                }
                continue;
            }
            std::uint32_t middle = partition(task.begin, task.end, split);
            std::uint32_t left = static_cast<std::uint32_t>(bvh.nodes.size());
            node.first = left;
            node.count = 0;
            bvh.nodes.emplace_back();
            bvh.nodes.emplace_back();
            tasks.push_back({left + 1, middle, task.end, task.depth + 1});
            tasks.push_back({left, task.begin, middle, task.depth + 1});
        }
        return bvh;
    }

private:
    struct CentroidBins {
        scene::Bounds centroid_bounds;
        int bin_of(const scene::Vec3& centroid, int axis) const {
            double low = centroid_bounds.low[axis];
            double extent = centroid_bounds.high[axis] - low;
            int bin = static_cast<int>((centroid[axis] - low) / extent * bin_count);
            return std::clamp(bin, 0, bin_count - 1);
        }
    };

    // Binned SAH over the items' centroids; a leaf where that is cheaper (and small) or where every centroid
    // is the same point (no split separates them: one leaf, as brute force). Halving splits where the
    // depth left is short.
    Split choose_split(std::uint32_t begin, std::uint32_t end, int depth, const scene::Bounds& box) {
        std::uint32_t count = end - begin;
        Split split;
        if (count <= 1) {
            return split;
        }
        bins_.centroid_bounds = empty_bounds();
        for (std::uint32_t i = begin; i < end; ++i) {
            grow(bins_.centroid_bounds, centroids_[order_[i]]);
        }
        if (depth + ceil_log2(count) >= bvh_max_depth) {
            split.halve = true;
            split.axis = largest_axis(bins_.centroid_bounds);
            return split;
        }
        double best_cost = infinity_d;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(bins_.centroid_bounds.high[axis] > bins_.centroid_bounds.low[axis])) {
                continue;
            }
            scene::Bounds bin_bounds[bin_count];
            std::uint32_t bin_items[bin_count] = {};
            std::fill(bin_bounds, bin_bounds + bin_count, empty_bounds());
            for (std::uint32_t i = begin; i < end; ++i) {
                int bin = bins_.bin_of(centroids_[order_[i]], axis);
                grow(bin_bounds[bin], boxes_[order_[i]]);
                ++bin_items[bin];
            }
            double right_cost[bin_count] = {};
            scene::Bounds right = empty_bounds();
            std::uint32_t right_items = 0;
            for (int bin = bin_count - 1; bin > 0; --bin) {
                grow(right, bin_bounds[bin]);
                right_items += bin_items[bin];
                right_cost[bin] = right_items == 0 ? infinity_d : half_area(right) * right_items;
            }
            scene::Bounds left = empty_bounds();
            std::uint32_t left_items = 0;
            for (int bin = 1; bin < bin_count; ++bin) {
                grow(left, bin_bounds[bin - 1]);
                left_items += bin_items[bin - 1];
                if (left_items == 0 || left_items == count) {
                    continue;
                }
                double cost = half_area(left) * left_items + right_cost[bin];
                if (cost < best_cost) {
                    best_cost = cost;
                    split.axis = axis;
                    split.bin = bin;
                }
            }
        }
        if (split.axis >= 0 && count <= max_leaf_items &&
            count * half_area(box) <= node_cost * half_area(box) + best_cost) {
            split.axis = -1;
        }
        return split;
    }

    static int largest_axis(const scene::Bounds& bounds) {
        scene::Vec3 size = bounds.high - bounds.low;
        return size[1] > size[0] ? (size[2] > size[1] ? 2 : 1) : (size[2] > size[0] ? 2 : 0);
    }

    // Both sides keep the items' order among themselves (stable), so the tree depends on nothing but the input.
    std::uint32_t partition(std::uint32_t begin, std::uint32_t end, const Split& split) {
        auto first = order_.begin() + begin;
        auto last = order_.begin() + end;
        if (split.halve) {
            std::stable_sort(first, last, [&](std::uint32_t a, std::uint32_t b) {
                return centroids_[a][split.axis] < centroids_[b][split.axis];
            });
            return begin + (end - begin) / 2;
        }
        auto middle = std::stable_partition(
            first, last, [&](std::uint32_t i) { return bins_.bin_of(centroids_[i], split.axis) < split.bin; });
        return static_cast<std::uint32_t>(middle - order_.begin());
    }

    const std::vector<BvhInput>& inputs_;
    std::vector<std::uint32_t> order_;
    std::vector<scene::Bounds> boxes_;
    std::vector<scene::Vec3> centroids_;
    CentroidBins bins_;
};

}  // namespace

Bvh build_bvh(const std::vector<BvhInput>& inputs) {
    return Builder(inputs).run();
}

std::size_t bvh_bytes(const Bvh& bvh) {
    return bvh.nodes.size() * sizeof(BvhNode) + bvh.items.size() * sizeof(BvhItem);
}

}  // namespace twinray::sse
