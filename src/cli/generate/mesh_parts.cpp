#include "cli/generate/mesh_parts.h"

#include <cmath>

namespace twinray::cli::generate {

SineCosine sine_cosine(double angle) {
    // angle = quadrant·π/2 + reduced with |reduced| <= π/4: π/2 in two parts (Cody and Waite, as fdlibm's
    // pio2_1 and pio2_1t), the first of 33 bits so that quadrant × it is exact.
    constexpr double half_pi_high = 0x1.921fb544p+0;
    constexpr double half_pi_low = 0x1.0b4611a626331p-34;
    const double quadrant = std::round(angle / (half_pi_high + half_pi_low));
    const double reduced = (angle - quadrant * half_pi_high) - quadrant * half_pi_low;
    // Taylor series: the first term left out is below 2^-60 at |reduced| = π/4.
    const double square = reduced * reduced;
    double sine = reduced, cosine = 1;
    double sine_term = reduced, cosine_term = 1;
    for (int k = 1; k <= 9; ++k) {
        sine_term *= -square / ((2 * k) * (2 * k + 1));
        cosine_term *= -square / ((2 * k - 1) * (2 * k));
        sine += sine_term;
        cosine += cosine_term;
    }
    switch (static_cast<long long>(quadrant) & 3) {
        case 0: return {sine, cosine};
        case 1: return {cosine, -sine};
        case 2: return {-sine, -cosine};
        default: return {-cosine, sine};
    }
}

void grid_triangles(int rows, int columns, const std::function<int(int, int)>& vertex, const TriangleEmitter& emit) {
    for (int row = 0; row < rows; ++row) {
        for (int column = 0; column < columns; ++column) {
            const int here = vertex(row, column);
            const int along = vertex(row, column + 1);
            const int below = vertex(row + 1, column);
            const int across = vertex(row + 1, column + 1);
            if (here != along) {
                emit(here, along, below);
            }
            if (below != across) {
                emit(along, across, below);
            }
        }
    }
}

void SquareGrid::triangles(const TriangleEmitter& emit) const {
    grid_triangles(
        quads_per_side, quads_per_side, [&](int row, int column) { return vertex(row, column); }, emit);
}

}  // namespace twinray::cli::generate
