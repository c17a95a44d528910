// The exact predicates (math/exact_predicates.h) against independent evaluations — long double where the value
// is clearly non-zero, exact integer arithmetic where it is at or near zero, constructions whose value is zero
// by algebra — and the two properties the watertight triangle test stands on: swapping an edge's end points
// negates its sign, and a ray through a vertex or an edge of a closed fan meets exactly one of its triangles.
#include "math/exact_predicates.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace math = twinray::math;
using math::Coordinates;

constexpr double unit_roundoff = 0x1p-53;

// [0, 1) from the generator's top 53 bits: the same numbers on every platform, which
// std::uniform_real_distribution does not promise.
double unit_interval(std::mt19937_64& rng) {
    return static_cast<double>(rng() >> 11) * 0x1p-53;
}

double uniform(std::mt19937_64& rng, double low, double high) {
    return low + (high - low) * unit_interval(rng);
}

// An integer in [low, high]; the modulo's bias (below 2^-40 here) does not matter to a test.
std::int64_t uniform_integer(std::mt19937_64& rng, std::int64_t low, std::int64_t high) {
    return low + static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(high - low + 1));
}

Coordinates plus(const Coordinates& p, const Coordinates& q) {
    return {p[0] + q[0], p[1] + q[1], p[2] + q[2]};
}
Coordinates minus(const Coordinates& p, const Coordinates& q) {
    return {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
}
Coordinates times(double s, const Coordinates& p) {
    return {s * p[0], s * p[1], s * p[2]};
}
Coordinates cross(const Coordinates& p, const Coordinates& q) {
    return {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
}
Coordinates normalized(const Coordinates& p) {
    return times(1 / std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), p);
}

// Each coordinate center ± half_width.
Coordinates random_point(std::mt19937_64& rng, const Coordinates& center, double half_width) {
    return {center[0] + uniform(rng, -half_width, half_width), center[1] + uniform(rng, -half_width, half_width),
            center[2] + uniform(rng, -half_width, half_width)};
}

// Up to 1e7 from the coordinate origin, on a logarithmic scale (so small offsets are as common as large).
Coordinates random_offset(std::mt19937_64& rng) {
    Coordinates offset;
    for (double& coordinate : offset) {
        coordinate = uniform(rng, -1, 1) * std::pow(10.0, uniform(rng, 0, 7));
    }
    return offset;
}

// A value or an input in hexadecimal floating point, so that a failure can be reproduced bit for bit.
std::string hex(const Coordinates& p) {
    std::ostringstream out;
    out << std::hexfloat << "(" << p[0] << ", " << p[1] << ", " << p[2] << ")";
    return out.str();
}
std::string describe(const Coordinates& origin, const Coordinates& direction, const Coordinates& a,
                     const Coordinates& b) {
    return "origin " + hex(origin) + " direction " + hex(direction) + " a " + hex(a) + " b " + hex(b);
}

// E as the formula reads, in double: what a test without exact arithmetic would see.
double naive_edge_value(const Coordinates& origin, const Coordinates& direction, const Coordinates& a,
                        const Coordinates& b) {
    Coordinates c = cross(minus(a, origin), minus(b, origin));
    return direction[0] * c[0] + direction[1] * c[1] + direction[2] * c[2];
}

// Σ |d_i|·(|(a − o)_j (b − o)_k| + |(a − o)_k (b − o)_j|) in double: E's rounding errors scale with it.
double naive_permanent(const Coordinates& origin, const Coordinates& direction, const Coordinates& a,
                       const Coordinates& b) {
    Coordinates to_a = minus(a, origin), to_b = minus(b, origin);
    double permanent = 0;
    for (int axis = 0; axis < 3; ++axis) {
        int j = (axis + 1) % 3, k = (axis + 2) % 3;
        permanent += std::fabs(direction[axis]) * (std::fabs(to_a[j] * to_b[k]) + std::fabs(to_a[k] * to_b[j]));
    }
    return permanent;
}

// Below this, double evaluation cannot tell E's sign (about the predicate's own filter bound).
bool double_is_unsure(const Coordinates& origin, const Coordinates& direction, const Coordinates& a,
                      const Coordinates& b) {
    return std::fabs(naive_edge_value(origin, direction, a, b)) <=
           8 * unit_roundoff * naive_permanent(origin, direction, a, b);
}

int sign_of(double value) {
    return (value > 0) - (value < 0);
}

// E and its permanent in long double (64-bit significand on x86-64; error below 8 roundings of it).
struct LongDoubleEdge {
    long double value = 0, permanent = 0;
};

LongDoubleEdge long_double_edge(const Coordinates& origin, const Coordinates& direction, const Coordinates& a,
                                const Coordinates& b) {
    LongDoubleEdge edge;
    std::array<long double, 3> to_a, to_b;
    for (int i = 0; i < 3; ++i) {
        to_a[i] = static_cast<long double>(a[i]) - origin[i];
        to_b[i] = static_cast<long double>(b[i]) - origin[i];
    }
    for (int axis = 0; axis < 3; ++axis) {
        int j = (axis + 1) % 3, k = (axis + 2) % 3;
        long double first = to_a[j] * to_b[k], second = to_a[k] * to_b[j];
        edge.value += direction[axis] * (first - second);
        edge.permanent += std::fabs(direction[axis]) * (std::fabs(first) + std::fabs(second));
    }
    return edge;
}

// Integer inputs and exact integer arithmetic (GCC's and Clang's 128-bit integers), an oracle independent of
// the predicates' expansions.
__extension__ typedef __int128 Int128;
using IntegerPoint = std::array<std::int64_t, 3>;

struct IntegerCase {
    IntegerPoint origin, direction, a, b;
};

Int128 exact_edge_value(const IntegerCase& c) {
    IntegerPoint to_a, to_b;
    for (int i = 0; i < 3; ++i) {
        to_a[i] = c.a[i] - c.origin[i];
        to_b[i] = c.b[i] - c.origin[i];
    }
    Int128 value = 0;
    for (int axis = 0; axis < 3; ++axis) {
        int j = (axis + 1) % 3, k = (axis + 2) % 3;
        value += Int128(c.direction[axis]) * (Int128(to_a[j]) * to_b[k] - Int128(to_a[k]) * to_b[j]);
    }
    return value;
}

// The tie-break the perturbed predicate promises, in integers.
int exact_perturbed_sign(const IntegerCase& c) {
    Int128 value = exact_edge_value(c);
    if (value != 0) {
        return value > 0 ? 1 : -1;
    }
    int kz = 0;
    for (int axis = 1; axis < 3; ++axis) {
        if (std::llabs(c.direction[axis]) > std::llabs(c.direction[kz])) {
            kz = axis;
        }
    }
    IntegerPoint edge;
    for (int i = 0; i < 3; ++i) {
        edge[i] = c.a[i] - c.b[i];
    }
    auto cross_component = [&](int axis) {
        int j = (axis + 1) % 3, k = (axis + 2) % 3;
        return Int128(edge[j]) * c.direction[k] - Int128(edge[k]) * c.direction[j];
    };
    Int128 first = cross_component((kz + 1) % 3), second = cross_component((kz + 2) % 3);
    Int128 decisive = first != 0 ? first : second;
    return (decisive > 0) - (decisive < 0);
}

// Near or at zero by construction: either the direction is p·(a − o) + q·(b − o) plus a step of at most one
// per coordinate, so that E = det(step, a − o, b − o) is at most 6·2^40 while each term summed to it reaches
// 2^64 (double evaluation rounds by 2^11 and more), or the edge is parallel to the direction (E and the
// tie-break both zero). Every coordinate is an integer below 2^42, exact in double.
IntegerCase near_degenerate_integer_case(std::mt19937_64& rng) {
    constexpr std::int64_t span = std::int64_t(1) << 20;
    auto random_integer_point = [&](std::int64_t half_width) {
        return IntegerPoint{uniform_integer(rng, -half_width, half_width),
                            uniform_integer(rng, -half_width, half_width),
                            uniform_integer(rng, -half_width, half_width)};
    };
    IntegerCase c;
    c.origin = random_integer_point(std::int64_t(1) << 40);
    IntegerPoint to_a = random_integer_point(span), to_b;
    if (uniform_integer(rng, 0, 3) == 0) {
        c.direction = random_integer_point(span);
        std::int64_t k = uniform_integer(rng, -3, 3);
        for (int i = 0; i < 3; ++i) {
            to_b[i] = to_a[i] + k * c.direction[i];
        }
    } else {
        to_b = random_integer_point(span);
        std::int64_t p = uniform_integer(rng, -8, 8), q = uniform_integer(rng, -8, 8);
        IntegerPoint step = uniform_integer(rng, 0, 2) == 0 ? IntegerPoint{} : random_integer_point(1);
        for (int i = 0; i < 3; ++i) {
            c.direction[i] = p * to_a[i] + q * to_b[i] + step[i];
        }
    }
    for (int i = 0; i < 3; ++i) {
        c.a[i] = c.origin[i] + to_a[i];
        c.b[i] = c.origin[i] + to_b[i];
    }
    return c;
}

// The integer point times 2^exponent, exactly (every exponent used keeps the values on the double grid).
Coordinates scaled_to_double(const IntegerPoint& p, int exponent) {
    return {std::ldexp(static_cast<double>(p[0]), exponent), std::ldexp(static_cast<double>(p[1]), exponent),
            std::ldexp(static_cast<double>(p[2]), exponent)};
}

TEST(ExactPredicates, SignAgreesWithLongDoubleWhereTheValueIsClearlyNonZero) {
    std::mt19937_64 rng(1);
    // Clearly non-zero: 32 roundings of long double away from zero, relative to the permanent; long double's
    // own error is below 8. Those within 8u of the permanent are beyond double: the exact path decides them.
    const long double clearly = 32 * std::numeric_limits<long double>::epsilon();
    constexpr int cases = 200000;
    int compared = 0, decided_beyond_double = 0;
    for (int n = 0; n < cases; ++n) {
        Coordinates offset = random_offset(rng);
        double scale = std::exp2(uniform(rng, -14, 14));
        Coordinates origin = random_point(rng, offset, scale);
        Coordinates a = random_point(rng, offset, scale), b = random_point(rng, offset, scale);
        Coordinates direction = times(std::exp2(uniform(rng, -10, 10)), random_point(rng, {0, 0, 0}, 1));
        if (n % 2 == 1) {
            // Aimed within about 2^-45 of the edge's line: the hard half.
            Coordinates on_line = plus(a, times(uniform(rng, -1, 2), minus(b, a)));
            Coordinates off_line = random_point(rng, {0, 0, 0}, scale * std::exp2(uniform(rng, -60, -45)));
            direction = minus(plus(on_line, off_line), origin);
        }
        LongDoubleEdge edge = long_double_edge(origin, direction, a, b);
        if (!(std::fabs(edge.value) > clearly * edge.permanent)) {
            continue;
        }
        ++compared;
        decided_beyond_double += double_is_unsure(origin, direction, a, b);
        int expected = edge.value > 0 ? 1 : -1;
        ASSERT_EQ(math::sign_of_ray_edge(origin, direction, a, b), expected)
            << describe(origin, direction, a, b) << "; long double E = " << static_cast<double>(edge.value)
            << ", permanent " << static_cast<double>(edge.permanent);
    }
    EXPECT_GT(compared, cases * 3 / 4) << compared << " of " << cases << " clearly non-zero";
    EXPECT_GT(decided_beyond_double, 1000)
        << decided_beyond_double << " of " << compared << " compared were beyond double evaluation";
}

TEST(ExactPredicates, SignMatchesExactIntegerArithmeticOnNearDegenerateInputs) {
    std::mt19937_64 rng(2);
    constexpr int cases = 200000;
    int zeros = 0, naive_wrong = 0;
    for (int n = 0; n < cases; ++n) {
        IntegerCase c = near_degenerate_integer_case(rng);
        Coordinates origin = scaled_to_double(c.origin, 0), direction = scaled_to_double(c.direction, 0);
        Coordinates a = scaled_to_double(c.a, 0), b = scaled_to_double(c.b, 0);
        Int128 exact = exact_edge_value(c);
        int expected = (exact > 0) - (exact < 0);
        double naive = naive_edge_value(origin, direction, a, b);
        ASSERT_EQ(math::sign_of_ray_edge(origin, direction, a, b), expected)
            << describe(origin, direction, a, b) << "; exact E ≈ " << static_cast<double>(exact) << ", in double "
            << naive;
        ASSERT_EQ(math::sign_of_ray_edge_perturbed(origin, direction, a, b), exact_perturbed_sign(c))
            << describe(origin, direction, a, b) << "; exact E ≈ " << static_cast<double>(exact);
        zeros += expected == 0;
        naive_wrong += sign_of(naive) != expected;
    }
    // Inputs that need the exact path: double evaluation gets many of them wrong.
    EXPECT_GT(naive_wrong, cases / 10) << "double evaluation wrong in " << naive_wrong << " of " << cases;
    EXPECT_GT(zeros, cases / 10) << zeros << " exact zeros of " << cases;
}

TEST(ExactPredicates, SignIsUnchangedByPowerOfTwoScalingAcrossTheWholeExponentRange) {
    // (points' exponent, direction's exponent): at 2^-1060 the differences are subnormal, and the products of
    // three underflow far below 2^-1074 unless the exact path scales them back up. From 2^900 the points (up to 2^41
    // before scaling) are past 2^339, where products of doubles overflow: long double's exponent holds them.
    constexpr std::array<std::array<int, 2>, 12> scalings{{{-1060, 0},
                                                           {0, -1060},
                                                           {-1000, -1000},
                                                           {-1060, -1060},
                                                           {-600, -300},
                                                           {250, 250},
                                                           {250, -1060},
                                                           {-1060, 250},
                                                           {900, 0},
                                                           {980, 990},
                                                           {980, -1060},
                                                           {-1060, 990}}};
    std::mt19937_64 rng(3);
    for (const std::array<int, 2>& scaling : scalings) {
        for (int n = 0; n < 20000; ++n) {
            IntegerCase c = near_degenerate_integer_case(rng);
            Coordinates origin = scaled_to_double(c.origin, scaling[0]);
            Coordinates a = scaled_to_double(c.a, scaling[0]), b = scaled_to_double(c.b, scaling[0]);
            Coordinates direction = scaled_to_double(c.direction, scaling[1]);
            Int128 exact = exact_edge_value(c);
            ASSERT_EQ(math::sign_of_ray_edge(origin, direction, a, b), (exact > 0) - (exact < 0))
                << "points ×2^" << scaling[0] << ", direction ×2^" << scaling[1] << ": "
                << describe(origin, direction, a, b) << "; unscaled exact E ≈ " << static_cast<double>(exact);
            ASSERT_EQ(math::sign_of_ray_edge_perturbed(origin, direction, a, b), exact_perturbed_sign(c))
                << "points ×2^" << scaling[0] << ", direction ×2^" << scaling[1] << ": "
                << describe(origin, direction, a, b);
        }
    }
}

// Coordinates spanning more than 2^600 (a vertex's x and y 2^-830 or less beside its z of 1): products of the small
// ones fall below the subnormals even after the exact path scales the points up, so only a wider exponent keeps
// them. The ray runs along z through the origin and the edge's end points lie at z = 1, so
// E = s²·(i1·i4 − i2·i3), s the small coordinates' scale, and its sign is that of an integer; an exact zero is broken
// by c = (a − b) × d = ((a − b)_y, −(a − b)_x, 0).
TEST(ExactPredicates, SignIsExactForCoordinatesSpanningMoreThanTwoToThe600) {
    std::mt19937_64 rng(6);
    int decided_in_the_wider_exponent = 0, cases = 0;
    for (int exponent : {-700, -830, -1000, -1040}) {
        const double s = std::ldexp(1.0, exponent);
        for (int n = 0; n < 5000; ++n) {
            std::array<std::int64_t, 4> i;
            for (std::int64_t& value : i) {
                value = uniform_integer(rng, -(std::int64_t{1} << 26), std::int64_t{1} << 26);
            }
            if (n % 2 == 0) {
                i[3] = i[1] * i[2] / (i[0] == 0 ? 1 : i[0]);  // near, or at, an exact zero
            }
            const Coordinates origin{0, 0, 0}, direction{0, 0, 1};
            const Coordinates a{s * static_cast<double>(i[0]), s * static_cast<double>(i[1]), 1};
            const Coordinates b{s * static_cast<double>(i[2]), s * static_cast<double>(i[3]), 1};
            const Int128 exact = static_cast<Int128>(i[0]) * i[3] - static_cast<Int128>(i[1]) * i[2];
            const int expected = (exact > 0) - (exact < 0);
            const std::int64_t c_x = i[1] - i[3], c_y = i[2] - i[0];
            const int perturbed = expected != 0 ? expected : c_x != 0 ? (c_x > 0) - (c_x < 0) : (c_y > 0) - (c_y < 0);
            ASSERT_EQ(math::sign_of_ray_edge(origin, direction, a, b), expected)
                << "2^" << exponent << ": " << describe(origin, direction, a, b)
                << "; exact E/s² = " << static_cast<double>(exact);
            ASSERT_EQ(math::sign_of_ray_edge_perturbed(origin, direction, a, b), perturbed)
                << "2^" << exponent << ": " << describe(origin, direction, a, b);
            decided_in_the_wider_exponent += expected != 0 && exponent <= -830;
            ++cases;
        }
    }
    EXPECT_GT(decided_in_the_wider_exponent, 1000) << "of " << cases;
}

TEST(ExactPredicates, ProductsThatUnderflowInTheFilterDoNotDecideTheSign) {
    // E = 2^600·(3·2^-1076 − 2^-1076) − 2^62·3·2^-538 = 2^-475 − 3·2^-476 = −2^-476. In double the first two
    // products underflow, to 2^-1074 and 0, and E evaluates to +2^-476, far above 8u times its permanent.
    Coordinates origin{0, 0, 0}, direction{0x1p600, 0x1p62, 0};
    Coordinates a{0, 0x3p-538, 0x1p-538}, b{-3, 0x1p-538, 0x1p-538};
    double naive = naive_edge_value(origin, direction, a, b);
    ASSERT_GT(naive, 0) << "the construction no longer misleads double evaluation: E = " << naive;
    EXPECT_EQ(math::sign_of_ray_edge(origin, direction, a, b), -1) << describe(origin, direction, a, b);
    EXPECT_EQ(math::sign_of_ray_edge(origin, direction, b, a), 1) << describe(origin, direction, b, a);
}

TEST(ExactPredicates, ExactZeroIsFoundWhereDoubleEvaluationIsNot) {
    std::mt19937_64 rng(4);
    constexpr int cases = 20000;
    int naive_non_zero = 0;
    for (int n = 0; n < cases; ++n) {
        Coordinates origin;
        for (double& coordinate : origin) {
            coordinate = (rng() % 2 == 0 ? 1 : -1) * uniform(rng, 5e6, 1e7);
        }
        double scale = std::exp2(uniform(rng, -10, 10));
        Coordinates a = random_point(rng, origin, scale), b = random_point(rng, origin, scale);
        // a − o and b − o are exact (Sterbenz: a and o are within a factor of two), multiples of 2^-30 below
        // 2^11, and so are small integer combinations of them: the ray lies exactly in the plane of the origin
        // and the edge, through p·a + q·b + (1 − p − q)·o — a itself for (p, q) = (1, 0), a point of the
        // edge's line when p + q = 1.
        Coordinates to_a = minus(a, origin), to_b = minus(b, origin);
        double p = static_cast<double>(uniform_integer(rng, -4, 4));
        double q = static_cast<double>(uniform_integer(rng, -4, 4));
        if (p == 0 && q == 0) {
            p = 1;
        }
        Coordinates direction = plus(times(p, to_a), times(q, to_b));
        double naive = naive_edge_value(origin, direction, a, b);
        ASSERT_EQ(math::sign_of_ray_edge(origin, direction, a, b), 0)
            << describe(origin, direction, a, b) << "; in double E = " << naive;
        // The tie-break is zero exactly when the direction is along the edge (q = −p).
        int perturbed = math::sign_of_ray_edge_perturbed(origin, direction, a, b);
        if (q == -p) {
            ASSERT_EQ(perturbed, 0) << describe(origin, direction, a, b);
        } else {
            ASSERT_NE(perturbed, 0) << describe(origin, direction, a, b);
        }
        naive_non_zero += naive != 0;
    }
    EXPECT_GT(naive_non_zero, cases / 4) << "double evaluation non-zero in " << naive_non_zero << " of " << cases;
}

TEST(ExactPredicates, SwappingTheEdgeEndPointsNegatesTheSign) {
    std::mt19937_64 rng(5);
    constexpr int cases = 150000;
    int zeros = 0, unsure = 0;
    for (int n = 0; n < cases; ++n) {
        Coordinates offset = random_offset(rng);
        double scale = std::exp2(uniform(rng, -14, 14));
        Coordinates a = random_point(rng, offset, scale), b = random_point(rng, offset, scale);
        Coordinates origin = random_point(rng, offset, scale);
        Coordinates direction = random_point(rng, {0, 0, 0}, 1);
        // A point of the edge's line, within an ulp of it (exactly on it for some of these s).
        constexpr std::array<double, 4> exact_steps{0.5, 2, -1, 0.25};
        double s = n % 6 < 2 ? exact_steps[rng() % 4] : uniform(rng, -2, 3);
        Coordinates on_line = plus(a, times(s, minus(b, a)));
        if (n % 3 == 1) {
            origin = on_line;
        } else if (n % 3 == 2) {
            direction = minus(on_line, origin);
        }
        int forward = math::sign_of_ray_edge(origin, direction, a, b);
        ASSERT_EQ(math::sign_of_ray_edge(origin, direction, b, a), -forward) << describe(origin, direction, a, b);
        int perturbed = math::sign_of_ray_edge_perturbed(origin, direction, a, b);
        ASSERT_NE(perturbed, 0) << describe(origin, direction, a, b);
        ASSERT_EQ(math::sign_of_ray_edge_perturbed(origin, direction, b, a), -perturbed)
            << describe(origin, direction, a, b);
        zeros += forward == 0;
        unsure += double_is_unsure(origin, direction, a, b);
    }
    // The near-degenerate two thirds reach the exact path and its zeros.
    EXPECT_GT(unsure, cases / 10) << unsure << " of " << cases << " beyond double evaluation";
    EXPECT_GT(zeros, cases / 100) << zeros << " exact zeros of " << cases;
}

// A closed fan of 3 to 12 triangles (center, rim[i], rim[i + 1]) in a plane of any orientation, radius 1e-4 to
// 1e4, up to 1e7 from the coordinate origin. Every point is snapped to a grid 2^-48 of the largest coordinate,
// so sums, halves and small differences of them are exact: a ray can be made to pass exactly through the
// centre or a spoke's midpoint.
struct Fan {
    Coordinates center;
    std::vector<Coordinates> rim;
    double radius, grid;
};

Coordinates snapped(const Coordinates& p, double grid) {
    return {std::nearbyint(p[0] / grid) * grid, std::nearbyint(p[1] / grid) * grid, std::nearbyint(p[2] / grid) * grid};
}

Fan random_fan(std::mt19937_64& rng) {
    Fan fan;
    fan.radius = std::pow(10.0, uniform(rng, -4, 4));
    Coordinates offset = random_offset(rng);
    double extent = std::max({std::fabs(offset[0]), std::fabs(offset[1]), std::fabs(offset[2])}) + 16 * fan.radius;
    fan.grid = std::exp2(std::ceil(std::log2(extent)) - 48);
    fan.center = snapped(offset, fan.grid);
    Coordinates normal;
    do {
        normal = random_point(rng, {0, 0, 0}, 1);
    } while (std::fabs(normal[0]) + std::fabs(normal[1]) + std::fabs(normal[2]) < 0.5);
    normal = normalized(normal);
    Coordinates u = normalized(cross(normal, std::fabs(normal[0]) < 0.5 ? Coordinates{1, 0, 0} : Coordinates{0, 1, 0}));
    Coordinates v = cross(normal, u);
    // Gaps between successive spokes in proportion to weights in [0.75, 1.25]: each below π even for three.
    int count = static_cast<int>(uniform_integer(rng, 3, 12));
    std::vector<double> weights(count);
    double total = 0;
    for (double& weight : weights) {
        weight = uniform(rng, 0.75, 1.25);
        total += weight;
    }
    double angle = uniform(rng, 0, 2 * std::numbers::pi);
    for (double weight : weights) {
        double length = fan.radius * uniform(rng, 0.5, 1);
        Coordinates spoke = plus(times(length * std::cos(angle), u), times(length * std::sin(angle), v));
        fan.rim.push_back(snapped(plus(fan.center, spoke), fan.grid));
        angle += 2 * std::numbers::pi * weight / total;
    }
    return fan;
}

struct Ray {
    Coordinates origin, direction;
};

// A ray from either side of the fan, at most about 55° from its normal, through `target` exactly: the
// direction is on the grid and origin = target − direction is exact.
Ray ray_through(std::mt19937_64& rng, const Fan& fan, const Coordinates& target) {
    Coordinates u = normalized(minus(fan.rim[0], fan.center));
    Coordinates normal = normalized(cross(minus(fan.rim[0], fan.center), minus(fan.rim[1], fan.center)));
    Coordinates v = cross(normal, u);
    double side = rng() % 2 == 0 ? 1 : -1;
    Coordinates tilted = plus(times(side, normal), plus(times(uniform(rng, -1, 1), u), times(uniform(rng, -1, 1), v)));
    Coordinates direction = snapped(times(fan.radius * uniform(rng, 1, 4), tilted), fan.grid);
    return {minus(target, direction), direction};
}

// The perturbed signs of each triangle's edges (center→rim[i], rim[i]→rim[i+1], rim[i+1]→center).
std::vector<std::array<int, 3>> edge_signs(const Fan& fan, const Ray& ray) {
    std::vector<std::array<int, 3>> signs;
    for (std::size_t i = 0; i < fan.rim.size(); ++i) {
        const Coordinates& here = fan.rim[i];
        const Coordinates& next = fan.rim[(i + 1) % fan.rim.size()];
        signs.push_back({math::sign_of_ray_edge_perturbed(ray.origin, ray.direction, fan.center, here),
                         math::sign_of_ray_edge_perturbed(ray.origin, ray.direction, here, next),
                         math::sign_of_ray_edge_perturbed(ray.origin, ray.direction, next, fan.center)});
    }
    return signs;
}

int triangles_hit(const std::vector<std::array<int, 3>>& signs) {
    int hits = 0;
    for (const std::array<int, 3>& s : signs) {
        hits += s[0] != 0 && s[0] == s[1] && s[1] == s[2];
    }
    return hits;
}

std::string describe(const Fan& fan, const Ray& ray, const std::vector<std::array<int, 3>>& signs) {
    std::string text = "ray " + hex(ray.origin) + " + t·" + hex(ray.direction) + "; centre " + hex(fan.center);
    for (std::size_t i = 0; i < fan.rim.size(); ++i) {
        text += "\n  rim " + hex(fan.rim[i]) + " signs " + std::to_string(signs[i][0]) + " " +
                std::to_string(signs[i][1]) + " " + std::to_string(signs[i][2]);
    }
    return text;
}

TEST(ExactPredicates, ARayThroughAFanVertexHitsExactlyOneTriangle) {
    std::mt19937_64 rng(6);
    for (int n = 0; n < 5000; ++n) {
        Fan fan = random_fan(rng);
        for (int r = 0; r < 4; ++r) {
            Ray ray = ray_through(rng, fan, fan.center);
            // Exactly through the centre: every spoke's E is zero, left to the tie-break.
            ASSERT_EQ(math::sign_of_ray_edge(ray.origin, ray.direction, fan.center, fan.rim[0]), 0)
                << describe(ray.origin, ray.direction, fan.center, fan.rim[0]);
            std::vector<std::array<int, 3>> signs = edge_signs(fan, ray);
            ASSERT_EQ(triangles_hit(signs), 1) << describe(fan, ray, signs);
        }
    }
}

TEST(ExactPredicates, ARayThroughAFanSpokesMidpointHitsExactlyOneTriangle) {
    std::mt19937_64 rng(7);
    for (int n = 0; n < 5000; ++n) {
        Fan fan = random_fan(rng);
        for (const Coordinates& end : fan.rim) {
            Coordinates midpoint = times(0.5, plus(fan.center, end));
            Ray ray = ray_through(rng, fan, midpoint);
            // Exactly through the spoke: its E is zero in both triangles beside it.
            ASSERT_EQ(math::sign_of_ray_edge(ray.origin, ray.direction, fan.center, end), 0)
                << describe(ray.origin, ray.direction, fan.center, end);
            std::vector<std::array<int, 3>> signs = edge_signs(fan, ray);
            ASSERT_EQ(triangles_hit(signs), 1) << "through " << hex(midpoint) << ": " << describe(fan, ray, signs);
        }
    }
}

// Exactly collinear triples: the textbook one, two 3e7 from the origin on a dyadic step (a + k·step exact), and
// one on a step of full significands, whose products round.
std::vector<std::array<Coordinates, 3>> collinear_triples() {
    Coordinates base{1e7, -3e7, 12345.678}, step{0.25, -0.5, 0.125};
    Coordinates full_step{0.422, 0.873, -0.156};
    return {{{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}},
            {{base, plus(base, times(3, step)), plus(base, times(-7, step))}},
            {{plus(base, times(11, step)), base, plus(base, times(5, step))}},
            {{{0, 0, 0}, full_step, times(2, full_step)}}};
}

TEST(ExactPredicates, CollinearIsTrueForRepeatedAndExactlyCollinearPoints) {
    Coordinates a{0.1, -2.5e7, 3e-3}, b{-7.25, 1e-30, 4e5};
    EXPECT_TRUE(math::exactly_collinear(a, a, a));
    EXPECT_TRUE(math::exactly_collinear(a, a, b));
    EXPECT_TRUE(math::exactly_collinear(a, b, a));
    EXPECT_TRUE(math::exactly_collinear(b, a, a));
    for (const std::array<Coordinates, 3>& triple : collinear_triples()) {
        EXPECT_TRUE(math::exactly_collinear(triple[0], triple[1], triple[2]))
            << hex(triple[0]) << " " << hex(triple[1]) << " " << hex(triple[2]);
    }
}

TEST(ExactPredicates, CollinearIsFalseForPointsOneUlpOffTheirLine) {
    constexpr double infinity = std::numeric_limits<double>::infinity();
    int naive_zero = 0, nudged = 0;
    for (const std::array<Coordinates, 3>& triple : collinear_triples()) {
        for (int point = 1; point < 3; ++point) {
            for (int axis = 0; axis < 3; ++axis) {
                for (double toward : {-infinity, infinity}) {
                    std::array<Coordinates, 3> off = triple;
                    off[point][axis] = std::nextafter(off[point][axis], toward);
                    Coordinates naive = cross(minus(off[1], off[0]), minus(off[2], off[0]));
                    EXPECT_FALSE(math::exactly_collinear(off[0], off[1], off[2]))
                        << hex(off[0]) << " " << hex(off[1]) << " " << hex(off[2])
                        << "; in double (b − a) × (c − a) = " << hex(naive);
                    naive_zero += naive == Coordinates{0, 0, 0};
                    ++nudged;
                }
            }
        }
    }
    // The step of full significands loses a one-ulp nudge in its rounded products: double evaluation finds
    // some of these collinear.
    EXPECT_GT(naive_zero, 0) << naive_zero << " of " << nudged << " look collinear in double";
}

}  // namespace
