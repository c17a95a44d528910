// Filters in double, then expansions (Shewchuk 1997): a value held as a sum of doubles (or long doubles) that do not
// overlap, in increasing magnitude, zeros removed, so that sums and products are exact and the sign is that of the
// largest (last) component. A filter never decides where its arithmetic overflowed: an infinite or NaN value or
// bound fails its test, and the exact path takes over. Two-Product is std::fma's error term (explicit, so
// -ffp-contract=off leaves it alone); -ffast-math, which the build never uses, would reassociate Two-Sum into nothing.
#include "math/exact_predicates.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <optional>

namespace twinray::math {
namespace {

constexpr double unit_roundoff = 0x1p-53;
// Eight times the largest error of a product that underflows (half the smallest subnormal, 2^-1075).
constexpr double underflow_slack = 0x1p-1072;

// The expansions' arithmetic is written once for two types. In double it is exact while every product's error lies on
// the double grid, which exact_range_shift sees to where the inputs allow it. In long double (x87's 64-bit significand
// and 15-bit exponent, on every x86-64) it is exact for any finite doubles, unscaled: a product of three differences
// of doubles is a multiple of 2^-3222 and below 2^3078, far within its range. It is the slower, so it is taken only
// where double cannot be exact.

// high + low, exactly, high the rounded value.
template <typename Real>
struct TwoTerms {
    Real high, low;
};

// Knuth's Two-Sum: exact for any finite x and y.
template <typename Real>
TwoTerms<Real> two_sum(Real x, Real y) {
    Real sum = x + y;
    Real y_part = sum - x;
    Real x_part = sum - y_part;
    return {sum, (x - x_part) + (y - y_part)};
}

// Exact when the error lies on the grid of Real.
template <typename Real>
TwoTerms<Real> two_product(Real x, Real y) {
    Real product = x * y;
    return {product, std::fma(x, y, -product)};
}

template <typename Real, int Capacity>
struct Expansion {
    // Only the first `size` are set: zeroing the rest cost the exact path half its time.
    std::array<Real, Capacity> components;
    int size = 0;

    void append(Real component) {
        if (component != 0) {
            components[size++] = component;
        }
    }
};

template <typename Real, int Capacity>
int sign(const Expansion<Real, Capacity>& e) {
    if (e.size == 0) {
        return 0;
    }
    return e.components[e.size - 1] > 0 ? 1 : -1;
}

template <typename Real>
Expansion<Real, 2> difference(Real x, Real y) {
    TwoTerms<Real> exact = two_sum(x, -y);
    Expansion<Real, 2> e;
    e.append(exact.low);
    e.append(exact.high);
    return e;
}

template <typename Real, int Capacity>
void negate(Expansion<Real, Capacity>& e) {
    for (int i = 0; i < e.size; ++i) {
        e.components[i] = -e.components[i];
    }
}

// Fast-Expansion-Sum with zero elimination: both inputs' components merged by magnitude and accumulated from
// the smallest by Two-Sum (Shewchuk's Theorem 13: exact, the result again strongly non-overlapping).
template <typename Real, int M, int N>
Expansion<Real, M + N> sum(const Expansion<Real, M>& e, const Expansion<Real, N>& f) {
    Expansion<Real, M + N> h;
    if (e.size + f.size == 0) {
        return h;
    }
    int i = 0, j = 0;
    auto next_smallest = [&] {
        bool from_e = j == f.size || (i < e.size && std::fabs(e.components[i]) < std::fabs(f.components[j]));
        return from_e ? e.components[i++] : f.components[j++];
    };
    Real running = next_smallest();
    while (i + j < e.size + f.size) {
        TwoTerms<Real> step = two_sum(running, next_smallest());
        h.append(step.low);
        running = step.high;
    }
    h.append(running);
    return h;
}

// Scale-Expansion with zero elimination (Shewchuk's Theorem 19): e·factor exactly.
template <typename Real, int N>
Expansion<Real, 2 * N> scaled(const Expansion<Real, N>& e, Real factor) {
    Expansion<Real, 2 * N> h;
    if (e.size == 0) {
        return h;
    }
    TwoTerms<Real> first = two_product(e.components[0], factor);
    h.append(first.low);
    Real carry = first.high;
    for (int i = 1; i < e.size; ++i) {
        TwoTerms<Real> product = two_product(e.components[i], factor);
        TwoTerms<Real> low = two_sum(carry, product.low);
        h.append(low.low);
        TwoTerms<Real> high = two_sum(product.high, low.high);
        h.append(high.low);
        carry = high.high;
    }
    h.append(carry);
    return h;
}

// x·y for two exact differences.
template <typename Real>
Expansion<Real, 8> product(const Expansion<Real, 2>& x, const Expansion<Real, 2>& y) {
    Expansion<Real, 4> none;
    return sum(y.size > 0 ? scaled(x, y.components[0]) : none, y.size > 1 ? scaled(x, y.components[1]) : none);
}

template <typename Real>
using Differences = std::array<Expansion<Real, 2>, 3>;

template <typename Real>
Differences<Real> differences(const Coordinates& p, const Coordinates& q) {
    return {difference<Real>(p[0], q[0]), difference<Real>(p[1], q[1]), difference<Real>(p[2], q[2])};
}

// (x × y)[axis], exactly.
template <typename Real>
Expansion<Real, 16> cross_component(const Differences<Real>& x, const Differences<Real>& y, int axis) {
    int j = (axis + 1) % 3, k = (axis + 2) % 3;
    Expansion<Real, 8> subtracted = product(x[k], y[j]);
    negate(subtracted);
    return sum(product(x[j], y[k]), subtracted);
}

// Two-Product is exact only while its error is a multiple of 2^-1074, which products of tiny inputs are not.
// Powers of two scale exactly, and scaling the points (or one side of a cross product) by one and the
// direction by another changes E only by a positive factor, so each group of inputs is scaled up until its
// largest magnitude is at least 2^300, never down (that could round). A non-zero coordinate at most 2^600
// below it is then at least 2^-300, a multiple of 2^-352, and so is every difference: a product of three is
// a multiple of 2^-1056, on the grid. Below 2^339 (2^301 if scaled) a sum of six such products stays below
// 2^1022: no overflow. A group that spans more, or reaches higher, is left to long double.
constexpr int exact_range_exponent = 300;
constexpr int double_exact_span_exponent = 600;
constexpr double double_exact_coordinate_limit = 0x1p339;

// The shift that brings the group's largest magnitude to at least 2^300, or nothing where double cannot be exact
// for it (its non-zero magnitudes span more than 2^600, or one is at least 2^339).
std::optional<int> exact_range_shift(std::initializer_list<Coordinates> group) {
    double largest = 0, least = std::numeric_limits<double>::infinity();
    for (const Coordinates& point : group) {
        for (double coordinate : point) {
            const double magnitude = std::fabs(coordinate);
            largest = std::max(largest, magnitude);
            least = magnitude > 0 ? std::min(least, magnitude) : least;
        }
    }
    if (largest == 0) {
        return 0;
    }
    if (largest >= double_exact_coordinate_limit ||
        std::ilogb(largest) - std::ilogb(least) > double_exact_span_exponent) {
        return std::nullopt;
    }
    return std::max(0, exact_range_exponent - std::ilogb(largest));
}

Coordinates shifted(const Coordinates& v, int shift) {
    return {std::ldexp(v[0], shift), std::ldexp(v[1], shift), std::ldexp(v[2], shift)};
}

// E exactly, in Real, from inputs on which Real's expansions are exact.
template <typename Real>
int exact_sign_of_ray_edge_in(const Coordinates& origin, const Coordinates& direction, const Coordinates& a,
                              const Coordinates& b) {
    Differences<Real> to_a = differences<Real>(a, origin);
    Differences<Real> to_b = differences<Real>(b, origin);
    auto term = [&](int axis) { return scaled(cross_component(to_a, to_b, axis), static_cast<Real>(direction[axis])); };
    return sign(sum(sum(term(0), term(1)), term(2)));
}

int exact_sign_of_ray_edge(const Coordinates& origin, const Coordinates& direction, const Coordinates& a,
                           const Coordinates& b) {
    std::optional<int> point_shift = exact_range_shift({origin, a, b});
    std::optional<int> direction_shift = exact_range_shift({direction});
    if (!point_shift || !direction_shift) {
        return exact_sign_of_ray_edge_in<long double>(origin, direction, a, b);
    }
    return exact_sign_of_ray_edge_in<double>(shifted(origin, *point_shift), shifted(direction, *direction_shift),
                                             shifted(a, *point_shift), shifted(b, *point_shift));
}

// The sign of ((p − q) × (r − s))[axis]. Filter: in double, each of the value's two monomials passes
// through four roundings (two differences, its product, the subtraction: relative error γ(4)), and a
// product that underflows errs by up to η = 2^-1075 instead; the sum ŝ of the two products' magnitudes as
// computed is short of the exact one by at most three roundings and 2η. So the value is off by at most
// 4.001u·ŝ + 2.001η, which 8u·ŝ + 8η, computed (two more roundings), exceeds.
int sign_of_cross_component(const Coordinates& p, const Coordinates& q, const Coordinates& r, const Coordinates& s,
                            int axis) {
    int j = (axis + 1) % 3, k = (axis + 2) % 3;
    double first = (p[j] - q[j]) * (r[k] - s[k]);
    double second = (p[k] - q[k]) * (r[j] - s[j]);
    double value = first - second;
    double bound = 8 * unit_roundoff * (std::fabs(first) + std::fabs(second)) + underflow_slack;
    if (std::fabs(value) > bound) {
        return value > 0 ? 1 : -1;
    }
    std::optional<int> pair_shift = exact_range_shift({p, q}), other_pair_shift = exact_range_shift({r, s});
    if (!pair_shift || !other_pair_shift) {
        return sign(cross_component(differences<long double>(p, q), differences<long double>(r, s), axis));
    }
    return sign(cross_component(differences<double>(shifted(p, *pair_shift), shifted(q, *pair_shift)),
                                differences<double>(shifted(r, *other_pair_shift), shifted(s, *other_pair_shift)),
                                axis));
}

int largest_axis(const Coordinates& v) {
    int largest = 0;
    for (int axis = 1; axis < 3; ++axis) {
        if (std::fabs(v[axis]) > std::fabs(v[largest])) {
            largest = axis;
        }
    }
    return largest;
}

}  // namespace

// Filter: Ê, E evaluated as written in double, differs from E by at most 7.001u·P̂ + 1.001η·(2‖d‖₁ + 3), with
// u = 2^-53, η = 2^-1075 and P̂ = Σ |d_i|·(|p_i| + |q_i|) computed in double from the same products p_i, q_i
// of (a − o) × (b − o). Why: each of E's six monomials d_i·(a − o)_j·(b − o)_k passes through at most seven
// roundings (two differences, the product, the subtraction, the product with d_i, two of the three-term
// sum: relative error γ(7), Higham §3.1); a product that underflows errs by up to η instead, magnified by
// |d_i| when it is a product of differences (2·‖d‖₁·η over the six) and not when it is the product with d_i
// (3η); and the exact permanent P = Σ |d_i|·(|(a − o)_j·(b − o)_k| + |(a − o)_k·(b − o)_j|) is at most
// (P̂ + η·(2‖d‖₁ + 3))/(1 − u)⁷, P̂ being P after seven roundings and those underflow errors. The bound below,
// 8u·P̂ + 8η·(‖d‖∞ + 1) evaluated in double (four roundings, two of which may underflow by η), still exceeds
// it; where |Ê| is above it, Ê has E's sign.
int sign_of_ray_edge(const Coordinates& origin, const Coordinates& direction, const Coordinates& a,
                     const Coordinates& b) {
    Coordinates to_a{a[0] - origin[0], a[1] - origin[1], a[2] - origin[2]};
    Coordinates to_b{b[0] - origin[0], b[1] - origin[1], b[2] - origin[2]};
    double value = 0, permanent = 0;
    for (int axis = 0; axis < 3; ++axis) {
        int j = (axis + 1) % 3, k = (axis + 2) % 3;
        double first = to_a[j] * to_b[k], second = to_a[k] * to_b[j];
        value += direction[axis] * (first - second);
        permanent += std::fabs(direction[axis]) * (std::fabs(first) + std::fabs(second));
    }
    double largest_direction = std::max({std::fabs(direction[0]), std::fabs(direction[1]), std::fabs(direction[2])});
    double bound = 8 * unit_roundoff * permanent + underflow_slack * (largest_direction + 1);
    if (std::fabs(value) > bound) {
        return value > 0 ? 1 : -1;
    }
    return exact_sign_of_ray_edge(origin, direction, a, b);
}

int sign_of_ray_edge_perturbed(const Coordinates& origin, const Coordinates& direction, const Coordinates& a,
                               const Coordinates& b) {
    int unperturbed = sign_of_ray_edge(origin, direction, a, b);
    if (unperturbed != 0) {
        return unperturbed;
    }
    int kz = largest_axis(direction);
    int kx = (kz + 1) % 3, ky = (kz + 2) % 3;
    // c = (a − b) × (direction − 0).
    constexpr Coordinates zero{};
    int first_order = sign_of_cross_component(a, b, direction, zero, kx);
    return first_order != 0 ? first_order : sign_of_cross_component(a, b, direction, zero, ky);
}

bool exactly_collinear(const Coordinates& a, const Coordinates& b, const Coordinates& c) {
    for (int axis = 0; axis < 3; ++axis) {
        if (sign_of_cross_component(b, a, c, a, axis) != 0) {
            return false;
        }
    }
    return true;
}

}  // namespace twinray::math
