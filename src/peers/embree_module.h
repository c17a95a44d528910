// Embree 3 in a module of our own (libtwinray_embree.so), loaded with dlopen by the first EmbreePeer:
// linked to twinray, Embree and TBB were loaded and relocated at every start of every command, though
// only `twinray bench` uses them (docs/performance.md, "Whole process").
#pragma once

#include "peers/embree_peer.h"
#include "scene/scene.h"
#include "sse/tracer.h"

#include <vector>

namespace twinray::peers {

// What the module offers, returned by its one exported symbol, twinray_embree_functions. `create`
// builds Embree's scene of `scene` (no CSG) in `mode` on kernels of instruction set `isa` and keeps the
// primary rays of a width x height image, row by row; it throws std::runtime_error if Embree fails.
struct EmbreeFunctions {
    void* (*create)(const scene::Scene& scene, std::vector<sse::Ray> rays, int width, int height, EmbreeIsa isa,
                    EmbreeMode mode);
    void (*destroy)(void* state);
    FirstHitRun (*cast_single)(const void* state);
    FirstHitRun (*cast_packets)(const void* state, int lanes);
    double (*build_seconds)(const void* state);
};

}  // namespace twinray::peers

extern "C" const twinray::peers::EmbreeFunctions* twinray_embree_functions();
