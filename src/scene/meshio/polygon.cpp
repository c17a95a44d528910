#include "scene/meshio/polygon.h"

#include <cmath>
#include <cstddef>

namespace twinray::scene::meshio {
namespace {

using Point = std::array<double, 2>;

// Twice the signed area of the triangle a, b, c: positive when it turns counter-clockwise.
double turn(const Point& a, const Point& b, const Point& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// Inside or on the edge of the counter-clockwise triangle a, b, c.
bool in_triangle(const Point& p, const Point& a, const Point& b, const Point& c) {
    return turn(a, b, p) >= 0 && turn(b, c, p) >= 0 && turn(c, a, p) >= 0;
}

}  // namespace

const std::vector<std::array<std::uint32_t, 3>>& PolygonTriangulator::triangulate(std::span<const Vec3> corners) {
    const auto count = static_cast<std::uint32_t>(corners.size());
    triangles_.clear();
    if (count == 3) {
        triangles_.push_back({0, 1, 2});
        return triangles_;
    }
    // Newell's normal: its largest component names the axis to drop, its sign whether the projection turns
    // counter-clockwise.
    Vec3 normal{};
    for (std::uint32_t i = 0; i < count; ++i) {
        const Vec3& a = corners[i];
        const Vec3& b = corners[(i + 1) % count];
        normal += Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
    }
    const Vec3 size{std::fabs(normal.x), std::fabs(normal.y), std::fabs(normal.z)};
    const int dropped = size.x >= size.y && size.x >= size.z ? 0 : size.y >= size.z ? 1 : 2;
    const int u = (dropped + 1) % 3;
    const int v = (dropped + 2) % 3;
    const bool mirrored = normal[dropped] < 0;
    projected_.clear();
    for (const Vec3& corner : corners) {
        projected_.push_back({corner[u], mirrored ? -corner[v] : corner[v]});
    }

    remaining_.resize(count);
    for (std::uint32_t i = 0; i < count; ++i) {
        remaining_[i] = i;
    }
    // Candidates are tried from the second corner on, so that a convex polygon gives the fan from the first.
    std::size_t candidate = 1;
    while (remaining_.size() > 3) {
        const std::size_t n = remaining_.size();
        std::size_t ear = n;  // none yet
        for (std::size_t tried = 0; tried < n && ear == n; ++tried) {
            const std::size_t at = (candidate + tried) % n;
            const Point& previous = projected_[remaining_[(at + n - 1) % n]];
            const Point& corner = projected_[remaining_[at]];
            const Point& next = projected_[remaining_[(at + 1) % n]];
            if (turn(previous, corner, next) <= 0) {
                continue;  // reflex or flat: cutting here would leave the polygon
            }
            bool empty = true;
            for (std::size_t other = 0; other < n && empty; ++other) {
                const Point& p = projected_[remaining_[other]];
                const bool is_corner = p == previous || p == corner || p == next;
                empty = is_corner || !in_triangle(p, previous, corner, next);
            }
            if (empty) {
                ear = at;
            }
        }
        // No ear: the polygon is flat, twisted or self-intersecting, and any cut is as good; the candidate
        // keeps the result deterministic.
        if (ear == n) {
            ear = candidate % n;
        }
        triangles_.push_back({remaining_[(ear + n - 1) % n], remaining_[ear], remaining_[(ear + 1) % n]});
        remaining_.erase(remaining_.begin() + static_cast<std::ptrdiff_t>(ear));
        candidate = ear % remaining_.size();
    }
    triangles_.push_back({remaining_[0], remaining_[1], remaining_[2]});
    return triangles_;
}

}  // namespace twinray::scene::meshio
