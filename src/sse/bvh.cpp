#include "sse/bvh.h"

#include <emmintrin.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

namespace twinray::sse {
namespace {

constexpr int bin_count = 16;
// Items binned at a time: their references (32 bytes each) and bins stay in L1 between the two passes.
constexpr std::uint32_t block_items = 256;
constexpr float infinity_f = std::numeric_limits<float>::infinity();

// The doubles `xy` and `z` (x, y and z) rounded to the float at or below each (`up`: at or above), so that
// the float box holds the double one: exactly static_cast<float> and, where that went past, one
// std::nextafter step, four at a time and without a call per coordinate.
__m128 rounded_outward(__m128d xy, __m128d z, bool up) {
    __m128 nearest = _mm_movelh_ps(_mm_cvtpd_ps(xy), _mm_cvtpd_ps(z));
    __m128d back_xy = _mm_cvtps_pd(nearest), back_z = _mm_cvtps_pd(_mm_movehl_ps(nearest, nearest));
    __m128d past_xy = up ? _mm_cmplt_pd(back_xy, xy) : _mm_cmpgt_pd(back_xy, xy);
    __m128d past_z = up ? _mm_cmplt_pd(back_z, z) : _mm_cmpgt_pd(back_z, z);
    // Each double lane's mask is all ones or all zeros: its low half is the float lane's mask.
    __m128i past = _mm_unpacklo_epi64(_mm_shuffle_epi32(_mm_castpd_si128(past_xy), _MM_SHUFFLE(3, 3, 2, 0)),
                                      _mm_shuffle_epi32(_mm_castpd_si128(past_z), _MM_SHUFFLE(3, 3, 2, 0)));
    // One ulp in the float's bits: a zero of either sign first takes the direction's sign, then a float
    // stepping away from zero (the direction's sign) adds one and one stepping toward zero subtracts one.
    __m128i bits = _mm_castps_si128(nearest);
    __m128i zero = _mm_castps_si128(_mm_cmpeq_ps(nearest, _mm_setzero_ps()));
    __m128i direction = up ? _mm_setzero_si128() : _mm_set1_epi32(std::numeric_limits<std::int32_t>::min());
    __m128i signed_bits = _mm_or_si128(_mm_andnot_si128(zero, bits), _mm_and_si128(zero, direction));
    __m128i toward_zero = _mm_srai_epi32(_mm_xor_si128(signed_bits, direction), 31);
    __m128i step = _mm_add_epi32(_mm_set1_epi32(1), _mm_add_epi32(toward_zero, toward_zero));
    __m128i stepped = _mm_add_epi32(signed_bits, step);
    return _mm_castsi128_ps(_mm_or_si128(_mm_and_si128(past, stepped), _mm_andnot_si128(past, bits)));
}

// A box in float, low and high each one __m128 (the fourth lane unused). SSE2 only, the x86-64 baseline: the
// build needs nothing of SSE4.1. Float throughout, since every box is rounded outward to float once, from the
// padded double box, and float's min and max are exact: a node's box is the union of its items' float boxes,
// the same as rounding the union of their double boxes outward.
struct Box4 {
    __m128 low = _mm_set1_ps(infinity_f);
    __m128 high = _mm_set1_ps(-infinity_f);

    void grow(__m128 box_low, __m128 box_high) {
        low = _mm_min_ps(low, box_low);
        high = _mm_max_ps(high, box_high);
    }
    void grow(const Box4& box) { grow(box.low, box.high); }
    void grow(__m128 point) { grow(point, point); }
};

// Half extents, times `scale`; 0 for an empty box. Halved first, so that no difference of finite floats overflows.
__m128 half_extent(const Box4& box, __m128 scale) {
    __m128 half = _mm_set1_ps(0.5f);
    __m128 extent = _mm_sub_ps(_mm_mul_ps(box.high, half), _mm_mul_ps(box.low, half));
    return _mm_mul_ps(_mm_max_ps(extent, _mm_setzero_ps()), scale);
}

// A node's boxes measured in its own size: 1 / its largest half extent on x, y and z (1 where it is a point), so
// that the SAH's areas are at most 3 and no product overflows or underflows in float, whatever the scene's scale.
__m128 area_scale(const Box4& node) {
    alignas(16) float extent[4];
    _mm_store_ps(extent, half_extent(node, _mm_set1_ps(1.0f)));
    float largest = std::max({extent[0], extent[1], extent[2]});
    return _mm_set1_ps(largest > 0 ? 1.0f / largest : 1.0f);
}

// A quarter of the surface area, scaled (the SAH compares ratios, so constant factors are left out).
float area(const Box4& box, __m128 scale) {
    __m128 d = half_extent(box, scale);
    __m128 rotated = _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1));  // y, z, x
    __m128 products = _mm_mul_ps(d, rotated);                        // xy, yz, zx
    __m128 sum = _mm_add_ss(products, _mm_shuffle_ps(products, products, _MM_SHUFFLE(3, 3, 3, 1)));
    return _mm_cvtss_f32(_mm_add_ss(sum, _mm_shuffle_ps(products, products, _MM_SHUFFLE(3, 3, 3, 2))));
}

// The areas of three boxes, one a lane (the fourth unused): the same operations as area() on each.
__m128 areas(const Box4 (&boxes)[3], __m128 scale) {
    __m128 a = half_extent(boxes[0], scale), b = half_extent(boxes[1], scale), c = half_extent(boxes[2], scale);
    __m128 ab_low = _mm_unpacklo_ps(a, b), ab_high = _mm_unpackhi_ps(a, b);  // ax bx ay by, az bz aw bw
    __m128 x = _mm_movelh_ps(ab_low, c);
    __m128 y = _mm_shuffle_ps(ab_low, c, _MM_SHUFFLE(3, 1, 3, 2));
    __m128 z = _mm_shuffle_ps(ab_high, c, _MM_SHUFFLE(3, 2, 1, 0));
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, y), _mm_mul_ps(y, z)), _mm_mul_ps(z, x));
}

// The binary tree the SAH builds, collapsed into BvhNodes after. An inner node (count 0) has its two children
// at `first` and `first + 1`; a leaf holds items[first, first + count).
struct alignas(16) BinaryNode {
    float low[3];
    std::uint32_t first;
    float high[3];
    std::uint32_t count;
};

struct BinaryTree {
    LargeArray<BinaryNode> nodes;  // nodes[0] is the root
    LargeArray<BvhItem> items;     // leaves' items, in leaf order
};

__m128 low4(const BvhInput& input) {
    return _mm_load_ps(input.low);
}
__m128 high4(const BvhInput& input) {
    return _mm_load_ps(input.high);
}
// Twice the centroid: the factor ½ is folded into the bins' scale.
__m128 centroid2(const BvhInput& input) {
    return _mm_add_ps(low4(input), high4(input));
}

// An item's bin on x, y and z, one byte each (bin_count fits).
struct ItemBins {
    std::uint8_t axis[4];
};

// Maps twice-centroids to `count` bins on all three axes at once: bin = ⌊(c − low)·scale⌋, clamped. An axis
// on which every centroid is the same (or too close for the scale to be finite) puts everything in bin 0.
struct Binning {
    __m128 low;
    __m128 scale;
    __m128 last;
    int count;
    bool splittable[3];

    Binning(const Box4& centroids, int bins) : low(centroids.low), last(_mm_set1_ps(bins - 1)), count(bins) {
        // A hair under `bins`, so that the largest centroid lands in the last bin, not past it.
        __m128 extent = _mm_sub_ps(centroids.high, centroids.low);
        __m128 candidate = _mm_div_ps(_mm_set1_ps(static_cast<float>(bins) * (1.0f - 1.0f / 1024.0f)), extent);
        __m128 finite = _mm_cmplt_ps(_mm_andnot_ps(_mm_set1_ps(-0.0f), candidate), _mm_set1_ps(infinity_f));
        __m128 xyz = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
        __m128 usable = _mm_and_ps(_mm_and_ps(_mm_cmpgt_ps(extent, _mm_setzero_ps()), finite), xyz);
        scale = _mm_and_ps(usable, candidate);
        int mask = _mm_movemask_ps(usable);
        for (int axis = 0; axis < 3; ++axis) {
            splittable[axis] = (mask >> axis) & 1;
        }
    }

    // The bins of a twice-centroid on x, y, z (and 0 in the fourth byte).
    ItemBins bins_of(__m128 centroid2) const {
        __m128 position = _mm_mul_ps(_mm_sub_ps(centroid2, low), scale);
        position = _mm_min_ps(_mm_max_ps(position, _mm_setzero_ps()), last);
        __m128i bins = _mm_cvttps_epi32(position);
        bins = _mm_packs_epi32(bins, bins);
        ItemBins out;
        std::uint32_t packed = static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm_packus_epi16(bins, bins)));
        std::memcpy(out.axis, &packed, sizeof packed);
        return out;
    }
};

struct Split {
    int axis = -1;  // -1: make a leaf
    int bin = 0;    // items whose centroid falls in a bin below this one go left
    bool halve = false;
};

// The items of a node: where they are in the build's array, their boxes' union and their twice-centroids' bounds.
struct Range {
    std::uint32_t begin, end;
    Box4 box, centroids;
};

class Builder {
public:
    Builder(LargeArray<BvhInput>&& inputs, const BvhCosts& costs)
        : costs_(costs), references_(std::move(inputs)), bins_(references_.size()) {
        for (std::size_t i = 0; i < references_.size(); ++i) {
            references_[i].place = static_cast<std::uint32_t>(i);
        }
    }

    BinaryTree run() {
        BinaryTree bvh;
        if (references_.empty()) {
            return bvh;
        }
        bvh.nodes.reserve(2 * references_.size());
        bvh.nodes.resize(1);
        // Depth first, left child first, on an explicit stack: no recursion a degenerate scene could overflow.
        struct Task {
            std::uint32_t node;
            int depth;
            Range range;
        };
        Range root{0, static_cast<std::uint32_t>(references_.size()), {}, {}};
        for (const BvhInput& reference : references_) {
            root.box.grow(low4(reference), high4(reference));
            root.centroids.grow(centroid2(reference));
        }
        std::vector<Task> tasks{{0, 0, root}};
        while (!tasks.empty()) {
            Task task = tasks.back();
            tasks.pop_back();
            const Range& range = task.range;
            BinaryNode& node = bvh.nodes[task.node];
            alignas(16) float low[4], high[4];
            _mm_store_ps(low, range.box.low);
            _mm_store_ps(high, range.box.high);
            std::copy(low, low + 3, node.low);
            std::copy(high, high + 3, node.high);
            Split split = choose_split(range, task.depth);
            if (split.axis < 0) {
                // Leaves come left to right, so a leaf's items are its range of the final references.
                node.first = range.begin;
                node.count = range.end - range.begin;
                continue;
            }
            auto [left, right] = partition(range, split);
            std::uint32_t first = static_cast<std::uint32_t>(bvh.nodes.size());
            node.first = first;
            node.count = 0;
            bvh.nodes.emplace_back();
            bvh.nodes.emplace_back();
            tasks.push_back({first + 1, task.depth + 1, right});
            tasks.push_back({first, task.depth + 1, left});
        }
        // All at the end, in one tight loop: the items are scattered in memory, and loads issued back to back
        // overlap their cache misses where one per leaf, between splits, waited alone.
        bvh.items.reserve(references_.size());
        for (const BvhInput& reference : references_) {
            bvh.items.push_back(reference.item());
        }
        return bvh;
    }

private:
    // Binned SAH over the items' centroids, all three axes in one pass; a leaf where that is cheaper (and
    // small) or where every centroid is the same point (no split separates them: one leaf, as brute force).
    // Halving splits where the depth left is short.
    Split choose_split(const Range& range, int depth) {
        std::uint32_t count = range.end - range.begin;
        Split split;
        if (count <= 1) {
            return split;
        }
        if (depth + static_cast<int>(std::bit_width(count - 1)) >= bvh_max_depth) {
            split.halve = true;
            split.axis = largest_axis(range.centroids);
            return split;
        }
        const __m128 scale = area_scale(range.box);
        const float node_area = area(range.box, scale);
        // The test below keeps a leaf of count <= costs_.node items whatever split the sweep finds (best_cost >= 0),
        // unless the area is NaN (infinite coordinates): then the sweep cannot be skipped.
        if (static_cast<float>(count) <= costs_.node && count <= costs_.max_leaf_items && !std::isnan(node_area)) {
            return split;
        }
        // As many bins as items, up to bin_count: a small node's sweep then costs no more than its binning.
        binning_ = Binning(range.centroids, static_cast<int>(std::min<std::uint32_t>(count, bin_count)));
        const int bins = binning_.count;
        for (auto& axis : bin_boxes_) {
            std::fill(axis, axis + bins, Box4{});
        }
        std::fill_n(bin_items_, bins, BinItems{});
        // Every item's bins first, then the boxes, a block at a time (the block's items stay in L1): with the
        // bins known ahead, loading a bin's box need not guess whether an item just before stored to it, a
        // guess that made binning 3x slower where it went wrong. The bins stay for partition.
        const BvhInput* references = references_.data();
        ItemBins* item_bins = bins_.data();
        for (std::uint32_t block = range.begin; block < range.end; block += block_items) {
            std::uint32_t block_end = std::min(range.end, block + block_items);
            for (std::uint32_t i = block; i < block_end; ++i) {
                item_bins[i] = binning_.bins_of(centroid2(references[i]));
            }
            for (std::uint32_t i = block; i < block_end; ++i) {
                __m128 low = low4(references[i]), high = high4(references[i]);
                ItemBins item = item_bins[i];
                for (int axis = 0; axis < 3; ++axis) {
                    bin_boxes_[axis][item.axis[axis]].grow(low, high);
                    ++bin_items_[item.axis[axis]][axis];
                }
            }
        }
        // The three axes swept side by side, a lane each. Each cost is the left and the right side's; NaN where
        // the axis cannot split or a side would be empty, so that the search below, in the order axis then bin,
        // passes it over.
        alignas(16) float cost[bin_count][4];
        Box4 right[3];
        __m128i right_items = _mm_setzero_si128();
        for (int bin = bins - 1; bin > 0; --bin) {
            for (int axis = 0; axis < 3; ++axis) {
                right[axis].grow(bin_boxes_[axis][bin]);
            }
            right_items =
                _mm_add_epi32(right_items, _mm_load_si128(reinterpret_cast<const __m128i*>(bin_items_[bin].data())));
            _mm_store_ps(cost[bin], _mm_mul_ps(areas(right, scale), _mm_cvtepi32_ps(right_items)));
        }
        const __m128i none = _mm_setzero_si128(), all = _mm_set1_epi32(static_cast<std::int32_t>(count));
        const __m128 splittable = _mm_castsi128_ps(
            _mm_set_epi32(0, -binning_.splittable[2], -binning_.splittable[1], -binning_.splittable[0]));
        const __m128 nan = _mm_set1_ps(std::numeric_limits<float>::quiet_NaN());
        Box4 left[3];
        __m128i left_items = _mm_setzero_si128();
        for (int bin = 1; bin < bins; ++bin) {
            for (int axis = 0; axis < 3; ++axis) {
                left[axis].grow(bin_boxes_[axis][bin - 1]);
            }
            left_items =
                _mm_add_epi32(left_items, _mm_load_si128(reinterpret_cast<const __m128i*>(bin_items_[bin - 1].data())));
            __m128 both =
                _mm_add_ps(_mm_mul_ps(areas(left, scale), _mm_cvtepi32_ps(left_items)), _mm_load_ps(cost[bin]));
            __m128i empty_side = _mm_or_si128(_mm_cmpeq_epi32(left_items, none), _mm_cmpeq_epi32(left_items, all));
            __m128 splits = _mm_andnot_ps(_mm_castsi128_ps(empty_side), splittable);
            _mm_store_ps(cost[bin], _mm_or_ps(_mm_and_ps(splits, both), _mm_andnot_ps(splits, nan)));
        }
        float best_cost = std::numeric_limits<float>::infinity();
        for (int axis = 0; axis < 3; ++axis) {
            for (int bin = 1; bin < bins; ++bin) {
                if (cost[bin][axis] < best_cost) {
                    best_cost = cost[bin][axis];
                    split.axis = axis;
                    split.bin = bin;
                }
            }
        }
        if (split.axis >= 0 && count <= costs_.max_leaf_items &&
            static_cast<float>(count) * node_area <= costs_.node * node_area + best_cost) {
            split.axis = -1;
        }
        return split;
    }

    static int largest_axis(const Box4& bounds) {
        alignas(16) float size[4];
        _mm_store_ps(size, _mm_sub_ps(bounds.high, bounds.low));
        return size[1] > size[0] ? (size[2] > size[1] ? 2 : 1) : (size[2] > size[0] ? 2 : 0);
    }

    // Two pointers from both ends, gathering each side's boxes on the way; deterministic (the tree depends
    // on nothing but the input), though not stable: the order within a leaf decides no answer (ties go to
    // the earlier leaf, and shadow products are multiplied in list order, bvh_traversal.h).
    std::pair<Range, Range> partition(const Range& range, const Split& split) {
        if (split.halve) {
            return halve(range, split.axis);
        }
        Range left{range.begin, range.begin, {}, {}}, right{range.end, range.end, {}, {}};
        std::uint32_t i = range.begin, j = range.end;
        while (i < j) {
            const BvhInput& reference = references_[i];
            __m128 twice_centroid = centroid2(reference);
            if (bins_[i].axis[split.axis] < split.bin) {
                left.box.grow(low4(reference), high4(reference));
                left.centroids.grow(twice_centroid);
                ++i;
            } else {
                right.box.grow(low4(reference), high4(reference));
                right.centroids.grow(twice_centroid);
                std::swap(references_[i], references_[--j]);
                std::swap(bins_[i], bins_[j]);
            }
        }
        left.end = i;
        right.begin = i;
        return {left, right};
    }

    // Sorted by centroid (ties by input order) and cut in two equal halves: depth log2(count) at most.
    std::pair<Range, Range> halve(const Range& range, int axis) {
        auto first = references_.begin() + range.begin;
        auto last = references_.begin() + range.end;
        std::sort(first, last, [axis](const BvhInput& a, const BvhInput& b) {
            float ca = a.low[axis] + a.high[axis], cb = b.low[axis] + b.high[axis];
            return ca < cb || (ca == cb && a.place < b.place);
        });
        std::uint32_t middle = range.begin + (range.end - range.begin) / 2;
        Range halves[2] = {{range.begin, middle, {}, {}}, {middle, range.end, {}, {}}};
        for (Range& half : halves) {
            for (std::uint32_t i = half.begin; i < half.end; ++i) {
                half.box.grow(low4(references_[i]), high4(references_[i]));
                half.centroids.grow(centroid2(references_[i]));
            }
        }
        return {halves[0], halves[1]};
    }

    const BvhCosts costs_;
    LargeArray<BvhInput> references_;
    // Each item's bins in the node being split, kept in step with references_ by partition.
    LargeArray<ItemBins> bins_;
    Binning binning_{Box4{}, bin_count};
    // The node's bins on each axis: their boxes and item counts. One set: with the bins known a block ahead, a
    // second set for odd items (so that neighbours in one bin did not wait on each other) measured slower.
    Box4 bin_boxes_[3][bin_count];
    // Item counts a bin, one axis a lane, for the sweeps' vectors.
    using BinItems = std::array<std::int32_t, 4>;
    alignas(16) BinItems bin_items_[bin_count];
};

// A binary node's area as the SAH measures it, unscaled (which child to open first when collapsing). Its
// boxes load as one __m128 each: the fourth lane (first, count) is one area() leaves out.
float area(const BinaryNode& node) {
    Box4 box;
    box.grow(_mm_load_ps(node.low), _mm_load_ps(node.high));
    return area(box, _mm_set1_ps(1.0f));
}

// Each BvhNode takes a binary inner node's place: its two children, then, while fewer than four, the inner
// child of largest area (the likeliest to be entered, Embree's rule; ties to the leftmost) is replaced by its
// own two, in place, so the children stay in the binary tree's left-to-right order. Depth first, first child
// first, so a subtree's nodes lie together. Deterministic: nothing but the binary tree decides.
Bvh collapse(BinaryTree&& binary) {
    Bvh bvh;
    bvh.items = std::move(binary.items);
    if (binary.nodes.empty()) {
        return bvh;
    }
    const LargeArray<BinaryNode>& from = binary.nodes;
    bvh.nodes.reserve(from.size() / 2 + 1);
    struct Task {
        std::uint32_t binary, node;
    };
    std::vector<Task> tasks{{0, 0}};
    bvh.nodes.emplace_back();
    while (!tasks.empty()) {
        Task task = tasks.back();
        tasks.pop_back();
        std::uint32_t children[4] = {task.binary};
        float areas[4] = {area(from[task.binary])};
        int child_count = 1;
        while (child_count < 4) {
            int widest = -1;
            for (int c = 0; c < child_count; ++c) {
                if (from[children[c]].count == 0 && (widest < 0 || areas[c] > areas[widest])) {
                    widest = c;
                }
            }
            if (widest < 0) {
                break;
            }
            std::uint32_t left = from[children[widest]].first;
            std::copy_backward(children + widest + 1, children + child_count, children + child_count + 1);
            std::copy_backward(areas + widest + 1, areas + child_count, areas + child_count + 1);
            children[widest] = left;
            children[widest + 1] = left + 1;
            areas[widest] = area(from[left]);
            areas[widest + 1] = area(from[left + 1]);
            ++child_count;
        }
        Task pending[4];
        int pending_count = 0;
        for (int c = 0; c < 4; ++c) {
            BvhNode& node = bvh.nodes[task.node];  // value-initialized: an empty slot's box and first are 0
            if (c >= child_count) {
                node.count[c] = BvhNode::empty_child;
                continue;
            }
            const BinaryNode& child = from[children[c]];
            for (int axis = 0; axis < 3; ++axis) {
                node.low[axis][c] = child.low[axis];
                node.high[axis][c] = child.high[axis];
            }
            node.count[c] = child.count;
            if (child.count > 0) {
                node.first[c] = child.first;
            } else {
                node.first[c] = static_cast<std::uint32_t>(bvh.nodes.size());
                pending[pending_count++] = {children[c], node.first[c]};
                bvh.nodes.emplace_back();
            }
        }
        for (int p = pending_count - 1; p >= 0; --p) {
            tasks.push_back(pending[p]);
        }
    }
    return bvh;
}

}  // namespace

// The item's box padded (as scene::around with `padding` times its largest |coordinate|) and rounded outward, in SSE2
// doubles: the same IEEE operations as the scalar formula, a pair at a time.
BvhInput::BvhInput(const scene::Bounds& bounds, BvhItem item, double padding) {
    __m128d a_xy = _mm_loadu_pd(&bounds.low[0]), a_z = _mm_load_sd(&bounds.low[2]);
    __m128d b_xy = _mm_loadu_pd(&bounds.high[0]), b_z = _mm_load_sd(&bounds.high[2]);
    __m128d magnitude = _mm_castsi128_pd(_mm_set1_epi64x(std::numeric_limits<std::int64_t>::max()));
    __m128d largest = _mm_max_pd(_mm_max_pd(_mm_and_pd(a_xy, magnitude), _mm_and_pd(b_xy, magnitude)),
                                 _mm_max_sd(_mm_and_pd(a_z, magnitude), _mm_and_pd(b_z, magnitude)));
    largest = _mm_max_sd(largest, _mm_unpackhi_pd(largest, largest));
    __m128d pad = _mm_add_sd(_mm_mul_sd(_mm_set_sd(padding), largest), _mm_set_sd(1e-30));
    pad = _mm_unpacklo_pd(pad, pad);
    // std::min(a, b) is b only where b < a, as minpd(b, a); std::max(a, b) likewise maxpd(b, a).
    __m128 low_bound =
        rounded_outward(_mm_sub_pd(_mm_min_pd(b_xy, a_xy), pad), _mm_sub_pd(_mm_min_pd(b_z, a_z), pad), false);
    __m128 high_bound =
        rounded_outward(_mm_add_pd(_mm_max_pd(b_xy, a_xy), pad), _mm_add_pd(_mm_max_pd(b_z, a_z), pad), true);
    // Each store's fourth lane lands on the word after the box; those words are set after.
    _mm_store_ps(this->low, low_bound);
    _mm_store_ps(this->high, high_bound);
    place = 0;
    packed_item = item.list << index_bits | item.index;
}

Bvh build_bvh(LargeArray<BvhInput> inputs, const BvhCosts& costs) {
    // Two statements: the builder, and the inputs it sorted, are gone before the tree is collapsed.
    BinaryTree binary = Builder(std::move(inputs), costs).run();
    return collapse(std::move(binary));
}

std::size_t bvh_bytes(const Bvh& bvh) {
    return bvh.nodes.size() * sizeof(BvhNode) + bvh.items.size() * sizeof(BvhItem) +
           bvh.file_order.size() * sizeof(std::uint32_t);
}

}  // namespace twinray::sse
