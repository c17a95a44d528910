// The 2009 thesis's table 3.1 on this machine: one 3-vector dot product by SSE4.1 dpps, SSE3 hadd, SSE
// shuffles, scalar code and x87, plus the structure-of-arrays way the SSE tracer uses (four dot
// products per three multiplies and two adds). Thesis (Core 2 Duo T9300, MSVC 2008, same units):
// dpps 2714, hadd 4758, shuffles 4899, x87 6318. Each variant runs over the same 4096 pairs of vectors
// (L1-resident), one result at a time through benchmark::DoNotOptimize, so the compiler can neither
// drop the work nor fuse iterations into wider vector code; the table at the end gives each variant's
// time per dot product and its ratio to scalar code (the median over --benchmark_repetitions=N when
// given). Built with -msse4.1; not a test.
#include "scene/portable_random.h"

#include <benchmark/benchmark.h>
#include <smmintrin.h>

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace {

constexpr int count = 4096;

struct alignas(16) Vector4 {
    float x, y, z, w;
};

// Seeded, portable values in [-1, 1): the same inputs on every machine.
std::vector<Vector4> inputs(std::uint64_t seed) {
    std::vector<Vector4> vectors(count);
    twinray::SplitMix64 random(seed);
    for (Vector4& v : vectors) {
        v = {static_cast<float>(random.uniform(-1, 1)), static_cast<float>(random.uniform(-1, 1)),
             static_cast<float>(random.uniform(-1, 1)), 0.0f};
    }
    return vectors;
}

const std::vector<Vector4>& left() {
    static const std::vector<Vector4> vectors = inputs(1);
    return vectors;
}
const std::vector<Vector4>& right() {
    static const std::vector<Vector4> vectors = inputs(2);
    return vectors;
}

void dpps(benchmark::State& state) {
    const Vector4* a = left().data();
    const Vector4* b = right().data();
    for (auto _ : state) {
        for (int i = 0; i < count; ++i) {
            __m128 dot = _mm_dp_ps(_mm_load_ps(&a[i].x), _mm_load_ps(&b[i].x), 0x71);
            benchmark::DoNotOptimize(dot);
        }
    }
}

void hadd(benchmark::State& state) {
    const Vector4* a = left().data();
    const Vector4* b = right().data();
    for (auto _ : state) {
        for (int i = 0; i < count; ++i) {
            __m128 product = _mm_mul_ps(_mm_load_ps(&a[i].x), _mm_load_ps(&b[i].x));
            __m128 pairs = _mm_hadd_ps(product, product);
            __m128 dot = _mm_hadd_ps(pairs, pairs);
            benchmark::DoNotOptimize(dot);
        }
    }
}

void shuffles(benchmark::State& state) {
    const Vector4* a = left().data();
    const Vector4* b = right().data();
    for (auto _ : state) {
        for (int i = 0; i < count; ++i) {
            __m128 product = _mm_mul_ps(_mm_load_ps(&a[i].x), _mm_load_ps(&b[i].x));
            __m128 swapped = _mm_shuffle_ps(product, product, _MM_SHUFFLE(2, 3, 0, 1));
            __m128 pairs = _mm_add_ps(product, swapped);
            __m128 dot = _mm_add_ss(pairs, _mm_movehl_ps(swapped, pairs));
            benchmark::DoNotOptimize(dot);
        }
    }
}

void scalar(benchmark::State& state) {
    const Vector4* a = left().data();
    const Vector4* b = right().data();
    for (auto _ : state) {
        for (int i = 0; i < count; ++i) {
            float dot = a[i].x * b[i].x + a[i].y * b[i].y + a[i].z * b[i].z;
            benchmark::DoNotOptimize(dot);
        }
    }
}

// long double arithmetic is x87 code on x86-64: the thesis's scalar baseline (MSVC 2008, 32-bit).
void x87(benchmark::State& state) {
    const Vector4* a = left().data();
    const Vector4* b = right().data();
    for (auto _ : state) {
        for (int i = 0; i < count; ++i) {
            long double dot = static_cast<long double>(a[i].x) * b[i].x + static_cast<long double>(a[i].y) * b[i].y +
                              static_cast<long double>(a[i].z) * b[i].z;
            benchmark::DoNotOptimize(dot);
        }
    }
}

// The SSE tracer's way: the x, y, z of four vectors each in one register (transposed once, outside
// the loop, as the tracer's packets are built), four dot products per three multiplies and two adds.
void structure_of_arrays(benchmark::State& state) {
    static const std::vector<float> soa = [] {
        std::vector<float> lanes(6 * count);
        for (int i = 0; i < count; ++i) {
            int group = i / 4, lane = i % 4;
            const float ai[3] = {left()[i].x, left()[i].y, left()[i].z};
            const float bi[3] = {right()[i].x, right()[i].y, right()[i].z};
            for (int axis = 0; axis < 3; ++axis) {
                lanes[static_cast<std::size_t>(24 * group + 4 * axis + lane)] = ai[axis];
                lanes[static_cast<std::size_t>(24 * group + 12 + 4 * axis + lane)] = bi[axis];
            }
        }
        return lanes;
    }();
    const float* p = soa.data();
    for (auto _ : state) {
        for (int group = 0; group < count / 4; ++group) {
            const float* g = p + 24 * group;
            __m128 dot = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_load_ps(g), _mm_load_ps(g + 12)),
                                               _mm_mul_ps(_mm_load_ps(g + 4), _mm_load_ps(g + 16))),
                                    _mm_mul_ps(_mm_load_ps(g + 8), _mm_load_ps(g + 20)));
            benchmark::DoNotOptimize(dot);
        }
    }
}

BENCHMARK(dpps);
BENCHMARK(hadd);
BENCHMARK(shuffles);
BENCHMARK(scalar);
BENCHMARK(x87);
BENCHMARK(structure_of_arrays);

// Keeps each benchmark's CPU time per iteration for the table printed after the runs: CPU time, not
// wall time, because the machines we share run other work, and a descheduled thread's wall time grows.
class RecordingReporter : public benchmark::ConsoleReporter {
public:
    void ReportRuns(const std::vector<Run>& runs) override {
        // With --benchmark_repetitions, the median of the repetitions; else the one run.
        for (const Run& run : runs) {
            bool median = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
            bool single = run.run_type == Run::RT_Iteration && run.repetitions <= 1;
            if (!run.error_occurred && (median || single)) {
                nanoseconds_[run.run_name.function_name] = run.GetAdjustedCPUTime();
            }
        }
        ConsoleReporter::ReportRuns(runs);
    }
    const std::map<std::string, double>& nanoseconds() const { return nanoseconds_; }

private:
    std::map<std::string, double> nanoseconds_;
};

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) {
        return 1;
    }
    RecordingReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    const auto& times = reporter.nanoseconds();
    auto scalar_time = times.find("scalar");
    auto x87_time = times.find("x87");
    if (scalar_time == times.end() || x87_time == times.end()) {
        return 0;
    }
    const std::map<std::string, double> thesis = {{"dpps", 2714}, {"hadd", 4758}, {"shuffles", 4899}, {"x87", 6318}};
    std::printf("\n%-20s %12s %14s %12s %18s\n", "dot product", "ns per dot", "time / scalar", "time / x87",
                "thesis time / x87");
    for (const char* name : {"dpps", "hadd", "shuffles", "scalar", "x87", "structure_of_arrays"}) {
        auto found = times.find(name);
        if (found == times.end()) {
            continue;
        }
        double per_dot = found->second / count;
        auto thesis_time = thesis.find(name);
        std::string thesis_ratio = "";
        if (thesis_time != thesis.end()) {
            char text[32];
            std::snprintf(text, sizeof text, "%.2f", thesis_time->second / thesis.at("x87"));
            thesis_ratio = text;
        }
        std::printf("%-20s %12.3f %14.2f %12.2f %18s\n", name, per_dot, found->second / scalar_time->second,
                    found->second / x87_time->second, thesis_ratio.c_str());
    }
    benchmark::Shutdown();
    return 0;
}
