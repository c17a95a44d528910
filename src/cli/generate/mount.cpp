// mount: Eric Haines's SPD "mount", a fractal mountain and a pyramid of four glass spheres over its front. The
// mountain is a square of two triangles subdivided `depth` times by midpoint displacement into 2·4^depth, an
// open surface, its front facing up; flat. Subdividing the square's two triangles at their midpoints gives
// the triangles of the n × n grid of quads (n = 2^depth) each cut along the same diagonal, every midpoint a
// grid point: so each is computed once, from its edge's two ends, and the triangles on both sides of the
// edge share it, with no cracks between them.
#include "cli/generate/families.h"
#include "cli/generate/mesh_parts.h"
#include "cli/generate/scene_parts.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace twinray::cli::generate {
namespace {

constexpr double half_width = 3;
// The outline, never displaced, stays this far above the floor, and no midpoint goes below it: a face in the
// floor's own plane would leave each tracer to choose between two coincident surfaces.
constexpr double foot_height = 0.05;
// The first midpoint, the square's centre, rises to the summit; the next level's are displaced by up to
// first_displacement either way, and each level after by half the one before, as its edges are half as long:
// the slopes are as steep at every scale.
constexpr double summit_height = 2;
constexpr double first_displacement = 0.6;

constexpr double sphere_radius = 0.4;
// The spheres' axis, on the slope in front of the summit as the camera sees it.
constexpr double spheres_x = -0.6;
constexpr double spheres_z = 2;
constexpr double sphere_clearance = 0.05;

std::int64_t mount_triangles(int depth) {
    return 2 * (std::int64_t{1} << (2 * depth));
}

class FractalMountain {
public:
    // Draws one random number per midpoint off the outline, level by level, row by row.
    FractalMountain(int depth, SplitMix64& random) : grid_{1 << depth, half_width} {
        const int n = grid_.quads_per_side;
        heights_.assign(static_cast<std::size_t>(n + 1) * (n + 1), foot_height);
        if (depth == 0) {
            return;
        }
        at(n / 2, n / 2) = summit_height;
        double displacement = first_displacement;
        // `step` is the new level's spacing: the points already there are the multiples of 2·step.
        for (int step = n / 4; step >= 1; step /= 2, displacement /= 2) {
            for (int row = step; row < n; row += step) {
                for (int column = step; column < n; column += step) {
                    const bool row_old = row % (2 * step) == 0, column_old = column % (2 * step) == 0;
                    if (row_old && column_old) {
                        continue;
                    }
                    // The edge this point halves: along a row, along a column, or the quads' diagonal.
                    const double ends = row_old      ? at(row, column - step) + at(row, column + step)
                                        : column_old ? at(row - step, column) + at(row + step, column)
                                                     : at(row - step, column + step) + at(row + step, column - step);
                    at(row, column) = std::fmax(foot_height, ends / 2 + displacement * random.uniform(-1, 1));
                }
            }
        }
    }

    const SquareGrid& grid() const { return grid_; }

    void each_vertex(const PointEmitter& emit) const {
        for (int row = 0; row <= grid_.quads_per_side; ++row) {
            for (int column = 0; column <= grid_.quads_per_side; ++column) {
                emit({grid_.coordinate(row), height(row, column), grid_.coordinate(column)});
            }
        }
    }

    // The highest vertex within `reach` of (x, z) along both axes, and the mountain's surface above that
    // square too (each triangle is no higher than its corners) when reach has a grid step to spare.
    double highest_near(double x, double z, double reach) const {
        double highest = foot_height;
        for (int row = 0; row <= grid_.quads_per_side; ++row) {
            for (int column = 0; column <= grid_.quads_per_side; ++column) {
                if (std::fabs(grid_.coordinate(row) - x) <= reach && std::fabs(grid_.coordinate(column) - z) <= reach) {
                    highest = std::max(highest, height(row, column));
                }
            }
        }
        return highest;
    }

private:
    double height(int row, int column) const { return heights_[static_cast<std::size_t>(grid_.vertex(row, column))]; }
    double& at(int row, int column) { return heights_[static_cast<std::size_t>(grid_.vertex(row, column))]; }

    SquareGrid grid_;
    std::vector<double> heights_;
};

// SPD's pyramid: three touching spheres in a triangle around the axis and one resting on them, the three
// clear of the highest point of the mountain beneath.
void write_glass_pyramid(SceneTextWriter& out, const FractalMountain& mountain, int material) {
    const double axis_distance = 2 * sphere_radius / std::sqrt(3.0);  // the base's centres from the axis
    const double cell = 2 * half_width / mountain.grid().quads_per_side;
    const double base_y = mountain.highest_near(spheres_x, spheres_z, axis_distance + sphere_radius + cell) +
                          sphere_clearance + sphere_radius;
    // The base's centres at 90°, 210° and 330° around the axis: cos 30° = √3/2, sin 30° = 1/2.
    const double half_root3 = std::sqrt(3.0) / 2;
    const double offsets[3][2] = {{0, -1}, {-half_root3, 0.5}, {half_root3, 0.5}};
    for (const auto& [dx, dz] : offsets) {
        out.sphere({spheres_x + axis_distance * dx, base_y, spheres_z + axis_distance * dz}, sphere_radius, material);
    }
    // The top sphere's centre and the base's make a regular tetrahedron of edge 2r, of height 2r·√(2/3).
    out.sphere({spheres_x, base_y + 2 * sphere_radius * std::sqrt(2.0 / 3), spheres_z}, sphere_radius, material);
}

}  // namespace

GeneratedScene write_mount(int size, std::uint64_t seed, const SceneSink& sink) {
    SplitMix64 random(seed);
    const int depth = nearest_parameter(0, size, mount_triangles);
    scene::Scene header = framed_scene({0, 1, 0}, 3.8, {0.3, 0.45, 1});
    const int mountain_material = add_material(header, "mountain", plastic(random_color(random)));
    const int glass_material = add_material(header, "glass", glass());
    const FractalMountain mountain(depth, random);
    const int quads_per_side = mountain.grid().quads_per_side;
    SceneTextWriter out(sink, decimals_resolving(2 * half_width / quads_per_side));
    out.begin(header);
    write_floor(out);
    out.mesh({[&](const PointEmitter& emit) { mountain.each_vertex(emit); },
              [&](const TriangleEmitter& emit) { mountain.grid().triangles(emit); },
              {}},
             mountain_material);
    write_glass_pyramid(out, mountain, glass_material);
    out.end();
    return {out.primitives(), out.triangles(),
            std::to_string(out.triangles()) + " triangles: depth " + std::to_string(depth) + ", " +
                std::to_string(quads_per_side) + " x " + std::to_string(quads_per_side) + " quads, 4 glass spheres"};
}

}  // namespace twinray::cli::generate
