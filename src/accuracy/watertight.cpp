#include "accuracy/watertight.h"

#include "reference/tracer.h"
#include "scene/geometry.h"
#include "scene/portable_random.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace twinray::accuracy {
namespace {

using scene::Vec3;
using Triangle = std::array<std::uint32_t, 3>;

// Embree's verify places its sphere at (148376, 1234, −223423); its direction scaled to each distance.
Vec3 centre_at(double distance) {
    const Vec3 direction = math::normalize(Vec3{148376, 1234, -223423});
    return distance * direction;
}

Vec3 random_unit(SplitMix64& random) {
    for (;;) {
        Vec3 v{random.uniform(-1, 1), random.uniform(-1, 1), random.uniform(-1, 1)};
        double squared = math::dot(v, v);
        if (squared > 1e-4 && squared <= 1) {
            return v / std::sqrt(squared);
        }
    }
}

// Two unit vectors spanning the plane perpendicular to the unit n.
std::pair<Vec3, Vec3> plane_axes(const Vec3& n) {
    Vec3 helper = std::fabs(n.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    Vec3 u = math::normalize(math::cross(n, helper));
    return {u, math::cross(n, u)};
}

// The mesh as a scene of its own: one mesh, its degenerate triangles listed, a camera at `eye`.
scene::Scene mesh_scene(std::vector<Vec3> vertices, std::vector<Triangle> triangles, const Vec3& eye) {
    auto data = std::make_shared<scene::MeshData>();
    data->vertices = std::move(vertices);
    data->triangles = std::move(triangles);
    data->degenerate = scene::degenerate_triangles(*data);
    scene::Scene scene;
    scene.camera.eye = eye;
    scene.camera.look_at = eye + Vec3{0, 0, -1};
    scene.meshes.push_back({std::move(data), 0, 0, std::nullopt});
    scene.leaf_paths.push_back("objects[0]");
    scene.leaf_materials.push_back(0);
    return scene;
}

// Each undirected edge of the mesh once, as its two vertices.
std::vector<std::pair<std::uint32_t, std::uint32_t>> edges_of(const std::vector<Triangle>& triangles) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> seen;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const Triangle& t : triangles) {
        for (int i = 0; i < 3; ++i) {
            std::uint32_t a = std::min(t[i], t[(i + 1) % 3]), b = std::max(t[i], t[(i + 1) % 3]);
            if (seen[{a, b}]++ == 0) {
                edges.push_back({a, b});
            }
        }
    }
    return edges;
}

// Where a probe aims: a vertex, a point on an edge (its midpoint or a random one) or inside a face, picked
// in turn so that each kind gets a third of the probes (faces a sixth, shared with random edge points).
Vec3 aim_point(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles,
               const std::vector<std::uint32_t>& aim_vertices,
               const std::vector<std::pair<std::uint32_t, std::uint32_t>>& aim_edges, int index, SplitMix64& random) {
    auto pick = [&](std::size_t count) { return static_cast<std::size_t>(random.next() % count); };
    switch (index % 6) {
        case 0:
        case 1: return vertices[aim_vertices[pick(aim_vertices.size())]];
        case 2:
        case 3: {
            auto [a, b] = aim_edges[pick(aim_edges.size())];
            return 0.5 * (vertices[a] + vertices[b]);
        }
        case 4: {
            auto [a, b] = aim_edges[pick(aim_edges.size())];
            return vertices[a] + random.uniform(0, 1) * (vertices[b] - vertices[a]);
        }
        default: {
            const Triangle& t = triangles[pick(triangles.size())];
            double s = random.uniform(0, 1), r = random.uniform(0, 1);
            if (s + r > 1) {
                s = 1 - s;
                r = 1 - r;
            }
            return vertices[t[0]] + s * (vertices[t[1]] - vertices[t[0]]) + r * (vertices[t[2]] - vertices[t[0]]);
        }
    }
}

WatertightProbe probe_towards(const Vec3& origin, const Vec3& target, double length) {
    return {origin, math::normalize(target - origin), length};
}

// A UV sphere: rings of `segments` vertices between two poles, fans at the poles, counter-clockwise outside.
WatertightCase sphere_case(double distance, double size, int probes, SplitMix64& random) {
    const Vec3 centre = centre_at(distance);
    constexpr int rings = 24, segments = 48;
    std::vector<Vec3> vertices{centre + size * Vec3{0, 1, 0}};
    for (int ring = 1; ring < rings; ++ring) {
        double polar = std::numbers::pi * ring / rings;
        for (int s = 0; s < segments; ++s) {
            double azimuth = 2 * std::numbers::pi * s / segments;
            vertices.push_back(centre + size * Vec3{std::sin(polar) * std::cos(azimuth), std::cos(polar),
                                                    std::sin(polar) * std::sin(azimuth)});
        }
    }
    vertices.push_back(centre + size * Vec3{0, -1, 0});
    const auto south = static_cast<std::uint32_t>(vertices.size() - 1);
    auto at = [](int ring, int s) { return static_cast<std::uint32_t>(1 + (ring - 1) * segments + s % segments); };
    std::vector<Triangle> triangles;
    for (int s = 0; s < segments; ++s) {
        triangles.push_back({0, at(1, s + 1), at(1, s)});
        for (int ring = 1; ring + 1 < rings; ++ring) {
            triangles.push_back({at(ring, s), at(ring, s + 1), at(ring + 1, s + 1)});
            triangles.push_back({at(ring, s), at(ring + 1, s + 1), at(ring + 1, s)});
        }
        triangles.push_back({at(rings - 1, s), at(rings - 1, s + 1), south});
    }
    std::vector<std::uint32_t> aim_vertices(vertices.size());
    for (std::uint32_t i = 0; i < aim_vertices.size(); ++i) {
        aim_vertices[i] = i;
    }
    auto edges = edges_of(triangles);
    WatertightCase out{"sphere", distance, size, {}, {}};
    for (int i = 0; i < probes; ++i) {
        Vec3 target = aim_point(vertices, triangles, aim_vertices, edges, i, random);
        out.probes.push_back(probe_towards(centre, target, 2 * size));
    }
    out.scene = mesh_scene(std::move(vertices), std::move(triangles), centre);
    return out;
}

// 5 to 12 triangles around the centre, their spokes at jittered angles, in a random plane.
WatertightCase fan_case(double distance, double size, int probes, SplitMix64& random) {
    const Vec3 centre = centre_at(distance);
    const Vec3 normal = random_unit(random);
    auto [u, w] = plane_axes(normal);
    const int count = 5 + static_cast<int>(random.next() % 8);
    std::vector<Vec3> vertices{centre};
    for (int i = 0; i < count; ++i) {
        double angle = 2 * std::numbers::pi * (i + random.uniform(-0.3, 0.3)) / count;
        double radius = size * random.uniform(0.5, 1);
        vertices.push_back(centre + radius * (std::cos(angle) * u + std::sin(angle) * w));
    }
    std::vector<Triangle> triangles;
    for (int i = 0; i < count; ++i) {
        triangles.push_back({0, static_cast<std::uint32_t>(1 + i), static_cast<std::uint32_t>(1 + (i + 1) % count)});
    }
    std::vector<std::uint32_t> aim_vertices{0};
    std::vector<std::pair<std::uint32_t, std::uint32_t>> spokes;
    for (int i = 0; i < count; ++i) {
        spokes.push_back({0, static_cast<std::uint32_t>(1 + i)});
    }
    WatertightCase out{"fan", distance, size, {}, {}};
    for (int i = 0; i < probes; ++i) {
        // Faces are aimed at in the inner half, where the fan surely covers the plane around the target, and
        // points of spokes short of the rim, whose outer end is the fan's border.
        Vec3 target = aim_point(vertices, triangles, aim_vertices, spokes, i, random);
        if (i % 6 == 4 || i % 6 == 5) {
            target = centre + (i % 6 == 4 ? 0.99 : 0.5) * (target - centre);
        }
        Vec3 above = target + size * (normal + random.uniform(-0.5, 0.5) * u + random.uniform(-0.5, 0.5) * w);
        out.probes.push_back(probe_towards(above, target, 3 * size));
    }
    out.scene = mesh_scene(std::move(vertices), std::move(triangles), centre);
    return out;
}

// 64 splits of a square, each at a random point strictly inside a random triangle; inner edges and vertices
// are those not on the square's border.
WatertightCase split_square_case(double distance, double size, int probes, SplitMix64& random) {
    const Vec3 centre = centre_at(distance);
    const Vec3 normal = random_unit(random);
    auto [u, w] = plane_axes(normal);
    std::vector<Vec3> vertices{centre - size * u - size * w, centre + size * u - size * w, centre + size * u + size * w,
                               centre - size * u + size * w};
    std::vector<Triangle> triangles{{0, 1, 2}, {0, 2, 3}};
    for (int split = 0; split < 64; ++split) {
        std::size_t pick = static_cast<std::size_t>(random.next() % triangles.size());
        Triangle t = triangles[pick];
        double a = random.uniform(0.1, 1), b = random.uniform(0.1, 1), c = random.uniform(0.1, 1);
        double sum = a + b + c;
        Vec3 inside = (a / sum) * vertices[t[0]] + (b / sum) * vertices[t[1]] + (c / sum) * vertices[t[2]];
        auto v = static_cast<std::uint32_t>(vertices.size());
        vertices.push_back(inside);
        triangles[pick] = {t[0], t[1], v};
        triangles.push_back({t[1], t[2], v});
        triangles.push_back({t[2], t[0], v});
    }
    std::vector<std::uint32_t> inner_vertices;
    for (std::uint32_t i = 4; i < vertices.size(); ++i) {
        inner_vertices.push_back(i);
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> inner_edges;
    for (auto edge : edges_of(triangles)) {
        bool border = edge.first < 4 && edge.second < 4 && (edge.second - edge.first) % 2 == 1;
        if (!border) {
            inner_edges.push_back(edge);
        }
    }
    WatertightCase out{"split square", distance, size, {}, {}};
    for (int i = 0; i < probes; ++i) {
        // Nested splits put inner points arbitrarily near the border, where a ray within an ulp of one may
        // rightly pass outside the square (at 1e7 an ulp is 2e-9, a border point 5e-10 in): such a target
        // is drawn again, so every probe must cross.
        Vec3 target;
        do {
            target = aim_point(vertices, triangles, inner_vertices, inner_edges, i, random);
        } while (std::max(std::fabs(math::dot(target - centre, u)), std::fabs(math::dot(target - centre, w))) >
                 0.999 * size);
        out.probes.push_back({target + size * normal, -1.0 * normal, 2 * size});
    }
    out.scene = mesh_scene(std::move(vertices), std::move(triangles), centre);
    return out;
}

// An axis-aligned grid of 8 × 8 squares, each split along a diagonal (alternating), on a binary grid around
// the centre: spacing h a power of two and every coordinate a multiple of h, so that vertices, rays straight
// down and their differences are exact in double and, re-based on the centre, in float. Rays land exactly on
// edges and vertices: the edge functions are exactly 0 there, in every tracer, and only the tie rule decides.
WatertightCase grid_case(double distance, double size, int probes, SplitMix64& random) {
    const double h = std::exp2(std::floor(std::log2(size / 4)));
    const Vec3 rough = centre_at(distance);
    const Vec3 centre{h * std::round(rough.x / h), h * std::round(rough.y / h), h * std::round(rough.z / h)};
    constexpr int cells = 8;
    std::vector<Vec3> vertices;
    for (int j = 0; j <= cells; ++j) {
        for (int i = 0; i <= cells; ++i) {
            vertices.push_back(centre + Vec3{h * (i - cells / 2), h * (j - cells / 2), 0});
        }
    }
    auto at = [](int i, int j) { return static_cast<std::uint32_t>(j * (cells + 1) + i); };
    std::vector<Triangle> triangles;
    for (int j = 0; j < cells; ++j) {
        for (int i = 0; i < cells; ++i) {
            if ((i + j) % 2 == 0) {
                triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            } else {
                triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
                triangles.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
            }
        }
    }
    WatertightCase out{"grid", distance, size, {}, {}};
    const double above = 4 * h;
    for (int k = 0; k < probes; ++k) {
        // Inner points on the grid of half cells: vertices, edge midpoints, the cells' centres (on a diagonal).
        int i = 1 + static_cast<int>(random.next() % (2 * cells - 1));
        int j = 1 + static_cast<int>(random.next() % (2 * cells - 1));
        Vec3 target = centre + Vec3{0.5 * h * (i - cells), 0.5 * h * (j - cells), 0};
        out.probes.push_back({target + Vec3{0, 0, above}, Vec3{0, 0, -1}, 2 * above});
    }
    out.scene = mesh_scene(std::move(vertices), std::move(triangles), centre);
    return out;
}

}  // namespace

std::vector<double> watertight_distances() {
    return {1, 1e3, 1e5, 1e7};
}

std::vector<double> watertight_sizes() {
    return {1e-4, 1e-2, 1, 1e2, 1e4};
}

std::vector<std::string> watertight_families() {
    return {"sphere", "fan", "split square", "grid"};
}

WatertightCase make_watertight_case(const std::string& family, double distance, double size, int probes) {
    // FNV-1a of the family and the two decades: the same seed on every machine (std::hash is not portable).
    std::uint64_t seed = 0xcbf29ce484222325ULL;
    for (char c : family + "/" + std::to_string(std::lround(std::log10(distance))) + "/" +
                      std::to_string(std::lround(std::log10(size)))) {
        seed = (seed ^ static_cast<unsigned char>(c)) * 0x100000001b3ULL;
    }
    SplitMix64 random(seed);
    if (family == "sphere") {
        return sphere_case(distance, size, probes, random);
    }
    if (family == "fan") {
        return fan_case(distance, size, probes, random);
    }
    if (family == "split square") {
        return split_square_case(distance, size, probes, random);
    }
    if (family == "grid") {
        return grid_case(distance, size, probes, random);
    }
    throw std::invalid_argument("unknown watertightness family \"" + family + "\"");
}

CrossingCounter oracle_crossings(const scene::Scene& scene) {
    auto tracer = std::make_shared<reference::Tracer<double>>(scene);
    return [tracer](const WatertightProbe& probe) {
        return tracer->mesh_crossings({probe.origin, probe.direction}, probe.length);
    };
}

CrossingCounter sse_crossings(const scene::Scene& scene, const sse::Precision& precision) {
    auto tracer = std::make_shared<sse::Tracer>(scene, precision);
    return [tracer](const WatertightProbe& probe) {
        return tracer->mesh_crossings({probe.origin, sse::Vec3(probe.direction)}, static_cast<float>(probe.length));
    };
}

WatertightTally count_watertightness(const WatertightCase& watertight, const CrossingCounter& crossings) {
    WatertightTally tally;
    for (const WatertightProbe& probe : watertight.probes) {
        int count = crossings(probe);
        ++tally.rays;
        tally.misses += count == 0 ? 1 : 0;
        tally.double_hits += count >= 2 ? 1 : 0;
    }
    return tally;
}

}  // namespace twinray::accuracy
