// Numerical stability at the extremes (docs/numerics.md): how far each tracer's hit points lie from the
// true surface when a scene is scaled and moved away from the origin, and whether rays leaving a surface
// re-hit it by error. `twinray numerics` prints these figures; the extremes tests assert on the same code.
#pragma once

#include "render/ray_tree.h"
#include "scene/scene.h"
#include "tracing/any_tracer.h"

#include <memory>
#include <string>
#include <vector>

namespace twinray::numerics {

enum class TracerKind { reference_double, reference_float, sse };

const char* tracer_name(TracerKind kind);

// The measurements hold the tracers by the interface every judge holds (tracing/any_tracer.h).
using tracing::AnyTracer;
using tracing::FirstHit;
using Vec3d = tracing::Vec3d;

// tracing::make_tracer of the tracer tracer_name(kind) names. For TracerKind::sse the CPU must support SSE4.1.
std::unique_ptr<AnyTracer> make_tracer(const scene::Scene& scene, TracerKind kind);

// The scene scaled by `scale` about the origin, then moved by `shift` along every axis: camera, lights
// and every primitive with it, so the image is the same up to rounding. `camera_distance` moves the eye
// that many times farther from the point it looks at and narrows the field of view to frame the same
// image: rays then travel far (t ≫ |p|) to surfaces near the origin.
scene::Scene transformed(const scene::Scene& scene, double scale, double shift, double camera_distance = 1);

// The cases of the error-against-scale table: uniform scale 1e-4 … 1e6 at the origin, then an object
// of size 1 moved 10 … 1e6 away from it, then seen from 100 … 10 000 times farther away.
struct ScaleCase {
    double scale;
    double shift;
    double camera_distance;
};
std::vector<ScaleCase> scale_cases();

// How far the showcase is moved to find where float's error outgrows a pixel: 1, 2, 5 × 10^k up to 1e7.
std::vector<double> footprint_shifts();

// The scene with every number rounded to single precision: the geometry the float tracers work on.
scene::Scene rounded_to_float(const scene::Scene& scene);

// The geometry a tracer holds, in world coordinates: the scene as given (reference), rounded to float
// (reference-float), rounded to float relative to sse::origin_of and moved back in double (sse).
scene::Scene held_geometry(const scene::Scene& scene, TracerKind kind);

// The primitive of each leaf (Scene::leaf_paths order).
std::vector<const scene::Object*> leaf_objects(const scene::Scene& scene);

// Distance from `point` to the surface of `primitive` as the scene gives it (double parameters),
// computed in long double: the truth a hit point is measured against.
long double distance_to_surface(const scene::Object& primitive, const Vec3d& point);

// The closed interval of the line origin + t·direction inside `primitive` (enter ≤ exit, either may be
// infinite for a plane), in long double: the truth grazing rays are judged against. `valid` is false
// where the line misses. Same boundary rule as the tracers: a line within a face is not inside.
struct ExactSpan {
    bool valid = false;
    long double enter = 0, exit = 0;
};
ExactSpan exact_span(const scene::Object& primitive, const Vec3d& origin, const Vec3d& direction);

// The unit normal line of the primitive's surface nearest `point` (its sign is not meaningful).
Vec3d exact_normal(const scene::Object& primitive, const Vec3d& point);

// What one tracer does with a grid of primary rays and every ray they spawn.
struct Measurement {
    int rays = 0;          // primary rays
    int hits = 0;          // primary rays that hit
    double max_error = 0;  // largest distance of a primary hit point from its true surface, / size
    int secondary = 0;     // secondary and shadow rays that left a surface
    int acne = 0;          // of them, re-hit the primitive they left well before the exact line does
    int leaks = 0;         // refracted rays into a solid that found no surface to leave it by
};

// `size` is the length the errors are measured in (the object's size); `grid` × `grid` primary rays
// through the centres of a grid × grid image. Hit points are measured against the scene as given; acne
// against the geometry the tracer holds (held_geometry), since a float primitive is not where the double
// one is. For TracerKind::sse the CPU must support SSE4.1.
Measurement measure(const scene::Scene& scene, TracerKind kind, int grid, double size);

// Per primitive type, the largest ratio of a primary hit point's distance from its true surface to the
// footprint of the pixel it was traced through (the pixel's width at the hit's distance), over every
// pixel of a `width`-wide image (rows in proportion).
struct FootprintRatio {
    std::string primitive;  // plane, sphere, cylinder, box
    double max_ratio = 0;
};
std::vector<FootprintRatio> footprint_ratios(const scene::Scene& scene, TracerKind kind, int width);

}  // namespace twinray::numerics
