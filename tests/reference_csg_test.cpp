// The span operations of reference/csg.h directly, on spans along a line in +x. The first hits they give
// through whole CSG trees are hand-solved expectations of every tracer: src/plugin/hand_solved_csg.cpp.
#include "reference/csg.h"

#include <gtest/gtest.h>

#include <limits>

namespace {

using twinray::reference::Crossing;
using twinray::reference::Span;
using twinray::reference::SpanList;
using V = twinray::reference::Vec3<double>;

Crossing<double> at(double t, double normal_x, int leaf) {
    return {t, V(normal_x, 0, 0), leaf};
}

// A solid's span along +x: entered through a face facing −x, left through one facing +x.
Span<double> solid(double enter, double exit, int leaf) {
    return {at(enter, -1, leaf), at(exit, 1, leaf)};
}

void expect_crossing(const Crossing<double>& actual, double t, double normal_x, int leaf) {
    EXPECT_EQ(actual.t, t);
    EXPECT_EQ(actual.outward_normal.x, normal_x);
    EXPECT_EQ(actual.leaf, leaf);
}

TEST(ReferenceCsgSpans, UnionOfOverlappingSpansIsOneSpanFromFirstEntryToLastExit) {
    SpanList<double> result = twinray::reference::csg_union<double>({solid(1, 3, 0)}, {solid(2, 5, 1)});
    ASSERT_EQ(result.size(), 1u);
    expect_crossing(result[0].enter, 1, -1, 0);
    expect_crossing(result[0].exit, 5, 1, 1);
}

TEST(ReferenceCsgSpans, UnionOfTouchingSpansLeavesNoSeamWhereTheyTouch) {
    SpanList<double> result = twinray::reference::csg_union<double>({solid(1, 2, 0)}, {solid(2, 3, 1)});
    ASSERT_EQ(result.size(), 1u);
    expect_crossing(result[0].enter, 1, -1, 0);
    expect_crossing(result[0].exit, 3, 1, 1);
}

TEST(ReferenceCsgSpans, IntersectionIsBoundedByTheLaterEntryAndTheEarlierExit) {
    SpanList<double> result = twinray::reference::csg_intersection<double>({solid(1, 3, 0)}, {solid(2, 5, 1)});
    ASSERT_EQ(result.size(), 1u);
    expect_crossing(result[0].enter, 2, -1, 1);
    expect_crossing(result[0].exit, 3, 1, 0);
    EXPECT_TRUE(twinray::reference::csg_intersection<double>({solid(1, 2, 0)}, {solid(3, 4, 1)}).empty());
}

// [1,5] minus [2,3]: two pieces; the cavity's walls are the subtrahend's crossings with their normals
// turned to face into the cavity.
TEST(ReferenceCsgSpans, DifferenceSplitsTheSpanWithCavityWallsFacingIntoTheCavity) {
    SpanList<double> result = twinray::reference::csg_difference<double>({solid(1, 5, 0)}, {solid(2, 3, 1)});
    ASSERT_EQ(result.size(), 2u);
    expect_crossing(result[0].enter, 1, -1, 0);
    expect_crossing(result[0].exit, 2, 1, 1);
    expect_crossing(result[1].enter, 3, -1, 1);
    expect_crossing(result[1].exit, 5, 1, 0);
}

TEST(ReferenceCsgSpans, DifferenceWithNothingOrEverythingRemovedKeepsOrEmptiesTheSpan) {
    SpanList<double> kept = twinray::reference::csg_difference<double>({solid(1, 5, 0)}, {});
    ASSERT_EQ(kept.size(), 1u);
    expect_crossing(kept[0].enter, 1, -1, 0);
    expect_crossing(kept[0].exit, 5, 1, 0);
    EXPECT_TRUE(twinray::reference::csg_difference<double>({solid(1, 5, 0)}, {solid(0, 6, 1)}).empty());
}

// Both operands enter at t = 1: the bound is the crossing of the smaller leaf, though it is in b.
TEST(ReferenceCsgSpans, CrossingsAtTheSameTAreBoundedByTheSmallestLeaf) {
    SpanList<double> result = twinray::reference::csg_union<double>({solid(1, 2, 3)}, {solid(1, 4, 1)});
    ASSERT_EQ(result.size(), 1u);
    expect_crossing(result[0].enter, 1, -1, 1);
    expect_crossing(result[0].exit, 4, 1, 1);
}

// A ray made of NaNs has NaN crossings, which equal nothing: the sweep looped forever on the first one
// (found by bvh_differential_fuzz, tests/data/fuzz_regressions/bvh_differential/). Every operation, either
// operand first, must end with no more spans than its operands hold.
TEST(ReferenceCsgSpans, ASweepOverNanCrossingsEnds) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const SpanList<double> a = {solid(nan, nan, 0)};
    const SpanList<double> b = {solid(1, 2, 1), solid(nan, 3, 1)};
    for (const auto& combine : {twinray::reference::csg_union<double>, twinray::reference::csg_intersection<double>,
                                twinray::reference::csg_difference<double>}) {
        EXPECT_LE(combine(a, b).size(), 4u);
        EXPECT_LE(combine(b, a).size(), 4u);
    }
}

}  // namespace
