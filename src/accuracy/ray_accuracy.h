// A tracer's first hits held against reference<double>'s, primary ray by primary ray: the pairing, the
// geometry helpers and the statistics that the conformance suite (tests/conformance_test.cpp) judges
// by and that `twinray bench` reports, so both read the same numbers.
#pragma once

#include "reference/tracer.h"
#include "scene/scene.h"
#include "sse/tracer.h"
#include "tracing/any_tracer.h"

#include <functional>
#include <optional>
#include <vector>

namespace twinray::accuracy {

using RefVec = reference::Vec3<double>;
using RefHit = reference::Hit<double>;
using RefRay = reference::Ray<double>;

// A first hit in double, whichever tracer found it along its own primary ray.
struct FirstHit {
    int leaf = -1;
    double t = 0;
    RefVec point;
    RefVec normal;
    bool entering = false;
    int part = -1;  // on an instance of a solid shape, the shape's primitive
};

// A tracer's first hit along its primary ray through pixel (x, y) of a width × height image.
using FirstHitOf = std::function<std::optional<FirstHit>(int x, int y)>;

FirstHitOf first_hits_of(const reference::Tracer<double>& tracer, int width, int height);
FirstHitOf first_hits_of(const reference::Tracer<float>& tracer, int width, int height);
FirstHitOf first_hits_of(const sse::Tracer& tracer, int width, int height);
FirstHitOf first_hits_of(const tracing::AnyTracer& tracer, int width, int height);

// Every pixel's first hit, row by row: computed once, compared with many tracers.
std::vector<std::optional<FirstHit>> all_first_hits(const FirstHitOf& tracer, int width, int height);

double angle_between(RefVec a, RefVec b);  // radians

// The largest coordinate of the camera and the primitives: the scale S of the float bound ε·(S + t).
double largest_coordinate(const scene::Scene& scene);

// The reference's ray through image-plane position (px, py) in pixels (px = x + 0.5 is a pixel centre).
RefRay reference_ray_at(const scene::Scene& scene, double px, double py, int width, int height);

// A ray is in the silhouette/seam band when rays shifted by `band_pixels` of a pixel on the image plane
// see a different primitive, a hit where it misses (or the reverse), or a normal turned by more than
// `normal_bound_radians`: there a change of float rounding legitimately changes the answer.
constexpr double band_pixels = 1e-3;
constexpr double normal_bound_radians = 1e-3;
bool in_silhouette_band(const reference::Tracer<double>& reference, const scene::Scene& scene, int x, int y, int width,
                        int height, const std::optional<RefHit>& centre);

// On a mesh, a ray is in a shared edge's band when rays shifted by `band_pixels` meet another triangle (or
// none): there a change of float rounding may hand the ray to the neighbour across the edge.
bool in_triangle_band(const reference::Tracer<double>& reference, const scene::Scene& scene, int x, int y, int width,
                      int height, const RefHit& centre);

// Primary rays of a tracer against reference<double>: where both hit the same object, t's relative
// error |t − t_ref|/t_ref and the angle between the normals; elsewhere, disagreements counted.
struct RayAccuracy {
    long rays = 0;
    long hit_miss_disagreements = 0;  // one hits, the other misses
    long other_object = 0;            // both hit, different objects
    double t_relative_p50 = 0, t_relative_p999 = 0, t_relative_max = 0;
    double normal_angle_max_degrees = 0;

    double per_million(long count) const {
        return rays == 0 ? 0 : 1e6 * static_cast<double>(count) / static_cast<double>(rays);
    }
};

RayAccuracy measure_rays(const std::vector<std::optional<FirstHit>>& expected, const FirstHitOf& actual, int width,
                         int height);

}  // namespace twinray::accuracy
