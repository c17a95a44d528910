// `twinray bench --scaling`'s memory floor (docs/performance.md, "The floor of this machine"): the caches the
// kernel reports and the time of a load that misses each of them, one at a time (a walk's chain of dependent
// node fetches) and with many in flight (rays whose walks overlap), so that a time per ray can be set against
// what its cache lines cost at best.
#include "cli/bench_run.h"
#include "render/large_array.h"
#include "scene/portable_random.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

namespace twinray::cli::bench {
namespace {

constexpr std::size_t line_bytes = 64;

// One cache line: the index of the next line of the chase, and padding so that each load is a line of its own.
struct alignas(line_bytes) Line {
    std::uint64_t next;
    std::uint64_t padding[7];
};

struct Cache {
    int level = 0;
    std::size_t bytes = 0;
};

// The data and unified caches of CPU 0 in /sys/devices/system/cpu/cpu0/cache (what lscpu reads); none where the
// folder is missing.
std::vector<Cache> caches_in_sys() {
    std::vector<Cache> caches;
    for (int index = 0;; ++index) {
        const std::string folder = "/sys/devices/system/cpu/cpu0/cache/index" + std::to_string(index) + "/";
        std::ifstream level_file(folder + "level"), type_file(folder + "type"), size_file(folder + "size");
        if (!level_file || !type_file || !size_file) {
            break;
        }
        Cache cache;
        std::string type, size;
        level_file >> cache.level;
        type_file >> type;
        size_file >> size;
        if (type == "Instruction" || size.empty()) {
            continue;
        }
        const char unit = size.back();
        cache.bytes = std::stoull(size) * (unit == 'K' ? 1024u : unit == 'M' ? 1024u * 1024u : 1u);
        caches.push_back(cache);
    }
    return caches;
}

// The data and unified caches of CPU 0, as /sys/devices/system/cpu/cpu0/cache gives them (what lscpu reads;
// glibc's sysconf reports 384 MB of L3 on one VM here, lscpu 32 MiB). Some VMs here have no such folder: then
// L1 and L2 as sysconf gives them, and no L3, whose sysconf size is not to be trusted (508 MB on another VM); the
// DRAM row's buffer is large enough either way.
std::vector<Cache> data_caches() {
    std::vector<Cache> caches = caches_in_sys();
    if (!caches.empty()) {
        return caches;
    }
    const long level1 = sysconf(_SC_LEVEL1_DCACHE_SIZE), level2 = sysconf(_SC_LEVEL2_CACHE_SIZE);
    if (level1 > 0) {
        caches.push_back({1, static_cast<std::size_t>(level1)});
    }
    if (level2 > 0) {
        caches.push_back({2, static_cast<std::size_t>(level2)});
    }
    return caches;
}

// Lines in one random cycle (Sattolo's shuffle over SplitMix64, the project's seeded portable generator), on
// 2 MB pages as the tracers' large arrays are, so that a miss pays DRAM and not a page walk as well.
class Chase {
public:
    explicit Chase(std::size_t bytes) : lines_(bytes / line_bytes) {
        const std::size_t count = lines_.size();
        std::vector<std::uint64_t> order(count);
        for (std::size_t i = 0; i < count; ++i) {
            order[i] = i;
        }
        SplitMix64 random(2026);
        for (std::size_t i = count - 1; i > 0; --i) {
            std::swap(order[i], order[random.next() % i]);
        }
        for (std::size_t i = 0; i < count; ++i) {
            lines_[order[i]].next = order[(i + 1) % count];
        }
    }

    // Nanoseconds per load over `loads` loads in Chains independent chains, interleaved (a chain's loads wait for
    // each other, the chains' do not), or over those done within `budget_seconds`, whichever comes first: under a
    // sanitizer a load from DRAM took 4.5 µs, and two million of them each run of the bench's test.
    template <int Chains>
    double ns_per_load(std::size_t loads, double budget_seconds) const {
        std::array<std::uint64_t, Chains> at{};
        for (int chain = 0; chain < Chains; ++chain) {
            at[static_cast<std::size_t>(chain)] = static_cast<std::uint64_t>(chain) * (lines_.size() / Chains);
        }
        constexpr std::size_t steps_between_clocks = 1024;
        const std::size_t steps = loads / Chains;
        std::size_t step = 0;
        const auto start = std::chrono::steady_clock::now();
        double seconds = 0;
        while (step < steps && seconds < budget_seconds) {
            for (const std::size_t end = std::min(steps, step + steps_between_clocks); step < end; ++step) {
                for (std::uint64_t& position : at) {
                    position = lines_[position].next;
                }
            }
            seconds = seconds_since(start);
        }
        std::uint64_t sum = 0;
        for (std::uint64_t position : at) {
            sum += position;
        }
        sink_ = sum;  // keeps the chase from being optimised away
        return seconds * 1e9 / static_cast<double>(step * Chains);
    }

private:
    LargeArray<Line> lines_;
    mutable volatile std::uint64_t sink_ = 0;
};

// Loads per measurement: 0.1–0.7 s where each misses to DRAM (50–320 ns here), and at most
// `seconds_per_measure`.
constexpr std::size_t loads_per_measure = std::size_t{1} << 21;
constexpr double seconds_per_measure = 0.5;
// Misses in flight at once in the overlapped chase: above the line-fill buffers of any core of today (10–24).
constexpr int chains_in_flight = 32;

std::string size_text(std::size_t bytes) {
    return bytes >= (std::size_t{1} << 20) ? std::to_string(bytes >> 20) + " MiB"
                                           : std::to_string(bytes >> 10) + " KiB";
}

// "L2 (1 MiB)"
std::string cache_name(const Cache& cache) {
    return "L" + std::to_string(cache.level) + " (" + size_text(cache.bytes) + ")";
}

}  // namespace

void bench_memory_floor(int runs, Report& report) {
    const std::vector<Cache> caches = data_caches();
    std::vector<std::pair<std::string, std::size_t>> buffers;  // what a row measures, its chase's bytes
    std::size_t largest = 0;
    for (const Cache& cache : caches) {
        // Half a level: its loads hit it and miss the level below.
        buffers.push_back({cache_name(cache), cache.bytes / 2});
        largest = std::max(largest, cache.bytes);
    }
    if (!caches.empty()) {
        // An eighth of the last level too: a VM's share of a shared last level can be far below its size.
        buffers.insert(buffers.end() - 1, {cache_name(caches.back()), caches.back().bytes / 8});
    }
    // Sixteen times the last level: a load hits a cache one time in sixteen at most.
    const std::size_t dram_bytes = std::max<std::size_t>(16 * largest, std::size_t{256} << 20);
    buffers.push_back({"DRAM", dram_bytes});
    double overlapped_ns = 0;  // the last row's: DRAM's
    for (const auto& [what, bytes] : buffers) {
        Chase chase(bytes);
        chase.ns_per_load<1>(loads_per_measure / 4, seconds_per_measure / 4);  // first touch and warm caches
        std::vector<double> dependent, overlapped;
        for (int run = 0; run < runs; ++run) {
            dependent.push_back(chase.ns_per_load<1>(loads_per_measure, seconds_per_measure));
            overlapped.push_back(chase.ns_per_load<chains_in_flight>(loads_per_measure, seconds_per_measure));
        }
        overlapped_ns = median(overlapped);
        report.scaling_floor.add_row(
            {what, size_text(bytes), cell("%.2f", median(dependent)), cell("%.2f", overlapped_ns)});
    }
    // The honest floor of a primary ray at a million primitives: 2 to 5 new lines whose misses overlap.
    report.scaling_floor.add_row({"floor of a primary ray: 2–5 new lines from DRAM in flight together", "", "",
                                  cell("%.0f", 2 * overlapped_ns) + "–" + cell("%.0f", 5 * overlapped_ns)});
}

}  // namespace twinray::cli::bench
