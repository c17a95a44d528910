// Embree 3 as a first-hit peer for `twinray bench` (built only when Embree is installed), each of our
// primitives in Embree's fastest form: spheres as its native point spheres, boxes as six native quads,
// planes as one large quad, cylinders (Embree has no capped cylinder) as user geometry whose callback
// runs the reference tracer's formula in float, each mesh as its native triangles; and the same primary
// rays as the SSE tracer (its camera, in float) cast one by one (rtcIntersect1) or as coherent packets
// of 4, 8 or 16 (rtcIntersect4/8/16).
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <memory>
#include <string>

namespace twinray::peers {

// Empty when Embree can hold the scene, else why not (CSG: Embree has no solids).
std::string embree_unsupported_reason(const scene::Scene& scene);

struct FirstHitRun {
    double seconds = 0;  // CPU time of the casts alone: rays are made before the clock starts
    std::uint64_t rays = 0;
    std::uint64_t hits = 0;
};

// Which of its kernels Embree runs: the widest the CPU has (AVX-512 here: Embree compiles one set per
// instruction set and picks at start-up), or its SSE4.2 ones, as narrow as the SSE tracer's SSE4.1 (SSE4.2
// adds string and CRC instructions, nothing a traversal uses).
enum class EmbreeIsa { widest, sse42 };

// How Embree builds its scene: its default, or with RTC_SCENE_FLAG_ROBUST, which its documentation gives as
// robust traversal and no optimisation that costs accuracy, against rays slipping through the edge two
// triangles share: what the SSE tracer's watertight triangle test rules out, so meshes are timed both ways.
enum class EmbreeMode { standard, robust };

class EmbreePeer {
public:
    // The scene at `width` (height by its aspect), on an Embree device of one thread running `isa`'s
    // kernels, built in `mode`. Throws std::runtime_error if Embree fails.
    EmbreePeer(const scene::Scene& scene, int width, EmbreeIsa isa = EmbreeIsa::widest,
               EmbreeMode mode = EmbreeMode::standard);
    ~EmbreePeer();
    EmbreePeer(const EmbreePeer&) = delete;
    EmbreePeer& operator=(const EmbreePeer&) = delete;

    FirstHitRun cast_single() const;  // rtcIntersect1 per ray
    // rtcIntersect4, 8 or 16 per tile of 2 × 2, 4 × 2 or 4 × 4 pixels, flagged coherent.
    FirstHitRun cast_packets(int lanes = 4) const;
    // CPU time of building Embree's scene (its geometries and BVH) on one thread, as the constructor did.
    double build_seconds() const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace twinray::peers
