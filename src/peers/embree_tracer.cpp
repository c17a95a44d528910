// Embree 3 behind the tracer ABI (include/twinray/tracer.h): the first tracer twinray judges that is not its own
// (docs/plugins.md). Spheres as RTC_GEOMETRY_TYPE_SPHERE_POINT, every mesh as RTC_GEOMETRY_TYPE_TRIANGLE, in float
// as Embree takes them; the other kinds are refused. Built twice: the default scene and, with
// TWINRAY_EMBREE_ROBUST, RTC_SCENE_FLAG_ROBUST (Embree's watertight mode).
#include "twinray/tracer.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <vector>

namespace {

#ifdef TWINRAY_EMBREE_ROBUST
constexpr RTCSceneFlags scene_flags = RTC_SCENE_FLAG_ROBUST;
constexpr const char* tracer_name = "embree 3 (robust)";
#else
constexpr RTCSceneFlags scene_flags = RTC_SCENE_FLAG_NONE;
constexpr const char* tracer_name = "embree 3";
#endif

struct Built {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    // By Embree's geometry id: the object it is, and whether its primitives are spheres (each its own object).
    std::vector<std::uint32_t> object_of_geometry;
    std::vector<std::uint32_t> sphere_objects;
    unsigned sphere_geometry = RTC_INVALID_GEOMETRY_ID;
};

// An intersect context that, when `collected` is set, gathers every hit the traversal meets and rejects each so
// that it goes on (the filter sees the candidate's t in the ray's tfar).
struct CollectingContext {
    RTCIntersectContext context;
    std::vector<twinray_hit>* collected;
    const Built* built;
};

twinray_hit abi_hit(const Built& built, float t, unsigned geometry, unsigned primitive, const float (&ng)[3], float u,
                    float v, const double (&direction)[3]) {
    twinray_hit hit{};
    hit.hit = 1;
    const bool sphere = geometry == built.sphere_geometry;
    hit.object = sphere ? built.sphere_objects[primitive] : built.object_of_geometry[geometry];
    hit.primitive = sphere ? TWINRAY_NONE : primitive;
    hit.instance = TWINRAY_NONE;
    hit.t = t;
    const double length = std::sqrt(double(ng[0]) * ng[0] + double(ng[1]) * ng[1] + double(ng[2]) * ng[2]);
    for (int axis = 0; axis < 3; ++axis) {
        hit.normal[axis] = ng[axis] / length;
    }
    hit.u = sphere ? 0 : u;
    hit.v = sphere ? 0 : v;
    hit.entering =
        hit.normal[0] * direction[0] + hit.normal[1] * direction[1] + hit.normal[2] * direction[2] < 0 ? 1 : 0;
    return hit;
}

void collect(const RTCFilterFunctionNArguments* arguments) {
    const auto* context = reinterpret_cast<const CollectingContext*>(arguments->context);
    if (context->collected == nullptr) {
        return;
    }
    auto* ray = reinterpret_cast<RTCRay*>(arguments->ray);
    auto* hit = reinterpret_cast<RTCHit*>(arguments->hit);
    arguments->valid[0] = 0;
    const double direction[3] = {ray->dir_x, ray->dir_y, ray->dir_z};
    const float ng[3] = {hit->Ng_x, hit->Ng_y, hit->Ng_z};
    const twinray_hit met =
        abi_hit(*context->built, ray->tfar, hit->geomID, hit->primID, ng, hit->u, hit->v, direction);
    // Embree calls the filter again for a triangle its spatial splits put in several leaves (its documentation says
    // so): one surface met at one t is one hit.
    for (const twinray_hit& earlier : *context->collected) {
        if (earlier.object == met.object && earlier.primitive == met.primitive && earlier.t == met.t) {
            return;
        }
    }
    context->collected->push_back(met);
}

void* build(const twinray_scene* in, char* error, std::size_t error_size) {
    auto* built = new Built;
    built->device = rtcNewDevice(nullptr);
    if (built->device == nullptr) {
        std::snprintf(error, error_size, "rtcNewDevice failed (error %d)", int(rtcGetDeviceError(nullptr)));
        delete built;
        return nullptr;
    }
    built->scene = rtcNewScene(built->device);
    rtcSetSceneFlags(built->scene, scene_flags);
    auto attach = [&](RTCGeometry geometry, std::uint32_t object) {
        rtcSetGeometryIntersectFilterFunction(geometry, collect);
        rtcCommitGeometry(geometry);
        const unsigned id = rtcAttachGeometry(built->scene, geometry);
        rtcReleaseGeometry(geometry);
        built->object_of_geometry.resize(id + 1, TWINRAY_NONE);
        built->object_of_geometry[id] = object;
        return id;
    };
    if (in->sphere_count > 0) {
        RTCGeometry spheres = rtcNewGeometry(built->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* points = static_cast<float*>(rtcSetNewGeometryBuffer(
            spheres, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), in->sphere_count));
        for (std::uint32_t i = 0; i < in->sphere_count; ++i) {
            const twinray_sphere& sphere = in->spheres[i];
            for (int axis = 0; axis < 3; ++axis) {
                points[4 * i + axis] = static_cast<float>(sphere.center[axis]);
            }
            points[4 * i + 3] = static_cast<float>(sphere.radius);
            built->sphere_objects.push_back(sphere.object);
        }
        built->sphere_geometry = attach(spheres, TWINRAY_NONE);
    }
    for (std::uint32_t m = 0; m < in->mesh_count; ++m) {
        const twinray_mesh& mesh = in->meshes[m];
        RTCGeometry triangles = rtcNewGeometry(built->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            triangles, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertex_count));
        for (std::uint32_t i = 0; i < 3 * mesh.vertex_count; ++i) {
            vertices[i] = static_cast<float>(mesh.vertices[i]);
        }
        auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            triangles, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangle_count));
        for (std::uint32_t i = 0; i < 3 * mesh.triangle_count; ++i) {
            indices[i] = mesh.triangles[i];
        }
        attach(triangles, mesh.object);
    }
    rtcCommitScene(built->scene);
    if (const RTCError failure = rtcGetDeviceError(built->device); failure != RTC_ERROR_NONE) {
        std::snprintf(error, error_size, "Embree failed to build the scene (error %d)", int(failure));
        rtcReleaseScene(built->scene);
        rtcReleaseDevice(built->device);
        delete built;
        return nullptr;
    }
    return built;
}

void release(void* opaque) {
    auto* built = static_cast<Built*>(opaque);
    rtcReleaseScene(built->scene);
    rtcReleaseDevice(built->device);
    delete built;
}

RTCRayHit embree_ray(const twinray_ray& ray) {
    RTCRayHit query{};
    query.ray.org_x = static_cast<float>(ray.origin[0]);
    query.ray.org_y = static_cast<float>(ray.origin[1]);
    query.ray.org_z = static_cast<float>(ray.origin[2]);
    query.ray.dir_x = static_cast<float>(ray.direction[0]);
    query.ray.dir_y = static_cast<float>(ray.direction[1]);
    query.ray.dir_z = static_cast<float>(ray.direction[2]);
    // Embree's range is closed, the ABI's open: the next float past each end.
    query.ray.tnear = std::nextafter(static_cast<float>(ray.t_min), std::numeric_limits<float>::infinity());
    query.ray.tfar = std::nextafter(static_cast<float>(ray.t_max), 0.0f);
    query.ray.mask = 0xFFFFFFFFu;
    query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    return query;
}

int intersect(void* opaque, const twinray_ray* rays, std::size_t count, twinray_hit* hits, std::size_t* written, char*,
              std::size_t) {
    const auto* built = static_cast<const Built*>(opaque);
    CollectingContext context{{}, nullptr, built};
    rtcInitIntersectContext(&context.context);
    for (std::size_t i = 0; i < count; ++i) {
        RTCRayHit query = embree_ray(rays[i]);
        rtcIntersect1(built->scene, &context.context, &query);
        hits[i] = {};
        if (query.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
            const float ng[3] = {query.hit.Ng_x, query.hit.Ng_y, query.hit.Ng_z};
            hits[i] = abi_hit(*built, query.ray.tfar, query.hit.geomID, query.hit.primID, ng, query.hit.u, query.hit.v,
                              rays[i].direction);
        }
    }
    *written = count;
    return 0;
}

int hits_along(void* opaque, const twinray_ray* ray, twinray_hit* hits, std::size_t capacity, std::size_t* total, char*,
               std::size_t) {
    const auto* built = static_cast<const Built*>(opaque);
    std::vector<twinray_hit> collected;
    CollectingContext context{{}, &collected, built};
    rtcInitIntersectContext(&context.context);
    RTCRayHit query = embree_ray(*ray);
    rtcIntersect1(built->scene, &context.context, &query);
    std::stable_sort(collected.begin(), collected.end(),
                     [](const twinray_hit& a, const twinray_hit& b) { return a.t < b.t; });
    for (std::size_t i = 0; i < collected.size() && i < capacity; ++i) {
        hits[i] = collected[i];
    }
    *total = collected.size();
    return 0;
}

const twinray_tracer table = {TWINRAY_TRACER_ABI_VERSION,
                              TWINRAY_TRACER_THREAD_SAFE,
                              tracer_name,
                              RTC_VERSION_STRING,
                              TWINRAY_KIND_SPHERE | TWINRAY_KIND_TRIANGLES,
                              0x1p-24,
                              build,
                              intersect,
                              hits_along,
                              release};

}  // namespace

extern "C" __attribute__((visibility("default"))) const twinray_tracer* twinray_tracer_entry() {
    return &table;
}
