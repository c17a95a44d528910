// The watertightness suite (docs/conformance.md, "Watertight meshes"): rays that must cross exactly one
// triangle, aimed at shared edges and vertices (through a point computed on them in double, so each passes
// within an ulp of it) and at random points, judged by counting the triangles a tracer reports along each.
// None is a miss (the ray slipped through), two or more a double hit. Three families, each at every distance
// from the origin and every size:
// - sphere: a closed tessellated sphere, rays from its centre (inside) out through its vertices, edge
//   midpoints and random points on edges and faces (as Embree's `verify`, but judged ray by ray);
// - fan: a closed fan of triangles around one vertex in a random plane, rays from above it at the centre
//   vertex, the spokes' midpoints and random points on the spokes (Vulkan's closedFan);
// - split square: a square split again and again at random interior points (Vulkan's watertightness
//   cases), rays straight down at random points and at its inner edges and vertices;
// - grid: an axis-aligned grid of split squares on a binary grid, rays straight down exactly onto its edges
//   and vertices (every edge function there exactly 0 in every tracer: the tie rule alone decides).
#pragma once

#include "scene/scene.h"
#include "sse/tracer.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace twinray::accuracy {

// A ray that must cross exactly one triangle of the case's mesh within `length` of its origin.
struct WatertightProbe {
    scene::Vec3 origin;
    scene::Vec3 direction;  // unit, in double
    double length = 0;
};

struct WatertightCase {
    std::string family;   // "sphere", "fan", "split square"
    double distance = 0;  // of the mesh from the world's origin
    double size = 0;      // its radius or half-width
    scene::Scene scene;   // the mesh alone, the camera at its centre (where the SSE tracer re-bases)
    std::vector<WatertightProbe> probes;
};

// 1 to 1e7 and 1e-4 to 1e4, the ranges the suite must hold at.
std::vector<double> watertight_distances();
std::vector<double> watertight_sizes();
std::vector<std::string> watertight_families();

// `probes` rays (at least a few hundred per family, a third aimed at vertices, a third at edges), the same for
// the same arguments on any machine (seeded from them).
WatertightCase make_watertight_case(const std::string& family, double distance, double size, int probes);

struct WatertightTally {
    std::uint64_t rays = 0;
    std::uint64_t misses = 0;       // crossed no triangle
    std::uint64_t double_hits = 0;  // crossed two or more
};

// How many triangles a tracer reports along the probe.
using CrossingCounter = std::function<int(const WatertightProbe&)>;

// The oracle's count (reference<double>) and the SSE tracer's with `precision`, each tracer built once for
// the scene and kept by the counter.
CrossingCounter oracle_crossings(const scene::Scene& scene);
CrossingCounter sse_crossings(const scene::Scene& scene, const sse::Precision& precision);

WatertightTally count_watertightness(const WatertightCase& watertight, const CrossingCounter& crossings);

}  // namespace twinray::accuracy
