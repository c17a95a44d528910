// gears: Eric Haines's SPD "gears", whose point is concave polygons: a g × g grid of meshing spur gears, each
// a prism whose top and bottom are one concave polygon, the toothed outline, and whose sides are quads. The
// mesh holds triangles only, so the outline is cut into them by the loader's own ear clipper (the one that
// triangulates OBJ and PLY polygons), once, in a gear's own frame: every gear is that polygon moved. Each gear
// is its own closed shell, counter-clockwise seen from outside; flat.
#include "cli/generate/families.h"
#include "cli/generate/mesh_parts.h"
#include "cli/generate/scene_parts.h"
#include "scene/meshio/polygon.h"

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace twinray::cli::generate {
namespace {

// A multiple of 4, so that a gear has a tooth, or a gap, facing each of its four neighbours.
constexpr int teeth = 24;
constexpr int outline_corners = 4 * teeth;
// Each face the outline's corners − 2 triangles, each side quad two.
constexpr int triangles_per_gear = 2 * (outline_corners - 2) + 2 * outline_corners;

// The grid fills the square |x|, |z| <= half_width; neighbours' pitch circles touch.
constexpr double half_width = 3;
constexpr double thickness_per_pitch_radius = 0.4;
// The bottoms float this far above the floor: a face in the floor's own plane would leave each tracer to
// choose between two coincident surfaces.
constexpr double floor_clearance = 0.05;

// A tooth, in pitch radii and teeth: the usual addendum of one module (2/teeth) and dedendum of 1.25, its
// flanks straight from 0.3 of the tooth pitch either side of its centre at the root to 0.15 at the tip, which
// leaves a neighbour's tooth room in the gap at every radius.
constexpr double tip_radius = 1 + 2.0 / teeth;
constexpr double root_radius = 1 - 1.25 * 2.0 / teeth;
constexpr double root_half_width = 0.3;
constexpr double tip_half_width = 0.15;

std::int64_t gears_triangles(int gears_per_side) {
    return triangles_per_gear * std::int64_t{gears_per_side} * gears_per_side;
}

// The outline's corner `index`: its distance from the gear's centre in pitch radii and its angle in teeth,
// counter-clockwise seen from above; each tooth's root, tip, tip, root, then the gap's straight bottom.
struct OutlineCorner {
    double radius, angle;
};

OutlineCorner outline_corner(int index) {
    constexpr std::array<OutlineCorner, 4> tooth = {{{root_radius, -root_half_width},
                                                     {tip_radius, -tip_half_width},
                                                     {tip_radius, tip_half_width},
                                                     {root_radius, root_half_width}}};
    const OutlineCorner& corner = tooth[static_cast<std::size_t>(index % 4)];
    return {corner.radius, index / 4 + corner.angle};
}

// Angle θ counter-clockwise seen from above (+y) is the direction (cos θ, 0, −sin θ).
Vec3 outline_point(int index, double turned_by_teeth) {
    const OutlineCorner corner = outline_corner(index);
    const SineCosine direction = sine_cosine(2 * std::numbers::pi * (corner.angle + turned_by_teeth) / teeth);
    return {corner.radius * direction.cosine, 0, -corner.radius * direction.sine};
}

// The face's triangles as corners of the outline, counter-clockwise seen from above as the outline is.
std::vector<std::array<std::uint32_t, 3>> face_triangles() {
    std::vector<Vec3> outline;
    for (int i = 0; i < outline_corners; ++i) {
        outline.push_back(outline_point(i, 0));
    }
    scene::meshio::PolygonTriangulator triangulator;
    return triangulator.triangulate(outline);
}

// The shortest of the outline's edges, in pitch radii.
double shortest_outline_edge() {
    double shortest = tip_radius;
    for (int i = 0; i < outline_corners; ++i) {
        shortest = std::fmin(shortest, math::length(outline_point((i + 1) % outline_corners, 0) - outline_point(i, 0)));
    }
    return shortest;
}

struct GearGrid {
    int gears_per_side;
    double pitch_radius = half_width / gears_per_side;
    double top = floor_clearance + thickness_per_pitch_radius * pitch_radius;

    Vec3 center(int gear) const {
        const double spacing = 2 * pitch_radius;
        return {-half_width + spacing * (gear / gears_per_side + 0.5), 0,
                -half_width + spacing * (gear % gears_per_side + 0.5)};
    }
    // Half a tooth on every other gear, like a chessboard's colours: facing a neighbour's tooth is a gap.
    double turned_by_teeth(int gear) const { return (gear / gears_per_side + gear % gears_per_side) % 2 * 0.5; }

    // Each gear's bottom ring of outline corners, then its top ring.
    void each_vertex(const PointEmitter& emit) const {
        for (int gear = 0; gear < gears_per_side * gears_per_side; ++gear) {
            for (double y : {floor_clearance, top}) {
                for (int i = 0; i < outline_corners; ++i) {
                    const Vec3 point = pitch_radius * outline_point(i, turned_by_teeth(gear));
                    emit(center(gear) + Vec3{point.x, y, point.z});
                }
            }
        }
    }

    // Each gear's top, bottom and sides.
    void each_triangle(const std::vector<std::array<std::uint32_t, 3>>& face, const TriangleEmitter& emit) const {
        for (int gear = 0; gear < gears_per_side * gears_per_side; ++gear) {
            const int bottom = 2 * outline_corners * gear;
            const int top_ring = bottom + outline_corners;
            for (const auto& [a, b, c] : face) {
                emit(top_ring + static_cast<int>(a), top_ring + static_cast<int>(b), top_ring + static_cast<int>(c));
            }
            for (const auto& [a, b, c] : face) {
                emit(bottom + static_cast<int>(a), bottom + static_cast<int>(c), bottom + static_cast<int>(b));
            }
            // Rows from the bottom ring up and columns along the outline make grid_triangles' front the outside.
            grid_triangles(
                1, outline_corners,
                [&](int row, int column) { return bottom + row * outline_corners + column % outline_corners; }, emit);
        }
    }
};

}  // namespace

GeneratedScene write_gears(int size, std::uint64_t seed, const SceneSink& sink) {
    SplitMix64 random(seed);
    const GearGrid gears{nearest_parameter(1, size, gears_triangles)};
    const std::vector<std::array<std::uint32_t, 3>> face = face_triangles();
    scene::Scene header = framed_scene({0, gears.top / 2, 0}, half_width * std::sqrt(2.0) + 0.2, {0.35, 0.9, 0.6});
    const int material = add_material(header, "gears", metal(random_color(random), 0.3));
    SceneTextWriter out(sink, decimals_resolving(shortest_outline_edge() * gears.pitch_radius));
    out.begin(header);
    write_floor(out);
    out.mesh({[&](const PointEmitter& emit) { gears.each_vertex(emit); },
              [&](const TriangleEmitter& emit) { gears.each_triangle(face, emit); },
              {}},
             material);
    out.end();
    const std::string per_side = std::to_string(gears.gears_per_side);
    return {out.primitives(), out.triangles(),
            std::to_string(out.triangles()) + " triangles: " + per_side + " x " + per_side + " gears of " +
                std::to_string(teeth) + " teeth"};
}

}  // namespace twinray::cli::generate
