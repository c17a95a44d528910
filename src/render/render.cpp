#include "render/render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <ctime>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace twinray {

std::string accel_name(Accel accel) {
    switch (accel) {
        case Accel::none: return "none";
        case Accel::bvh: return "bvh";
        case Accel::automatic: break;
    }
    return "auto";
}

double process_cpu_seconds() {
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

int resolve_thread_count(int requested) {
    if (requested > 0) {
        return requested;
    }
    return std::max(1u, std::thread::hardware_concurrency());
}

// The calling thread is one of the workers (one thread fewer to start, which matters for renders of a
// few milliseconds), and it alone reports progress, between its items.
int parallel_for(int count, int threads, const std::function<void(int item, int worker)>& work,
                 const std::function<void(double fraction_done)>& progress, const std::atomic<bool>* cancel) {
    std::atomic<int> next_item{0};
    std::atomic<int> items_done{0};
    std::mutex failure_mutex;
    std::exception_ptr failure;
    auto last_report = std::chrono::steady_clock::now();

    auto worker = [&](int index) {
        try {
            for (int item = next_item++; item < count; item = next_item++) {
                // Relaxed is enough: the flag carries no data, and stopping one item later is harmless.
                if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) {
                    throw RenderCancelled();
                }
                work(item, index);
                ++items_done;
                if (index == 0 && progress &&
                    std::chrono::steady_clock::now() - last_report > std::chrono::milliseconds(100)) {
                    last_report = std::chrono::steady_clock::now();
                    progress(static_cast<double>(items_done) / count);
                }
            }
        } catch (...) {
            std::lock_guard lock(failure_mutex);
            failure = std::current_exception();
            next_item = count;
        }
    };

    int worker_count = std::min(resolve_thread_count(threads), std::max(count, 1));
    {
        std::vector<std::jthread> helpers;
        for (int i = 1; i < worker_count; ++i) {
            helpers.emplace_back(worker, i);
        }
        worker(0);
    }
    if (failure) {
        std::rethrow_exception(failure);
    }
    return worker_count;
}

}  // namespace twinray
