// The optimized tracer: single precision, SSE4.1 kernels that test four rays (a packet) against one
// primitive at once, the scene compiled into flat per-type arrays. Same per-ray API as the reference
// tracer; a single ray runs as a packet with one active lane, bit-identical to the same ray in render.
//
// This header is included by code built without -msse4.1 (CLI, tests, bench), so it exposes no
// intrinsics: the compiled scene lives behind a pointer (sse/compiled_scene.h, built with -msse4.1). Call
// cpu_supports_sse41() (sse/cpu.h) before constructing a Tracer.
#pragma once

#include "render/ray_tree.h"
#include "render/render.h"
#include "scene/scene.h"
#include "sse/vec3.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace twinray::sse {

// In world coordinates. The origin is in double: the tracer subtracts its own origin (origin_of) in double
// and rounds the difference to float, so a ray far from the world's origin but near the camera is held to
// float's precision of its distance from the camera, not of its coordinates. `direction` is of unit
// length, so t is a distance.
struct Ray {
    Vec3d origin;
    Vec3 direction;
};

struct Hit {
    float t = 0;
    Vec3d point;             // re-projected onto the primitive's surface; world coordinates (origin_of + float point)
    Vec3 normal;             // unit, facing the ray
    int leaf = -1;           // the primitive hit (Scene::leaf_paths)
    int triangle = -1;       // for a mesh, the triangle's index in it
    int part = -1;           // on an instance of a solid shape, the shape's primitive hit
    bool entering = false;   // enters the solid; on a mesh, meets a triangle's front
    float spawn_offset = 0;  // how far off the surface secondary rays start
    Vec3 shading_normal;     // `normal`, or on a smooth mesh the interpolated normal turned to its side
};

// The speed/accuracy knobs (docs/performance.md). The default is the exact tracer; each knob trades
// accuracy for speed. The five kernel knobs select a separately compiled tracer (precision.h), built
// for exact, each knob alone and rcp+rsqrt+textbook (precision_is_built); flush_denormals is a run-time
// MXCSR setting, combinable with any of them.
struct Precision {
    bool fast_rcp = false;            // divisions: _mm_rcp_ps + one Newton step instead of _mm_div_ps
    bool fast_rsqrt = false;          // normalisation: _mm_rsqrt_ps + one Newton step instead of sqrt, divide
    bool dpps = false;                // dot products: transposed to AoS and _mm_dp_ps instead of SoA
    bool textbook_quadratic = false;  // b² − ac instead of the cancellation-free discriminant
    bool moller_trumbore = false;     // triangles: Möller–Trumbore, not watertight, instead of the sheared test
    bool flush_denormals = false;     // MXCSR flush-to-zero and denormals-are-zero while tracing

    bool operator==(const Precision&) const = default;
};

// Whether the kernels of this combination are compiled in; the others are refused by Tracer and render
// with std::invalid_argument naming the combinations that are.
bool precision_is_built(const Precision& precision);
std::string built_precisions();
// Every combination precision_is_built, each without and with flush_denormals: what the suites judge.
std::vector<Precision> every_built_precision();
// "exact", or the knobs joined by '+' ("rcp+rsqrt+ftz").
std::string precision_name(const Precision& precision);

// With Accel::automatic (render/render.h) the tracer builds its BVH (docs/sse-tracer.md) where brute force
// would spend more than bvh_crossover sphere tests per packet on the bounded objects: each primitive weighed
// by its kind's relative_test_cost (a box 2.7, a triangle 6.2, a CSG object its leaves and 2.2). Where rays may be
// reflected or refracted (max_depth above 1 and a leaf whose material reflects or transmits), above
// bvh_crossover_with_secondary_rays: those rays leave the coherent packets that tile culling serves, and brute force
// tests every bounded object for each. Both measured per kind, matte and glass, by `twinray bench --scaling`'s
// crossover table (docs/performance.md, "The BVH").
constexpr std::size_t bvh_crossover = 48;
constexpr std::size_t bvh_crossover_with_secondary_rays = 24;

// The point the tracer compiles a scene relative to, in double (re-basing, docs/numerics.md): the eye
// where that makes the scene's coordinates smaller than the world's origin does (then every number the
// float kernels see is a distance from the camera), else the world's origin. Results are translated back.
scene::Vec3 origin_of(const scene::Scene& scene);

struct CompiledScene;

// What a tracer's BVH holds and cost to build (all zero without one), for `twinray bench --scaling`.
struct BvhStats {
    std::size_t items = 0;  // bounded primitives and CSG objects in its leaves
    std::size_t nodes = 0;
    std::size_t bytes = 0;  // nodes, leaf items and file order (sse::bvh_bytes)
    double build_cpu_seconds = 0;
    // With Accel::automatic (else 0), what brute force would spend per packet on the bounded items, in sphere tests,
    // with or without a BVH: what it compares with `crossover`.
    double brute_force_weight = 0;
    std::size_t crossover = bvh_crossover;  // or bvh_crossover_with_secondary_rays
};

class Tracer {
public:
    explicit Tracer(const scene::Scene& scene, const Precision& precision = {}, Accel accel = Accel::automatic);
    // The same, and scene.objects, scene.meshes and scene.leaf_paths emptied once compiled, for a caller that reads
    // none of them again (render): the compiled records are the tracer's own, and neither 600 000 spheres' objects (72
    // bytes each) nor a million instances' placements (136 MB) are held beside them.
    struct GiveUpGeometry {};
    static constexpr GiveUpGeometry give_up_geometry{};
    Tracer(scene::Scene& scene, GiveUpGeometry, const Precision& precision = {}, Accel accel = Accel::automatic);
    ~Tracer();
    Tracer(const Tracer&) = delete;
    Tracer& operator=(const Tracer&) = delete;

    // As the reference's (reference/ray.h), a ray is traced only if every component of its origin relative
    // to origin_of (in float) and of its direction is finite and the direction is of unit length within
    // 1e-3; any other ray is a miss (intersect) or the background (trace).
    std::optional<Hit> intersect(const Ray& ray) const;
    // The ray is one pixel's tree, with the whole ray budget (scene/depth_control.h). `tally`, if given,
    // adds the rays traced, the secondary rays the depth control left out and whether the budget ran out.
    // `tree`, if given, receives every ray traced, what it hit, each light's visibility, its colours and the
    // rays left out (twinray probe); the colour is the same with or without it.
    Color trace(const Ray& ray, int depth, TraceTally* tally = nullptr, RayTree* tree = nullptr) const;
    Ray primary_ray(int x, int y, int width, int height) const;

    // Every surface the ray crosses with t in (0, distance), by increasing (t, leaf, triangle), each as intersect
    // would report it were it the nearest; a triangle met twice at one t (through a shared edge) twice. Through the
    // BVH where there is one. The tracer ABI's hits_along (docs/plugins.md).
    std::vector<Hit> hits_along(const Ray& ray, float distance) const;
    // How many of hits_along's are on mesh triangles (accuracy/watertight.h).
    int mesh_crossings(const Ray& ray, float distance) const;

    const CompiledScene& compiled() const { return *scene_; }
    const Precision& precision() const { return precision_; }
    BvhStats bvh_stats() const;

private:
    Tracer(std::unique_ptr<CompiledScene> compiled, const Precision& precision);

    std::unique_ptr<CompiledScene> scene_;
    Precision precision_;
};

RenderResult render(const scene::Scene& scene, const RenderOptions& options);
RenderResult render(const scene::Scene& scene, const RenderOptions& options, const Precision& precision);
// With a tracer built for `scene` (its knobs and structure; options.accel is not read).
RenderResult render(const Tracer& tracer, const scene::Scene& scene, const RenderOptions& options);

// Primary rays only: every pixel's nearest hit (the same packets, tile culling and intersection as
// render, with the normal), no shading. The first-hit speed to hold against other ray casters (Embree).
struct FirstHits {
    std::uint64_t rays = 0;
    std::uint64_t hits = 0;
    // CPU time of the casts alone, as RenderResult's: building the tracer is left out.
    double tracing_cpu_seconds = 0;
};
FirstHits cast_primary_rays(const scene::Scene& scene, const RenderOptions& options, const Precision& precision = {});

}  // namespace twinray::sse
