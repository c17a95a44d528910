// The cost of a ray through the tracer ABI (docs/plugins.md): the C example's nearest hits on a one-sphere scene,
// where its own arithmetic is a few dozen operations, in batches of 1 to 4096 through plugin::BuiltScene (the
// checks included), beside the reference's own intersect of the same rays. Figures printed, never a test.
#include "plugin/plugin.h"
#include "reference/tracer.h"
#include "scene/sphere_field.h"

#include <benchmark/benchmark.h>

#include <limits>
#include <vector>

namespace {

using namespace twinray;

const scene::Scene& one_sphere() {
    static const scene::Scene scene = scene::sphere_field(1);
    return scene;
}

std::vector<reference::Ray<double>> primary_rays(std::size_t count) {
    const reference::Tracer<double> oracle(one_sphere());
    std::vector<reference::Ray<double>> rays;
    for (std::size_t i = 0; i < count; ++i) {
        rays.push_back(oracle.primary_ray(static_cast<int>(i % 64), static_cast<int>(i / 64 % 64), 64, 64));
    }
    return rays;
}

void AbiNearestHits(benchmark::State& state) {
    static const plugin::Plugin example(TWINRAY_EXAMPLE_TRACER);
    const plugin::BuiltScene built(example, one_sphere());
    const auto batch = static_cast<std::size_t>(state.range(0));
    std::vector<twinray_ray> rays;
    for (const reference::Ray<double>& ray : primary_rays(batch)) {
        rays.push_back({{ray.origin.x, ray.origin.y, ray.origin.z},
                        {ray.direction.x, ray.direction.y, ray.direction.z},
                        0,
                        std::numeric_limits<double>::infinity()});
    }
    std::vector<plugin::Hit> hits(batch);
    for (auto _ : state) {
        built.intersect(rays, hits);
        benchmark::DoNotOptimize(hits.data());
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * state.range(0));
}
BENCHMARK(AbiNearestHits)->Arg(1)->Arg(16)->Arg(256)->Arg(4096);

void ReferenceNearestHits(benchmark::State& state) {
    const reference::Tracer<double> oracle(one_sphere());
    const std::vector<reference::Ray<double>> rays = primary_rays(4096);
    for (auto _ : state) {
        for (const reference::Ray<double>& ray : rays) {
            benchmark::DoNotOptimize(oracle.intersect(ray));
        }
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * 4096);
}
BENCHMARK(ReferenceNearestHits);

}  // namespace

BENCHMARK_MAIN();
