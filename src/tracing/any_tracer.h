// One interface over every tracer twinray judges, below the judges: reference<double> (the oracle),
// reference<float>, the SSE tracer, and a tracer behind the tracer ABI whose hits reference<double> shades
// (plugin/plugin_intersector.h). Attribution, the probe, diff, bench, render and the numerics hold an AnyTracer and
// never know which; the per-ray conformance judges hold plugin::JudgedTracer, the ABI's view of the same tracers.
#pragma once

#include "render/ray_tree.h"
#include "render/render.h"
#include "scene/scene.h"
#include "sse/tracer.h"

#include <memory>
#include <string>
#include <vector>

namespace twinray::tracing {

using Vec3d = scene::Vec3;

// A first hit in double, whatever the tracer's precision (a float's widened exactly).
struct FirstHit {
    bool hit = false;
    int leaf = -1;
    double t = 0;
    Vec3d point{};
    Vec3d normal{};  // unit, facing the ray
    int triangle = -1;
    bool entering = false;  // the ray enters the object's inside there
    int part = -1;          // on an instance of a solid shape, the shape's primitive
};

class AnyTracer {
public:
    virtual ~AnyTracer() = default;
    // "reference<double>", "sse (float, SSE4.1)", "plugin NAME VERSION (shaded by reference<double>)", ...
    virtual std::string description() const = 0;
    // Of the arithmetic its hits are found in.
    virtual double unit_roundoff() const = 0;
    // The ray is rounded to the tracer's precision on the way in (a float tracer's direction, normalised in
    // double, rounded to float; the SSE tracer takes its origin in double).
    virtual FirstHit intersect(const Vec3d& origin, const Vec3d& direction) const = 0;
    virtual FirstHit primary_hit(int x, int y, int width, int height) const = 0;
    // The tree of pixel (x, y)'s primary ray, or of the ray given by hand.
    virtual void trace_primary(int x, int y, int width, int height, RayTree& tree) const = 0;
    virtual void trace_ray(const Vec3d& origin, const Vec3d& direction, RayTree& tree) const = 0;
    // The whole image, with options.accel as the tracer was made with.
    virtual RenderResult render(const RenderOptions& options) const = 0;
};

// The tracers built in; beside them "plugin:PATH" names a tracer behind the tracer ABI (docs/plugins.md).
const std::vector<std::string>& tracer_names();
bool is_plugin(const std::string& name);
std::string tracer_summary(const std::string& name);  // one phrase, for --help
// Empty when the tracer can run on this machine, else why not (the SSE tracer needs SSE4.1).
std::string tracer_unavailable_reason(const std::string& name);

// `scene` must outlive the tracer where render() is called; the rest reads only what the tracer built. `precision`
// applies to the SSE tracer only: knobs asked of another are refused (std::invalid_argument), as is an unknown name. A
// plug-in throws plugin::UnsupportedKind, plugin::PluginUnusable or, later, plugin::PluginFault.
std::unique_ptr<AnyTracer> make_tracer(const std::string& name, const scene::Scene& scene,
                                       const sse::Precision& precision = {}, Accel accel = Accel::automatic);

// Empty when `precision` can be used with the tracer, else why not.
std::string precision_problem(const std::string& name, const sse::Precision& precision);

}  // namespace twinray::tracing
