// Polygons of four and more corners as triangles, the same way for every format: ear clipping in the
// projection of the polygon on the coordinate plane its (Newell) normal is most nearly perpendicular to —
// convex and concave polygons alike, deterministic, in double.
#pragma once

#include "scene/scene.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace twinray::scene::meshio {

class PolygonTriangulator {
public:
    // Triangles covering the polygon with these corner positions (three or more, in order), each as three
    // positions in `corners`, wound as the polygon is. A convex polygon gives the fan from its first corner;
    // a concave one is cut only along diagonals inside it. Valid until the next call.
    const std::vector<std::array<std::uint32_t, 3>>& triangulate(std::span<const Vec3> corners);

private:
    std::vector<std::array<double, 2>> projected_;
    std::vector<std::uint32_t> remaining_;
    std::vector<std::array<std::uint32_t, 3>> triangles_;
};

}  // namespace twinray::scene::meshio
