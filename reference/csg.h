// Constructive solid geometry on span lists: the boolean operation applied along the ray's line.
#pragma once

#include "reference/ray.h"

#include <algorithm>
#include <cstddef>

namespace twinray::reference {

namespace csg_detail {

// Everything of the line outside the spans: the complement's crossings are the same surfaces with
// their outward normal turned around (a subtracted solid's surface faces into the cavity).
template <typename T>
SpanList<T> complement(const SpanList<T>& spans) {
    auto turned = [](Crossing<T> crossing) {
        crossing.outward_normal = -crossing.outward_normal;
        return crossing;
    };
    SpanList<T> gaps;
    Crossing<T> gap_start = infinitely_far(T(-1));
    for (const Span<T>& span : spans) {
        if (span.enter.t > gap_start.t) {
            gaps.push_back({gap_start, turned(span.enter)});
        }
        gap_start = turned(span.exit);
    }
    if (gap_start.t < std::numeric_limits<T>::infinity()) {
        gaps.push_back({gap_start, infinitely_far(T(1))});
    }
    return gaps;
}

template <typename T>
struct Event {
    Crossing<T> crossing;
    bool enters;
    int operand;  // 0 or 1
};

// A sweep over both lists' crossings in order of t, tracking whether the line is inside each operand.
// Crossings at the same t are applied together, so touching solids leave no seam; where the result
// changes, the crossing of the earliest primitive (smallest leaf) that moved the same way bounds it.
template <typename T, typename Inside>
SpanList<T> sweep(const SpanList<T>& a, const SpanList<T>& b, Inside inside) {
    std::vector<Event<T>> events;
    for (int operand = 0; operand < 2; ++operand) {
        for (const Span<T>& span : operand == 0 ? a : b) {
            events.push_back({span.enter, true, operand});
            events.push_back({span.exit, false, operand});
        }
    }
    std::stable_sort(events.begin(), events.end(),
                     [](const Event<T>& x, const Event<T>& y) { return x.crossing.t < y.crossing.t; });
    SpanList<T> result;
    bool in[2] = {false, false};
    Crossing<T> open_enter;
    for (std::size_t first = 0; first < events.size();) {
        // The first event is taken even if its t is NaN (a ray made of NaNs), which equals nothing: every
        // pass takes one event at least, so the sweep ends.
        std::size_t last = first + 1;
        while (last < events.size() && events[last].crossing.t == events[first].crossing.t) {
            ++last;
        }
        bool was_inside = inside(in[0], in[1]);
        for (std::size_t i = first; i < last; ++i) {
            in[events[i].operand] = events[i].enters;
        }
        bool now_inside = inside(in[0], in[1]);
        if (was_inside != now_inside) {
            const Event<T>* bound = nullptr;
            for (std::size_t i = first; i < last; ++i) {
                if (events[i].enters == now_inside &&
                    (bound == nullptr || events[i].crossing.leaf < bound->crossing.leaf)) {
                    bound = &events[i];
                }
            }
            if (now_inside) {
                open_enter = bound->crossing;
            } else {
                result.push_back({open_enter, bound->crossing});
            }
        }
        first = last;
    }
    return result;
}

}  // namespace csg_detail

template <typename T>
SpanList<T> csg_union(const SpanList<T>& a, const SpanList<T>& b) {
    return csg_detail::sweep(a, b, [](bool in_a, bool in_b) { return in_a || in_b; });
}

template <typename T>
SpanList<T> csg_intersection(const SpanList<T>& a, const SpanList<T>& b) {
    return csg_detail::sweep(a, b, [](bool in_a, bool in_b) { return in_a && in_b; });
}

template <typename T>
SpanList<T> csg_difference(const SpanList<T>& a, const SpanList<T>& b) {
    return csg_intersection(a, csg_detail::complement(b));
}

}  // namespace twinray::reference
