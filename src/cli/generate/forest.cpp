// forest: one tree declared once as a mesh shape (a trunk and three cones of foliage, 1 008 triangles) and `size`
// instances of it on a jittered square grid, each turned about the vertical, scaled and coloured at random: the
// scene of issue 25's instancing target, a million placements of a thousand-triangle model. Each part of the tree
// is a closed solid of revolution, counter-clockwise seen from outside.
#include "cli/generate/families.h"
#include "cli/generate/mesh_parts.h"
#include "cli/generate/scene_parts.h"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace twinray::cli::generate {
namespace {

// Around the axis: 12 for the trunk, 40 for each cone.
constexpr int trunk_segments = 12;
constexpr int cone_segments = 40;
constexpr double trunk_radius = 0.12;
constexpr double trunk_height = 0.6;
// The cones' bases (radius, height) and apexes, bottom to top, each overlapping the one below.
struct Cone {
    double base_radius, base_height, apex_height;
};
constexpr Cone cones[] = {{0.9, 0.45, 1.7}, {0.7, 1.1, 2.3}, {0.5, 1.7, 2.8}};
// Rings between a cone's apex and its base, so that its slope is a grid of quads (the tree's triangle count).
constexpr int cone_rings = 3;
// Trees stand this far apart on the grid, each moved by up to `jitter` along both axes.
constexpr double spacing = 2.2;
constexpr double jitter = 0.4;
constexpr int palette_size = 6;

// A solid of revolution: its profile from the top of the axis to its bottom, (radius, height), the first and last
// on the axis (radius 0, a pole: one vertex); `segments` around.
struct Revolution {
    std::vector<std::array<double, 2>> profile;
    int segments;

    int vertex_count() const { return 2 + static_cast<int>(profile.size() - 2) * segments; }
    // Rows down the profile and columns around (x = r·cos θ, z = r·sin θ) make grid_triangles' front the outside.
    int vertex(int row, int column) const {
        const int rows = static_cast<int>(profile.size()) - 1;
        if (row == 0) {
            return 0;
        }
        if (row == rows) {
            return vertex_count() - 1;
        }
        return 1 + (row - 1) * segments + column % segments;
    }
    void each_vertex(const PointEmitter& emit) const {
        for (std::size_t row = 0; row < profile.size(); ++row) {
            const bool pole = row == 0 || row + 1 == profile.size();
            for (int column = 0; column < (pole ? 1 : segments); ++column) {
                const SineCosine around = sine_cosine(2 * std::numbers::pi * column / segments);
                const auto [radius, height] = profile[row];
                emit({radius * around.cosine, height, radius * around.sine});
            }
        }
    }
    void each_triangle(int first_vertex, const TriangleEmitter& emit) const {
        grid_triangles(
            static_cast<int>(profile.size()) - 1, segments,
            [&](int row, int column) { return first_vertex + vertex(row, column); }, emit);
    }
};

std::vector<Revolution> tree_parts() {
    std::vector<Revolution> parts;
    parts.push_back({{{0, trunk_height}, {trunk_radius, trunk_height}, {trunk_radius, 0}, {0, 0}}, trunk_segments});
    for (const Cone& cone : cones) {
        Revolution part{{{0, cone.apex_height}}, cone_segments};
        for (int ring = 1; ring <= cone_rings + 1; ++ring) {
            const double share = static_cast<double>(ring) / (cone_rings + 1);
            part.profile.push_back(
                {share * cone.base_radius, cone.apex_height + share * (cone.base_height - cone.apex_height)});
        }
        part.profile.push_back({0, cone.base_height});
        parts.push_back(part);
    }
    return parts;
}

MeshLists tree_mesh(const std::vector<Revolution>& parts) {
    return {[&parts](const PointEmitter& emit) {
                for (const Revolution& part : parts) {
                    part.each_vertex(emit);
                }
            },
            [&parts](const TriangleEmitter& emit) {
                int first = 0;
                for (const Revolution& part : parts) {
                    part.each_triangle(first, emit);
                    first += part.vertex_count();
                }
            },
            nullptr};
}

}  // namespace

GeneratedScene write_forest(int size, std::uint64_t seed, const SceneSink& sink) {
    SplitMix64 random(seed);
    const int side = square_side(size);
    const double half_extent = 0.5 * spacing * side;
    scene::Scene header = framed_scene({0, 1.4, 0}, std::max(half_extent, 2.0), {0.55, 0.45, 0.8});
    add_palette(header, palette_size, random);
    // The smallest feature is the trunk's side between two segments, 2·r·sin(π/12) ≈ 0.062.
    SceneTextWriter out(sink, decimals_resolving(0.06));
    out.begin(header);
    const std::vector<Revolution> parts = tree_parts();
    out.shape_mesh("tree", tree_mesh(parts), 0);
    write_floor(out);
    for (int i = 0; i < size; ++i) {
        const int row = i / side, column = i % side;
        const double x = -half_extent + spacing * (column + 0.5) + random.uniform(-jitter, jitter);
        const double z = -half_extent + spacing * (row + 0.5) + random.uniform(-jitter, jitter);
        const double turn = random.uniform(0, 360);
        const double scale = random.uniform(0.7, 1.2);
        out.instance("tree", {turn, scale, {x, 0, z}}, palette_material(random, palette_size));
    }
    out.end();
    return {out.primitives(), out.triangles(),
            std::to_string(size) + " instances of a tree of " + std::to_string(out.triangles()) + " triangles, " +
                std::to_string(side) + " x " + std::to_string(side) + " grid"};
}

}  // namespace twinray::cli::generate
