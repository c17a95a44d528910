// The body of libtwinray_embree.so (peers/embree_module.h): the only code linked to Embree 3.
#include "peers/embree_module.h"

#include "reference/cylinder.h"
#include "scene/geometry.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <deque>
#include <limits>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace twinray::peers {
namespace {

using Shape = reference::CylinderShape<float>;
using FloatVec = reference::Vec3<float>;

// A plane becomes one quad of half-side plane_extent around its point nearest the origin: Embree has
// no infinite primitive, and its native quads beat a user callback. Our scenes meet their planes
// within about 1e4 of the origin.
constexpr double plane_extent = 1e5;

// Planes and boxes as quads (Embree's own geometry): four vertices each, index quads.
struct Quads {
    std::vector<float> vertices;  // x, y, z per vertex, then 4 bytes of padding Embree may read
    std::vector<unsigned> indices;

    void add(const scene::Vec3 corners[4]) {
        auto first = static_cast<unsigned>(vertices.size() / 3);
        for (int i = 0; i < 4; ++i) {
            for (int axis = 0; axis < 3; ++axis) {
                vertices.push_back(static_cast<float>(corners[i][axis]));
            }
            indices.push_back(first + static_cast<unsigned>(i));
        }
    }
};

scene::Vec3 combine(const scene::Vec3& p, double a, const scene::Vec3& u, double b, const scene::Vec3& v) {
    return {p[0] + a * u[0] + b * v[0], p[1] + a * u[1] + b * v[1], p[2] + a * u[2] + b * v[2]};
}

void add_plane(const scene::Plane& plane, Quads& quads) {
    const scene::Vec3& n = plane.normal;
    // A tangent: n crossed with the axis n is least aligned with, then the second by n × first.
    int least = std::fabs(n[0]) <= std::fabs(n[1]) && std::fabs(n[0]) <= std::fabs(n[2]) ? 0
                : std::fabs(n[1]) <= std::fabs(n[2])                                     ? 1
                                                                                         : 2;
    scene::Vec3 axis{least == 0 ? 1.0 : 0.0, least == 1 ? 1.0 : 0.0, least == 2 ? 1.0 : 0.0};
    scene::Vec3 u = math::normalize(math::cross(n, axis));
    scene::Vec3 v = math::cross(n, u);
    scene::Vec3 centre = plane.offset * n;
    const double e = plane_extent;
    const scene::Vec3 corners[4] = {combine(centre, -e, u, -e, v), combine(centre, e, u, -e, v),
                                    combine(centre, e, u, e, v), combine(centre, -e, u, e, v)};
    quads.add(corners);
}

void add_box(const scene::Box& box, Quads& quads) {
    for (int axis = 0; axis < 3; ++axis) {
        int a = (axis + 1) % 3, b = (axis + 2) % 3;
        for (double side : {box.min[axis], box.max[axis]}) {
            scene::Vec3 corners[4];
            const double along_a[4] = {box.min[a], box.max[a], box.max[a], box.min[a]};
            const double along_b[4] = {box.min[b], box.min[b], box.max[b], box.max[b]};
            for (int i = 0; i < 4; ++i) {
                corners[i][axis] = side;
                corners[i][a] = along_a[i];
                corners[i][b] = along_b[i];
            }
            quads.add(corners);
        }
    }
}

struct UserGeometry {
    std::vector<Shape> shapes;
    std::vector<RTCBounds> bounds;
};

RTCBounds bounds_of(const Shape& s) {
    FloatVec cap = s.base + s.height * s.axis;
    float r = s.radius;
    return {std::min(s.base[0], cap[0]) - r, std::min(s.base[1], cap[1]) - r, std::min(s.base[2], cap[2]) - r, 0,
            std::max(s.base[0], cap[0]) + r, std::max(s.base[1], cap[1]) + r, std::max(s.base[2], cap[2]) + r, 0};
}

void user_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* geometry = static_cast<const UserGeometry*>(args->geometryUserPtr);
    *args->bounds_o = geometry->bounds[args->primID];
}

// The nearest crossing of the shape in (tnear, tfar), as the reference finds it, recorded as Embree's hit.
void user_intersect(const RTCIntersectFunctionNArguments* args) {
    const auto* geometry = static_cast<const UserGeometry*>(args->geometryUserPtr);
    const Shape& shape = geometry->shapes[args->primID];
    RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] == 0) {
            continue;
        }
        // Inside an instance Embree hands over L⁻¹·d, not of unit length; the reference's formula takes a unit
        // direction, along which t grows by that length.
        FloatVec direction{RTCRayN_dir_x(rays, args->N, i), RTCRayN_dir_y(rays, args->N, i),
                           RTCRayN_dir_z(rays, args->N, i)};
        float length = reference::length(direction);
        reference::Ray<float> ray{
            {RTCRayN_org_x(rays, args->N, i), RTCRayN_org_y(rays, args->N, i), RTCRayN_org_z(rays, args->N, i)},
            direction / length};
        float near = RTCRayN_tnear(rays, args->N, i);
        float& far = RTCRayN_tfar(rays, args->N, i);
        auto span = reference::span_of(shape, ray);
        if (!span) {
            continue;
        }
        const reference::Crossing<float>& crossing = span->enter.t / length > near ? span->enter : span->exit;
        float t = crossing.t / length;
        if (!(t > near && t < far)) {
            continue;
        }
        far = t;
        RTCHitN_Ng_x(hits, args->N, i) = crossing.outward_normal[0];
        RTCHitN_Ng_y(hits, args->N, i) = crossing.outward_normal[1];
        RTCHitN_Ng_z(hits, args->N, i) = crossing.outward_normal[2];
        RTCHitN_u(hits, args->N, i) = 0;
        RTCHitN_v(hits, args->N, i) = 0;
        RTCHitN_primID(hits, args->N, i) = args->primID;
        RTCHitN_geomID(hits, args->N, i) = args->geomID;
        RTCHitN_instID(hits, args->N, i, 0) = args->context->instID[0];
    }
}

// The primitives of one Embree scene, gathered by kind before they become its geometries.
struct Geometries {
    std::vector<float> spheres;  // x, y, z, r
    Quads quads;
    UserGeometry user;
};

// Each primitive as Embree holds it: spheres natively, planes and boxes as quads, cylinders as user
// geometry intersected by the reference's formula. Anything else (CSG) is refused; a transformed primitive
// becomes an instance (add_placed).
void add_to_peer(const scene::Sphere& sphere, int, Geometries& geometries) {
    for (double v : {sphere.center[0], sphere.center[1], sphere.center[2], sphere.radius}) {
        geometries.spheres.push_back(static_cast<float>(v));
    }
}
void add_to_peer(const scene::Plane& plane, int, Geometries& geometries) {
    add_plane(plane, geometries.quads);
}
void add_to_peer(const scene::Box& box, int, Geometries& geometries) {
    add_box(box, geometries.quads);
}
void add_to_peer(const scene::Cylinder& cylinder, int leaf, Geometries& geometries) {
    geometries.user.shapes.push_back(reference::make_shape<float>(cylinder, leaf));
}
template <typename Unsupported>
void add_to_peer(const Unsupported&, int, Geometries&) {
    throw std::runtime_error("Embree peer: scenes with CSG are not supported");
}

// The scene takes its own reference to the committed geometry.
void attach(RTCScene scene, RTCGeometry geometry) {
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
}

// A mesh as Embree's native triangles, its vertices the scene's in float as the spheres' (no re-basing), its
// degenerate triangles left out: one collinear in double may round to a float sliver that Embree would hit
// where neither tracer ever does, and the SSE tracer leaves them out of its triangle list too, so both build
// over the same triangles. The buffers are Embree's (padded as it reads them), so none of ours need outlive it.
void add_mesh(RTCDevice device, RTCScene scene, const scene::MeshData& mesh) {
    const std::size_t hittable = mesh.triangles.size() - mesh.degenerate.size();
    if (hittable == 0) {
        return;
    }
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertex = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.vertices.size()));
    auto* index = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), hittable));
    if (vertex == nullptr || index == nullptr) {
        rtcReleaseGeometry(geometry);
        throw std::runtime_error("Embree: a mesh's buffers could not be allocated (error " +
                                 std::to_string(rtcGetDeviceError(device)) + ")");
    }
    for (const scene::Vec3& v : mesh.vertices) {
        for (int axis = 0; axis < 3; ++axis) {
            *vertex++ = static_cast<float>(v[axis]);
        }
    }
    scene::for_each_live_triangle(mesh, [&](std::uint32_t triangle) {
        index = std::copy(mesh.triangles[triangle].begin(), mesh.triangles[triangle].end(), index);
    });
    attach(scene, geometry);
}

// CPU time (user + system) of the process: the casts and the build run on the calling thread alone, and on a
// busy machine this does not count waiting for a core (the SSE tracer's side is timed the same way).
double cpu_seconds() {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// A primary ray in float world coordinates, as Embree takes it: its scene is built from the scene's float
// coordinates (the SSE tracer's rays are re-based, with a double origin).
struct FloatRay {
    sse::Vec3 origin, direction;
};

struct State {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    Geometries world;
    // A scene of its own per transformed primitive, in object space, with its geometries (kept where they are:
    // Embree shares their buffers).
    std::deque<Geometries> placed;
    std::vector<RTCScene> placed_scenes;
    int width = 0, height = 0;
    std::vector<FloatRay> rays;  // row by row
    double build_seconds = 0;    // CPU: the geometries and the scene's BVH, on one thread

    ~State() {
        if (scene != nullptr)
            rtcReleaseScene(scene);
        for (RTCScene child : placed_scenes)
            rtcReleaseScene(child);
        if (device != nullptr)
            rtcReleaseDevice(device);
    }
};

// The gathered primitives as Embree geometries of `scene`: the spheres, the quads and the user geometry, each
// one geometry where there are any.
void attach_all(RTCDevice device, RTCScene scene, Geometries& g) {
    if (!g.spheres.empty()) {
        RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, g.spheres.data(), 0,
                                   4 * sizeof(float), g.spheres.size() / 4);
        attach(scene, geometry);
    }
    if (!g.quads.indices.empty()) {
        g.quads.vertices.push_back(0.0f);  // the padding
        RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_QUAD);
        rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, g.quads.vertices.data(), 0,
                                   3 * sizeof(float), (g.quads.vertices.size() - 1) / 3);
        rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, g.quads.indices.data(), 0,
                                   4 * sizeof(unsigned), g.quads.indices.size() / 4);
        attach(scene, geometry);
    }
    if (!g.user.shapes.empty()) {
        for (const Shape& shape : g.user.shapes) {
            g.user.bounds.push_back(bounds_of(shape));
        }
        RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned>(g.user.shapes.size()));
        rtcSetGeometryUserData(geometry, &g.user);
        rtcSetGeometryBoundsFunction(geometry, user_bounds, nullptr);
        rtcSetGeometryIntersectFunction(geometry, user_intersect);
        attach(scene, geometry);
    }
}

template <typename S>
void add_object(State& s, const S& shape, int leaf) {
    add_to_peer(shape, leaf, s.world);
}

// An instance of `child` placed in the scene by `m`.
void attach_instance(State& s, RTCScene child, const scene::Transform& m) {
    float rows[12];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            rows[4 * i + j] = static_cast<float>(m.linear.row[i][j]);
        }
        rows[4 * i + 3] = static_cast<float>(m.translation[i]);
    }
    RTCGeometry instance = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance, child);
    rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, rows);
    attach(s.scene, instance);
}

// A transformed primitive as Embree's own instancing holds it: the primitive in a scene of its own, in object
// space, and an instance of that scene placed by the transform. Embree carries the ray into object space by
// the inverse as we do (without re-basing or normalising it).
template <typename S>
void add_object(State& s, const scene::Transformed<S>& primitive, int leaf) {
    Geometries& geometries = s.placed.emplace_back();
    add_to_peer(primitive.shape(), leaf, geometries);
    RTCScene child = rtcNewScene(s.device);
    s.placed_scenes.push_back(child);
    attach_all(s.device, child, geometries);
    rtcCommitScene(child);
    attach_instance(s, child, primitive.to_world());
}

// Each mesh shape once, as a scene of its own in its own space, for its instances (Embree's two-level scenes).
std::vector<RTCScene> shape_scenes(State& s, const scene::Scene& scene) {
    std::vector<RTCScene> scenes;
    for (const scene::MeshShape& shape : scene.mesh_shapes) {
        RTCScene child = rtcNewScene(s.device);
        s.placed_scenes.push_back(child);
        add_mesh(s.device, child, *shape.data);
        rtcCommitScene(child);
        scenes.push_back(child);
    }
    return scenes;
}

void* create(const scene::Scene& scene, std::vector<sse::Ray> rays, int width, int height, EmbreeIsa isa,
             EmbreeMode mode) {
    auto state = std::make_unique<State>();
    State& s = *state;
    // One thread, as the SSE tracer builds its BVH: build times compare like with like.
    s.device = rtcNewDevice(isa == EmbreeIsa::sse42 ? "threads=1,isa=sse4.2" : "threads=1");
    if (s.device == nullptr) {
        throw std::runtime_error("Embree: rtcNewDevice failed (error " + std::to_string(rtcGetDeviceError(nullptr)) +
                                 ")");
    }
    const double build_start = cpu_seconds();
    s.scene = rtcNewScene(s.device);
    rtcSetSceneFlags(s.scene, mode == EmbreeMode::robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    for (const scene::Object& object : scene.objects) {
        std::visit([&](const auto& shape) { add_object(s, shape, object.leaf); }, object.shape);
    }
    attach_all(s.device, s.scene, s.world);
    const std::vector<RTCScene> shapes = shape_scenes(s, scene);
    for (const scene::Mesh& mesh : scene.meshes) {
        if (mesh.placement) {
            attach_instance(s, shapes[static_cast<std::size_t>(mesh.placement->shape)], mesh.placement->transform());
        } else {
            add_mesh(s.device, s.scene, *mesh.data);
        }
    }
    rtcCommitScene(s.scene);
    s.build_seconds = cpu_seconds() - build_start;
    if (RTCError error = rtcGetDeviceError(s.device); error != RTC_ERROR_NONE) {
        throw std::runtime_error("Embree: building the scene failed (error " + std::to_string(error) + ")");
    }
    s.width = width;
    s.height = height;
    s.rays.reserve(rays.size());
    for (const sse::Ray& ray : rays) {
        s.rays.push_back({sse::Vec3(ray.origin), ray.direction});
    }
    return state.release();
}

void destroy(void* state) {
    delete static_cast<State*>(state);
}

FirstHitRun cast_single(const void* state) {
    const State& s = *static_cast<const State*>(state);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    FirstHitRun run;
    const double start = cpu_seconds();
    for (const FloatRay& ray : s.rays) {
        RTCRayHit rayhit{};
        rayhit.ray = {ray.origin.x,
                      ray.origin.y,
                      ray.origin.z,
                      0.0f,
                      ray.direction.x,
                      ray.direction.y,
                      ray.direction.z,
                      0.0f,
                      std::numeric_limits<float>::infinity(),
                      ~0u,
                      0,
                      0};
        rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(s.scene, &context, &rayhit);
        run.hits += rayhit.hit.geomID != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
    }
    run.seconds = cpu_seconds() - start;
    run.rays = s.rays.size();
    return run;
}

// Packets of `Lanes` rays over tiles of Width x Lanes/Width pixels, with the coherent flag: Embree's
// own path for rays that share an origin, its frustum per packet (issue 27's peer).
template <int Lanes, int Width, typename RayHitN, typename Intersect>
FirstHitRun cast_tiles(const State& s, Intersect intersect) {
    constexpr int height = Lanes / Width;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    FirstHitRun run;
    const double start = cpu_seconds();
    for (int y = 0; y < s.height; y += height) {
        for (int x = 0; x < s.width; x += Width) {
            alignas(64) RayHitN packet{};
            alignas(64) int valid[Lanes];
            for (int lane = 0; lane < Lanes; ++lane) {
                int px = x + lane % Width, py = y + lane / Width;
                valid[lane] = px < s.width && py < s.height ? -1 : 0;
                const FloatRay& ray =
                    s.rays[static_cast<std::size_t>(valid[lane] != 0 ? py * s.width + px : y * s.width + x)];
                packet.ray.org_x[lane] = ray.origin.x;
                packet.ray.org_y[lane] = ray.origin.y;
                packet.ray.org_z[lane] = ray.origin.z;
                packet.ray.dir_x[lane] = ray.direction.x;
                packet.ray.dir_y[lane] = ray.direction.y;
                packet.ray.dir_z[lane] = ray.direction.z;
                packet.ray.tnear[lane] = 0.0f;
                packet.ray.tfar[lane] = std::numeric_limits<float>::infinity();
                packet.ray.mask[lane] = ~0u;
                packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
            }
            intersect(valid, s.scene, &context, &packet);
            for (int lane = 0; lane < Lanes; ++lane) {
                run.hits += valid[lane] != 0 && packet.hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
            }
        }
    }
    run.seconds = cpu_seconds() - start;
    run.rays = s.rays.size();
    return run;
}

FirstHitRun cast_packets(const void* state, int lanes) {
    const State& s = *static_cast<const State*>(state);
    switch (lanes) {
        case 4: return cast_tiles<4, 2, RTCRayHit4>(s, rtcIntersect4);
        case 8: return cast_tiles<8, 4, RTCRayHit8>(s, rtcIntersect8);
        case 16: return cast_tiles<16, 4, RTCRayHit16>(s, rtcIntersect16);
        default: throw std::invalid_argument("Embree packets hold 4, 8 or 16 rays, not " + std::to_string(lanes));
    }
}

double build_seconds(const void* state) {
    return static_cast<const State*>(state)->build_seconds;
}

const EmbreeFunctions functions{create, destroy, cast_single, cast_packets, build_seconds};

}  // namespace

}  // namespace twinray::peers

extern "C" const twinray::peers::EmbreeFunctions* twinray_embree_functions() {
    return &twinray::peers::functions;
}
