// twinray's own SSE tracer behind the tracer ABI (include/twinray/tracer.h), built from the same sources as the one
// `twinray` runs directly: the proof that the ABI carries everything the suite needs, since `twinray conform` gives
// it the same per-ray verdicts through the ABI as it gives the tracer directly (docs/plugins.md). The exact
// kernels, the BVH where --accel auto would build one. Rays and hits cross in double: a ray's direction is rounded
// to float as the direct path rounds it, a hit's float t and normal widened exactly.
#include "peers/sse_segment.h"
#include "plugin/abi_scene.h"
#include "plugin/judged_tracer.h"
#include "sse/cpu.h"
#include "sse/tracer.h"
#include "twinray/tracer.h"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <limits>
#include <optional>
#include <vector>

namespace {

using twinray::scene::Vec3;

struct Built {
    twinray::plugin::AbiScene abi;
    twinray::sse::Tracer tracer;

    explicit Built(twinray::plugin::AbiScene rebuilt) : abi(std::move(rebuilt)), tracer(abi.scene) {}
};

void write_error(char* error, std::size_t error_size, const char* message) {
    if (error != nullptr && error_size > 0) {
        std::snprintf(error, error_size, "%s", message);
    }
}

twinray::sse::Ray sse_ray(const twinray_ray& ray) {
    return twinray::peers::sse_ray(twinray::plugin::origin_of(ray), twinray::plugin::direction_of(ray));
}

// The hit point's barycentrics in its triangle, in double: the ABI's u and v (the SSE tracer finds t, not them).
// An instance's triangle is in its shape's space, where the point is taken back to.
void barycentrics(const Built& built, const twinray::sse::Hit& hit, twinray_hit& out) {
    const twinray::scene::Mesh* mesh = built.abi.scene.mesh_of_leaf(hit.leaf);
    Vec3 point = hit.point;
    if (mesh->placement) {
        const twinray::scene::Transform to_world = mesh->placement->transform();
        point = to_world.inverse * (point - to_world.translation);
    }
    const auto& corners = mesh->data->triangles[static_cast<std::size_t>(hit.triangle)];
    const Vec3 a = mesh->data->vertices[corners[0]];
    const Vec3 e1 = mesh->data->vertices[corners[1]] - a, e2 = mesh->data->vertices[corners[2]] - a;
    const Vec3 p = point - a;
    // p ≈ u·e1 + v·e2, in the least-squares sense (p lies in the plane up to float's rounding of the point).
    const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2), p1 = dot(p, e1), p2 = dot(p, e2);
    const double determinant = d11 * d22 - d12 * d12;
    out.u = determinant != 0 ? (d22 * p1 - d12 * p2) / determinant : 0;
    out.v = determinant != 0 ? (d11 * p2 - d12 * p1) / determinant : 0;
}

twinray_hit abi_hit(const Built& built, const twinray::sse::Hit& hit) {
    twinray_hit out{};
    out.hit = 1;
    const auto leaf = static_cast<std::size_t>(hit.leaf);
    out.object = built.abi.object_of_leaf[leaf];
    out.instance = built.abi.instance_of_leaf[leaf];
    out.primitive = hit.triangle >= 0 ? static_cast<std::uint32_t>(hit.triangle) : TWINRAY_NONE;
    out.t = hit.t;
    // The tracer's normal faces the ray; the ABI's is outward, which it is where the ray enters.
    const float side = hit.entering ? 1.0f : -1.0f;
    for (int axis = 0; axis < 3; ++axis) {
        out.normal[axis] = side * hit.normal[axis];
    }
    out.entering = hit.entering ? 1 : 0;
    if (hit.triangle >= 0) {
        barycentrics(built, hit, out);
    }
    return out;
}

void* build(const twinray_scene* scene, char* error, std::size_t error_size) {
    if (!twinray::sse::cpu_supports_sse41()) {
        write_error(error, error_size, twinray::sse::missing_sse41_message().c_str());
        return nullptr;
    }
    try {
        return new Built(twinray::plugin::scene_from_abi(*scene));
    } catch (const std::exception& failure) {
        write_error(error, error_size, failure.what());
        return nullptr;
    }
}

int intersect(void* built, const twinray_ray* rays, std::size_t count, twinray_hit* hits, std::size_t* written,
              char* error, std::size_t error_size) {
    const Built& tracer = *static_cast<const Built*>(built);
    try {
        for (std::size_t i = 0; i < count; ++i) {
            const std::optional<twinray::sse::Hit> nearest =
                twinray::peers::nearest_within(tracer.tracer, sse_ray(rays[i]), rays[i].t_min, rays[i].t_max);
            hits[i] = nearest ? abi_hit(tracer, *nearest) : twinray_hit{};
        }
    } catch (const std::exception& failure) {
        write_error(error, error_size, failure.what());
        return 1;
    }
    *written = count;
    return 0;
}

int hits_along(void* built, const twinray_ray* ray, twinray_hit* hits, std::size_t capacity, std::size_t* total,
               char* error, std::size_t error_size) {
    const Built& tracer = *static_cast<const Built*>(built);
    try {
        const std::vector<twinray::sse::Hit> along =
            twinray::peers::crossings_within(tracer.tracer, sse_ray(*ray), ray->t_min, ray->t_max);
        for (std::size_t i = 0; i < along.size() && i < capacity; ++i) {
            hits[i] = abi_hit(tracer, along[i]);
        }
        *total = along.size();
    } catch (const std::exception& failure) {
        write_error(error, error_size, failure.what());
        return 1;
    }
    return 0;
}

void release(void* built) {
    delete static_cast<Built*>(built);
}

const twinray_tracer table = {TWINRAY_TRACER_ABI_VERSION,
                              TWINRAY_TRACER_THREAD_SAFE,
                              "twinray sse",
                              "exact kernels",
                              TWINRAY_KIND_PLANE | TWINRAY_KIND_SPHERE | TWINRAY_KIND_CYLINDER | TWINRAY_KIND_BOX |
                                  TWINRAY_KIND_TRIANGLES | TWINRAY_KIND_TRANSFORMED | TWINRAY_KIND_INSTANCES,
                              0x1p-24,
                              build,
                              intersect,
                              hits_along,
                              release};

}  // namespace

extern "C" __attribute__((visibility("default"))) const twinray_tracer* twinray_tracer_entry() {
    return &table;
}
