// What the mesh families of `twinray generate` share: a sine and cosine that are the same bits on every
// machine, the triangles of a grid of quads (a sphere's bands, a torus, a height field, a prism's sides) and
// the square grid of a height field.
#pragma once

#include "cli/generate/scene_text_writer.h"

#include <functional>

namespace twinray::cli::generate {

struct SineCosine {
    double sine, cosine;
};

// sin and cos of `angle` (radians, |angle| < 10^6) from + − × ÷ alone, so with -ffp-contract=off the
// same bits everywhere: the maths library's last bit differs between libraries, and the decimal grid
// would round such a difference to another digit whenever a value lies near a grid step's midpoint.
// Within a few units in the last place of the library's.
SineCosine sine_cosine(double angle);

// The triangles of a grid of quads between vertex rows 0..rows and columns 0..columns, `vertex(row,
// column)` giving each corner's index: a wrapped grid gives column `columns` the index of column 0, a pole
// gives a whole row one index. Each quad is cut along the diagonal from (row, column + 1) to (row + 1,
// column), both triangles counter-clockwise seen from the side the column direction × the row direction
// points to; a triangle with two corners on one vertex (beside a pole) is left out.
void grid_triangles(int rows, int columns, const std::function<int(int, int)>& vertex, const TriangleEmitter& emit);

// A height field's grid over the square |x|, |z| <= half_width: (n + 1)² vertices, row by row, rows along x and
// columns along z, which makes grid_triangles' front the top.
struct SquareGrid {
    int quads_per_side;
    double half_width;

    int vertex(int row, int column) const { return row * (quads_per_side + 1) + column; }
    double coordinate(int index) const { return -half_width + 2 * half_width * index / quads_per_side; }
    // The 2n² triangles, each quad cut along the same diagonal, fronts up.
    void triangles(const TriangleEmitter& emit) const;
};

}  // namespace twinray::cli::generate
