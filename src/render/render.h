// What every tracer's render() takes and gives, and the worker loop they share.
#pragma once

#include "image/image.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace twinray {

// Whether a tracer finds hits through a bounding volume hierarchy or tests every object (`--accel`): the
// image is the same bit for bit, only the time differs. `automatic` builds one where the scene is large
// enough for it to pay, each tracer by its own measured crossover (docs/performance.md, "The BVH").
enum class Accel { automatic, none, bvh };
// "auto", "none" or "bvh", as --accel spells them.
std::string accel_name(Accel accel);

struct RenderOptions {
    int width = 0;    // 0: the scene's
    int height = 0;   // 0: the scene's
    int threads = 0;  // 0: all hardware threads
    // Called on the calling thread (itself one of the workers) about ten times a second, with the share done.
    std::function<void(double fraction_done)> progress;
    // When set, workers read it between items and the render stops once it is true: parallel_for then
    // throws RenderCancelled and no image is returned. The CLI points it at the flag its SIGINT handler
    // sets (Ctrl-C), so a cancelled render stops within one item per thread.
    const std::atomic<bool>* cancel = nullptr;
    Accel accel = Accel::automatic;  // BVH or brute force (above): the time changes, the image does not
};

// Thrown by parallel_for (and so by every tracer's render) when RenderOptions::cancel became true.
class RenderCancelled : public std::runtime_error {
public:
    RenderCancelled() : std::runtime_error("render cancelled") {}
};

// What a render, or one pixel's trace(), counted.
struct TraceTally {
    std::uint64_t rays = 0;                     // primary, shadow, reflected and refracted rays traced
    std::uint64_t dropped_rays = 0;             // secondary rays the depth control left out (scene/depth_control.h)
    std::uint64_t pixels_over_budget = 0;       // pixels whose ray budget ran out before their tree was done
    std::int64_t first_pixel_over_budget = -1;  // y·width + x of the first of them in row-major order; -1: none

    // One pixel's tree, as a tracer's trace() counted it.
    void add_pixel(std::uint64_t traced, std::uint64_t dropped, bool over_budget) {
        rays += traced;
        dropped_rays += dropped;
        pixels_over_budget += over_budget ? 1 : 0;
    }

    // The tally of the pixel at y·width + x.
    void add(TraceTally pixel, std::int64_t pixel_index) {
        if (pixel.pixels_over_budget > 0 && pixel.first_pixel_over_budget < 0) {
            pixel.first_pixel_over_budget = pixel_index;
        }
        *this += pixel;
    }

    TraceTally& operator+=(const TraceTally& other) {
        rays += other.rays;
        dropped_rays += other.dropped_rays;
        pixels_over_budget += other.pixels_over_budget;
        if (other.first_pixel_over_budget >= 0 &&
            (first_pixel_over_budget < 0 || other.first_pixel_over_budget < first_pixel_over_budget)) {
            first_pixel_over_budget = other.first_pixel_over_budget;
        }
        return *this;
    }
};

struct RenderResult {
    Image image;
    TraceTally tally;
    // Wall time of the pixel loop alone: what render() spends before it (building the tracer, compiling the
    // scene) is left out, so tracers are timed on tracing.
    double tracing_seconds = 0;
    // CPU time (user + system, every thread's) of the same loop: on a busy machine a one-thread figure that
    // does not count waiting for a core.
    double tracing_cpu_seconds = 0;
};

// CPU time (user + system) the process has used so far, every thread's.
double process_cpu_seconds();

int resolve_thread_count(int requested);

// Runs work(item, worker) for every item in [0, count) on `threads` threads, items handed out in order one
// at a time; `worker` (0 ≤ worker < the returned count) tells which thread runs it. Each item must write
// only its own output, which is what makes a render bit-identical for any thread count. If `cancel`
// becomes true, no new item is started, the items under way finish, and RenderCancelled is thrown.
int parallel_for(int count, int threads, const std::function<void(int item, int worker)>& work,
                 const std::function<void(double fraction_done)>& progress, const std::atomic<bool>* cancel = nullptr);

// parallel_for summing what the items return (tallies whose += does not depend on order).
template <typename Sum>
Sum parallel_sum(int count, int threads, const std::function<Sum(int item)>& work,
                 const std::function<void(double fraction_done)>& progress, const std::atomic<bool>* cancel = nullptr) {
    std::vector<Sum> by_worker(static_cast<std::size_t>(resolve_thread_count(threads)));
    int workers = parallel_for(
        count, threads, [&](int item, int worker) { by_worker[static_cast<std::size_t>(worker)] += work(item); },
        progress, cancel);
    Sum total{};
    for (int worker = 0; worker < workers; ++worker) {
        total += by_worker[static_cast<std::size_t>(worker)];
    }
    return total;
}

}  // namespace twinray
