// Exact signs for the reference tracer's watertight ray–triangle test: which side of a triangle's edge a
// ray's line passes, decided exactly from the double inputs, so that two triangles sharing an edge or a
// vertex never both claim, or both miss, a ray through it. A floating-point filter answers almost every
// call; a value within the filter's rounding bound of zero is recomputed in exact expansion arithmetic
// (Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997).
//
// Exact for every finite input, round-to-nearest (the default) assumed: the exact arithmetic runs in double where its
// products stay on the double grid and below overflow (inputs below 2^339 whose non-zero magnitudes span at most
// 2^600, scaled up first: exact_predicates.cpp), and in long double, whose exponent holds any product of three
// differences of doubles, elsewhere.
#pragma once

#include <array>
#include <cmath>

namespace twinray::math {

using Coordinates = std::array<double, 3>;

// The sign (+1, −1 or 0) of E = direction · ((a − origin) × (b − origin)): the side of the edge a→b the
// ray's line passes, seen along the direction (t ≥ 0 is not asked). For a triangle's three edges taken in
// order the signs agree exactly when the line crosses the triangle, and their sum is direction · n, n the
// triangle's counter-clockwise normal. The direction need not be of unit length: only E's sign is used,
// and a positive factor does not change it.
int sign_of_ray_edge(const Coordinates& origin, const Coordinates& direction, const Coordinates& a,
                     const Coordinates& b);

// sign_of_ray_edge with exact zeros broken by Simulation of Simplicity (Edelsbrunner & Mücke, 1990). The
// origin is moved to origin + ε·e_kx + ε²·e_ky for an infinitely small ε > 0, kz the axis of the direction's
// largest |component| (ties to the lower axis), kx = (kz + 1) % 3, ky = (kz + 2) % 3. E is then
// E + ε·c[kx] + ε²·c[ky] with c = (a − b) × direction (moving the origin by δ adds δ · ((a − b) × direction)),
// so an exact zero takes the sign of c[kx], or else of c[ky]. Every edge is judged against the same moved
// ray, a real one: a ray through a vertex or an edge of a closed fan meets exactly one of its triangles, and
// swapping a and b still negates the result. 0 only when c = 0: the edge is parallel to the direction (or
// a = b, or the direction is zero).
int sign_of_ray_edge_perturbed(const Coordinates& origin, const Coordinates& direction, const Coordinates& a,
                               const Coordinates& b);

// True iff (b − a) × (c − a) is exactly the zero vector: the triangle abc has no area.
bool exactly_collinear(const Coordinates& a, const Coordinates& b, const Coordinates& c);

}  // namespace twinray::math
