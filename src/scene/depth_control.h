// Adaptive depth control: which secondary rays are worth tracing, and the per-pixel ray budget that bounds
// the work of every legal scene (docs/reference-tracer.md, "Adaptive depth control", derives the bounds).
//
// Both tracers call this, so both drop the same rays: every decision is made here, in double, from the
// scene's own coefficients, whatever the precision of the tracer that asks. Only a difference in the ray
// trees themselves (another object hit, total internal reflection decided otherwise) can make them differ.
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace twinray::scene {

// What one pixel's ray tree has traced and left out so far.
struct PixelLedger {
    std::uint32_t traced = 0;   // primary and secondary rays (shadow rays are bounded per hit, not counted)
    std::uint32_t dropped = 0;  // secondary rays not traced, by the cutoff or for lack of budget
    double dropped_bound = 0;   // Σ weight · radiance_bound over those: the most they could have added
    bool over_budget = false;   // a ray was left out for lack of budget, so dropped_bound may exceed the tolerance
};

// A ray's place in its pixel's tree: the product of the coefficients on its path from the camera, and how
// many rays (itself included) its subtree may trace.
struct RayShare {
    double weight = 1;
    int allowance = 0;
};

enum class DropReason { traced, cutoff, budget };

struct SecondaryCoefficients {
    double reflection = 0;
    double transmission = 0;
};

class DepthControl {
public:
    // Primary and secondary rays one pixel may trace. With shadow rays that is at most
    // ray_budget · (1 + lights) rays per pixel, each tested against every object, whatever the scene.
    static constexpr int ray_budget = 1024;
    // What the proven cutoff lets a pixel lose, per colour channel: just under half an 8-bit level, so a PNG
    // value moves by at most one level. The 0.01/255 left over covers float rounding in the sums that
    // would have held the dropped terms.
    static constexpr double pixel_tolerance = 0.49 / 255;

    explicit DepthControl(const Scene& scene);

    // The most any ray at `depth` (1 for primary rays) can return in one colour channel, its subtree
    // included; +∞ when the scene's transmissions make shadow rays unbounded.
    double radiance_bound(int depth) const { return radiance_bound_[static_cast<std::size_t>(depth)]; }

    // The primary ray's share: weight 1, the whole budget.
    static RayShare primary() { return {1.0, ray_budget}; }
    // The children of a hit of `material` with share `parent`, in the order the tracers trace them. The
    // refracted ray gets the rays its parent leaves in proportion to its coefficient; the reflected ray gets
    // what the refracted subtree did not use. `total_internal` moves the transmission onto the reflection.
    RayShare refracted(const RayShare& parent, int material) const;
    RayShare reflected(const RayShare& parent, int material, bool total_internal,
                       std::uint32_t used_by_refracted) const;

    // Whether a child ray with `share` at `depth` is traced. If not, the ledger is charged with it.
    DropReason decide(const RayShare& share, int depth, PixelLedger& ledger) const;

    // The weight below which POV-Ray should stop a ray (its adc_bailout) to judge the rays we trace: the
    // scene's min_weight; with the proven cutoff, the weight below which a single secondary ray cannot move
    // a pixel by pixel_tolerance (0 when nothing is provably negligible).
    double bailout_weight() const;

private:
    std::vector<SecondaryCoefficients> coefficients_;  // by material
    std::vector<double> radiance_bound_;               // by depth, 1..max_depth + 1
    std::optional<double> min_weight_;
    int max_depth_;
};

}  // namespace twinray::scene
