// What every tracer's render() takes and gives, and the worker loop they share.
#pragma once

#include "image/image.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>

namespace twinray {

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
};

// Thrown by parallel_for (and so by every tracer's render) when RenderOptions::cancel became true.
class RenderCancelled : public std::runtime_error {
public:
    RenderCancelled() : std::runtime_error("render cancelled") {}
};

struct RenderResult {
    Image image;
    std::uint64_t rays = 0;  // primary, shadow, reflected and refracted rays traced
};

int resolve_thread_count(int requested);

// Runs work(item) for every item in [0, count) on `threads` threads, items handed out in order one at
// a time. Each item must write only its own output, which is what makes a render bit-identical for
// any thread count. Returns the sum of what the items return (their ray counts). If `cancel` becomes
// true, no new item is started, the items under way finish, and RenderCancelled is thrown.
std::uint64_t parallel_for(int count, int threads, const std::function<std::uint64_t(int item)>& work,
                           const std::function<void(double fraction_done)>& progress,
                           const std::atomic<bool>* cancel = nullptr);

}  // namespace twinray
