// Why a pixel differs between the tracers (docs/conformance.md, "Why a pixel differs"): the first place
// their ray trees part, judged against the band float rounding allows there, propagated down the tree.
//
// Each class is a decision the SSE tracer's inputs legitimately tipped: at the ray where the trees part,
// the SSE tracer's ray is within the band of the reference's, and the reference itself, replayed with the
// SSE tracer's inputs (or inputs within the band), decides as the SSE tracer did. Anything else is
// unexplained: a difference float rounding cannot account for.
#pragma once

#include "image/image.h"
#include "reference/tracer.h"
#include "render/ray_tree.h"
#include "scene/scene.h"
#include "tracing/any_tracer.h"

#include <array>
#include <string>
#include <vector>

namespace twinray::accuracy {

enum class Cause {
    silhouette,   // hit or miss, another object, entering or leaving: a ray grazing an edge, silhouette, CSG seam
    shadow,       // a light blocked or facing away in one tree only: a grazing light or an occluder's silhouette
    refraction,   // refracted in one tree, totally reflected in the other: the critical angle
    drift,        // the same decisions; numbers or colours apart by what the propagated band allows
    unexplained,  // none of the above
};
constexpr int cause_count = 5;
const char* cause_name(Cause cause);

struct PixelCause {
    Cause cause = Cause::drift;
    std::string what;      // the first divergence (render/ray_tree.h), or empty where the trees agree
    int depth = 0;         // of the ray where the trees part
    double deviation = 0;  // the SSE ray's direction off the reference's there (radians)
    double band = 0;       // the band's angle there
};

// Why the trees `expected` (reference<double>) and `actual` (sse) of one ray differ; `reference` replays.
PixelCause attribute(const scene::Scene& scene, const reference::Tracer<double>& reference, const RayTree& expected,
                     const RayTree& actual);

struct AttributedPixel {
    int x = 0, y = 0;
    double error = 0;  // largest channel difference
    PixelCause cause;
};

// Every pixel of the two renders differing by more than `threshold` in some channel, attributed.
constexpr std::size_t max_unexplained_listed = 1000;
struct Attribution {
    std::array<long, cause_count> counts{};
    std::vector<AttributedPixel> unexplained;  // the largest errors first, at most max_unexplained_listed
};
// `actual` is the tracer that rendered `actual_image` (the SSE tracer, or a plug-in's hits shaded by the reference):
// its ray trees are held against reference<double>'s.
Attribution attribute_pixels(const scene::Scene& scene, const Image& reference_image, const Image& actual_image,
                             const tracing::AnyTracer& actual, double threshold);

// The verdict rule (docs/conformance.md, "Why a pixel differs"): a scene fails when any pixel is unexplained,
// or when the pixels of an explained class exceed its budget, a share of the image's pixels. Drift has no
// budget of its own: the image thresholds bound it.
struct ClassBudgets {
    double silhouette_percent = 0.5;
    double shadow_percent = 0.5;
    double refraction_percent = 0.5;
};
// Empty when the scene passes the rule, else why it fails.
std::string attribution_failure(const Attribution& attribution, long pixel_count, const ClassBudgets& budgets = {});

}  // namespace twinray::accuracy
