// Primary rays: the camera's packets of 2 × 2 pixels, tiles of 16 × 16 handed to the worker threads,
// and the primitives each tile can see. Only the SSE tracer's own translation units (built with
// -msse4.1) include this.
#pragma once

#include "render/ray_tree.h"
#include "sse/compiled_scene.h"
#include "sse/mutation.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace twinray::sse {

// The reference's camera (reference/tracer.cpp) in float, set up once per image size: the pixel
// centre (px, py) maps to u = (px·2/W − 1)·tan(fov/2) and v = (1 − py·2/H)·tan(fov/2)·H/W, with the
// two divisions hoisted out of the per-pixel work.
struct CameraPacket {
    Vec3x4 eye, forward, right, up;
    vfloat4 u_per_pixel, v_per_pixel, half_width, half_height;

    CameraPacket(const CompiledScene& s, int width, int height)
        : eye(broadcast(s.camera.eye)),
          forward(broadcast(s.camera.forward)),
          right(broadcast(s.camera.right)),
          up(broadcast(s.camera.up)),
          u_per_pixel(2.0f / static_cast<float>(width)),
          v_per_pixel(2.0f / static_cast<float>(height)),
          half_width(s.camera.half_width),
          half_height(s.camera.half_width * static_cast<float>(height) / static_cast<float>(width)) {}

    // The 2 × 2 pixels whose top-left is (x, y): lane i is pixel (x + i % 2, y + i / 2). Every lane is
    // computed alone, so a pixel's ray is the same in any packet.
    template <typename P>
    RayPacket rays(int x, int y, vbool4 active) const {
        constexpr float centre = mutated<Mutant::camera_off_by_half_pixel> ? 0.0f : 0.5f;
        vfloat4 px = vfloat4(static_cast<float>(x)) + vfloat4(_mm_setr_ps(centre, centre + 1, centre, centre + 1));
        vfloat4 py = vfloat4(static_cast<float>(y)) + vfloat4(_mm_setr_ps(centre, centre, centre + 1, centre + 1));
        vfloat4 u = (px * u_per_pixel - vfloat4(1.0f)) * half_width;
        vfloat4 v = (vfloat4(1.0f) - py * v_per_pixel) * half_height;
        Vec3x4 direction = normalize<P>(forward + u * right + v * up);
        return RayPacket(eye, direction, active);
    }
};

// Primary rays of one tile all start at the eye and pass through the tile's rectangle on the image
// plane: a pyramid. A primitive whose bounding sphere lies wholly outside one of its four side planes
// cannot be hit by any of them, so the tile's packets test only the rest. This is exact, not an
// approximation: the planes are moved out by a margin far beyond float rounding (1e-4 of the distance),
// so no primitive a ray could hit is ever dropped, and the image is the same as without culling.
// Secondary and shadow rays go everywhere and test every primitive. With a BVH only the primitives it leaves
// out (planes, never culled) are listed: the BVH culls the rest.
class TileCulling {
public:
    TileCulling(const CompiledScene& scene, int width, int height) : scene_(scene), width_(width), height_(height) {}

    // The primitives of scene.flat() visible in the pixels [x0, x1) × [y0, y1), written into `visible` (reused
    // storage: no allocation once it has grown).
    void select(int x0, int y0, int x1, int y1, PrimitiveLists& visible) const {
        std::array<Vec3d, 4> corners = {corner(x0, y0), corner(x1, y0), corner(x1, y1), corner(x0, y1)};
        std::array<Vec3d, 4> normals;
        Vec3d centre{0, 0, 0};  // inside the pyramid: orients each side plane's normal inward
        for (const Vec3d& c : corners) {
            centre += c;
        }
        for (int i = 0; i < 4; ++i) {
            normals[i] = math::cross(corners[i], corners[(i + 1) % 4]);
            double length = std::sqrt(math::dot(normals[i], normals[i]));
            double inward = math::dot(normals[i], centre) < 0 ? -1.0 : 1.0;
            normals[i] = (inward / length) * normals[i];
        }
        scene_.flat().for_each_pair(visible, [&](const auto& all, auto& kept) { keep_visible(all, normals, kept); });
    }

private:
    // The direction through pixel corner (x, y) of the image plane (pixel edges, not centres).
    Vec3d corner(int x, int y) const {
        const math::CameraBasis<float>& camera = scene_.camera;
        double half_height = static_cast<double>(camera.half_width) * height_ / width_;
        double u = (2.0 * x / width_ - 1.0) * camera.half_width;
        double v = (1.0 - 2.0 * y / height_) * half_height;
        return Vec3d(camera.forward) + u * Vec3d(camera.right) + v * Vec3d(camera.up);
    }

    template <typename Shape>
    void keep_visible(const PrimitiveList<Shape>& all, const std::array<Vec3d, 4>& normals,
                      PrimitiveList<Shape>& visible) const {
        visible.clear();
        Vec3d eye(scene_.camera.eye);
        for (std::size_t i = 0; i < all.items.size(); ++i) {
            double radius = all.bound_radii[i];
            Vec3d offset = all.bound_centers[i] - eye;
            double margin = radius + 1e-4 * (std::sqrt(math::dot(offset, offset)) + radius);
            bool outside = false;
            for (const Vec3d& normal : normals) {
                outside = outside || math::dot(normal, offset) < -margin;
            }
            if (!outside) {
                visible.push_back_from(all, i);
            }
        }
    }

    const CompiledScene& scene_;
    int width_, height_;
};

constexpr int tile = 16;

// Hands out the image's 16 × 16 tiles to the worker threads and calls
// work(x0, y0, x1, y1, visible) for the pixels [x0, x1) × [y0, y1) with the primitives the tile can see
// (TileCulling); sums what it returns (a Sum). The denormal mode is set per tile, on whichever thread runs it,
// and restored after: the workers are the shared render loop's, and the calling thread is one of them.
template <typename Sum, typename TileWork>
Sum for_each_tile(const CompiledScene& scene, scene::ImageSize size, const RenderOptions& options, bool flush_denormals,
                  TileWork&& work) {
    TileCulling culling(scene, size.width, size.height);
    int tiles_x = (size.width + tile - 1) / tile;
    int tiles_y = (size.height + tile - 1) / tile;
    return parallel_sum<Sum>(
        tiles_x * tiles_y, options.threads,
        [&](int index) {
            ScopedFlushDenormals denormals(flush_denormals);
            int x0 = (index % tiles_x) * tile;
            int y0 = (index / tiles_x) * tile;
            int x1 = std::min(x0 + tile, size.width);
            int y1 = std::min(y0 + tile, size.height);
            thread_local PrimitiveLists visible;
            culling.select(x0, y0, x1, y1, visible);
            return work(x0, y0, x1, y1, static_cast<const PrimitiveLists&>(visible));
        },
        options.progress, options.cancel);
}

// Calls per_packet(x, y, active) for each 2 × 2 packet of the pixels [x0, x1) × [y0, y1), (x, y) its
// top-left pixel; lanes past the edge are inactive.
template <typename PerPacket>
void for_each_packet(int x0, int y0, int x1, int y1, PerPacket&& per_packet) {
    for (int y = y0; y < y1; y += 2) {
        for (int x = x0; x < x1; x += 2) {
            vbool4 active{_mm_castsi128_ps(
                _mm_setr_epi32(-1, x + 1 < x1 ? -1 : 0, y + 1 < y1 ? -1 : 0, x + 1 < x1 && y + 1 < y1 ? -1 : 0))};
            per_packet(x, y, active);
        }
    }
}

}  // namespace twinray::sse
