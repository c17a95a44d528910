// CSG for the SSE tracer: span lists in fixed-capacity arrays on the stack, never a heap allocation per
// ray (the thesis's cylinder gained 1% because its intersection returned a heap-allocated interval
// container). The algorithm is the reference's (reference/csg.h): a sweep over both operands' crossings
// in order of t, crossings at equal t applied together, the earliest primitive bounding the result.
#pragma once

#include "scene/scene.h"
#include "sse/mutation.h"

#include <algorithm>
#include <cstdint>
#include <limits>

namespace twinray::sse {

// Tag bits of a crossing: the face (meaning per primitive type), and whether the outward normal is
// turned around (the crossing bounds a complement: a subtracted primitive's surface faces the cavity).
constexpr std::int32_t tag_face_mask = 0xF;
constexpr std::int32_t tag_flipped = 0x10;

// The reference's Crossing (reference/ray.h) with a face code and flag in place of the outward normal:
// the normal is worked out once, for the nearest hit only.
struct Crossing {
    float t;
    std::int32_t leaf;  // -1 for the infinite ends of a half-space
    std::int32_t tag;
};

// A span list of one CSG subtree. A result has at most (finite crossings)/2 + 1 spans, and every leaf
// adds at most two finite crossings, so max_csg_leaves + 1 spans always suffice.
struct SpanArray {
    static constexpr int capacity = scene::max_csg_leaves + 1;
    int count = 0;
    Crossing enter[capacity];
    Crossing exit[capacity];

    void clear() { count = 0; }
    // Copies only the spans in use, not the whole capacity.
    void assign(const SpanArray& other) {
        count = other.count;
        std::copy(other.enter, other.enter + count, enter);
        std::copy(other.exit, other.exit + count, exit);
    }
    void push(const Crossing& in, const Crossing& out) {
        enter[count] = in;
        exit[count] = out;
        ++count;
    }
};

inline Crossing far_end(float sign) {
    return {sign * std::numeric_limits<float>::infinity(), -1, 0};
}

inline void complement(const SpanArray& spans, SpanArray& gaps) {
    auto turned = [](Crossing crossing) {
        crossing.tag ^= tag_flipped;
        return crossing;
    };
    gaps.clear();
    Crossing gap_start = far_end(-1.0f);
    for (int i = 0; i < spans.count; ++i) {
        if (spans.enter[i].t > gap_start.t) {
            gaps.push(gap_start, turned(spans.enter[i]));
        }
        gap_start = turned(spans.exit[i]);
    }
    if (gap_start.t < std::numeric_limits<float>::infinity()) {
        gaps.push(gap_start, far_end(1.0f));
    }
}

// Both inputs are sorted, so their crossings merge in order without sorting: event 2i of a list is the
// enter of span i, event 2i + 1 its exit.
template <typename Inside>
void sweep(const SpanArray& a, const SpanArray& b, Inside inside, SpanArray& out) {
    auto event_t = [](const SpanArray& list, int event) {
        return (event & 1) ? list.exit[event >> 1].t : list.enter[event >> 1].t;
    };
    auto event_crossing = [](const SpanArray& list, int event) -> const Crossing& {
        return (event & 1) ? list.exit[event >> 1] : list.enter[event >> 1];
    };
    out.clear();
    int next[2] = {0, 0};
    const int end[2] = {2 * a.count, 2 * b.count};
    const SpanArray* lists[2] = {&a, &b};
    bool in[2] = {false, false};
    Crossing open_enter{};
    while (next[0] < end[0] || next[1] < end[1]) {
        float t = std::numeric_limits<float>::infinity();
        int first = -1;  // the list whose event sets t
        for (int k = 0; k < 2; ++k) {
            if (next[k] < end[k] && (first < 0 || event_t(*lists[k], next[k]) < t)) {
                t = event_t(*lists[k], next[k]);
                first = k;
            }
        }
        bool was_inside = inside(in[0], in[1]);
        const Crossing* bound[2] = {nullptr, nullptr};  // per direction: 0 leaving, 1 entering
        for (int k = 0; k < 2; ++k) {
            // The event that set t is taken even if t is NaN (a ray made of NaNs), which equals nothing:
            // every pass takes one event at least, so the sweep ends.
            bool take = k == first;
            while (next[k] < end[k] && (take || event_t(*lists[k], next[k]) == t)) {
                take = false;
                bool enters = (next[k] & 1) == 0;
                const Crossing& crossing = event_crossing(*lists[k], next[k]);
                in[k] = enters;
                const Crossing*& best = bound[enters ? 1 : 0];
                if (best == nullptr || crossing.leaf < best->leaf) {
                    best = &crossing;
                }
                ++next[k];
            }
        }
        bool now_inside = inside(in[0], in[1]);
        if (was_inside != now_inside) {
            if (now_inside) {
                open_enter = *bound[1];
            } else {
                out.push(open_enter, *bound[0]);
            }
        }
    }
}

inline void csg_combine(scene::CsgOp op, const SpanArray& a, const SpanArray& b, SpanArray& scratch, SpanArray& out) {
    switch (op) {
        case scene::CsgOp::union_:
            sweep(
                a, b, [](bool x, bool y) { return mutated<Mutant::csg_union_intersection_swapped> ? x && y : x || y; },
                out);
            break;
        case scene::CsgOp::intersection:
            sweep(
                a, b, [](bool x, bool y) { return mutated<Mutant::csg_union_intersection_swapped> ? x || y : x && y; },
                out);
            break;
        case scene::CsgOp::difference:
            complement(b, scratch);
            sweep(
                a, scratch, [](bool x, bool y) { return x && y; }, out);
            break;
    }
}

}  // namespace twinray::sse
