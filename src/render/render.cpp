#include "render/render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace twinray {

int resolve_thread_count(int requested) {
    if (requested > 0) {
        return requested;
    }
    return std::max(1u, std::thread::hardware_concurrency());
}

std::uint64_t parallel_for(int count, int threads, const std::function<std::uint64_t(int item)>& work,
                           const std::function<void(double fraction_done)>& progress) {
    std::atomic<int> next_item{0};
    std::atomic<int> items_done{0};
    std::atomic<std::uint64_t> total{0};
    std::mutex mutex;
    std::condition_variable finished;
    int workers_running = std::min(resolve_thread_count(threads), std::max(count, 1));
    std::exception_ptr failure;

    auto worker = [&] {
        try {
            std::uint64_t sum = 0;
            for (int item = next_item++; item < count; item = next_item++) {
                sum += work(item);
                ++items_done;
            }
            total += sum;
        } catch (...) {
            std::lock_guard lock(mutex);
            failure = std::current_exception();
            next_item = count;
        }
        std::lock_guard lock(mutex);
        --workers_running;
        finished.notify_all();
    };

    std::vector<std::jthread> pool;
    int worker_count = workers_running;
    for (int i = 0; i < worker_count; ++i) {
        pool.emplace_back(worker);
    }
    {
        std::unique_lock lock(mutex);
        while (!finished.wait_for(lock, std::chrono::milliseconds(100), [&] { return workers_running == 0; })) {
            if (progress) {
                lock.unlock();
                progress(static_cast<double>(items_done) / count);
                lock.lock();
            }
        }
    }
    pool.clear();
    if (failure) {
        std::rethrow_exception(failure);
    }
    return total;
}

}  // namespace twinray
