// A sample of the watertightness suite (accuracy/watertight.h; `twinray watertight` runs the millions): every
// family at every distance and size, for the oracle and the exact SSE tracer, with no miss and no double hit
// allowed. Rays leaving a closed mesh from inside meet its back, and say so.
#include "accuracy/watertight.h"
#include "reference/tracer.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

namespace {

namespace accuracy = twinray::accuracy;
namespace reference = twinray::reference;
namespace sse = twinray::sse;

constexpr int probes_per_case = 1000;

struct Failures {
    std::ostringstream text;
    std::uint64_t rays = 0, misses = 0, double_hits = 0;

    void add(const accuracy::WatertightCase& watertight, const accuracy::WatertightTally& tally) {
        rays += tally.rays;
        misses += tally.misses;
        double_hits += tally.double_hits;
        if (tally.misses + tally.double_hits > 0) {
            text << "  " << watertight.family << " at distance " << watertight.distance << ", size " << watertight.size
                 << ": " << tally.misses << " misses, " << tally.double_hits << " double hits of " << tally.rays
                 << "\n";
        }
    }
};

// Every family at every distance and size.
const std::uint64_t rays_in_all = accuracy::watertight_families().size() * accuracy::watertight_distances().size() *
                                  accuracy::watertight_sizes().size() * probes_per_case;

template <typename Count>
Failures every_case(Count&& make_counter) {
    Failures failures;
    for (const std::string& family : accuracy::watertight_families()) {
        for (double distance : accuracy::watertight_distances()) {
            for (double size : accuracy::watertight_sizes()) {
                accuracy::WatertightCase watertight =
                    accuracy::make_watertight_case(family, distance, size, probes_per_case);
                failures.add(watertight, accuracy::count_watertightness(watertight, make_counter(watertight.scene)));
            }
        }
    }
    return failures;
}

TEST(Watertight, TheOracleNeitherMissesNorDoubleHitsAnyEdgeOrVertexAtAnyDistanceAndSize) {
    Failures failures = every_case(accuracy::oracle_crossings);
    EXPECT_EQ(failures.rays, rays_in_all);
    EXPECT_EQ(failures.misses, 0u) << failures.text.str();
    EXPECT_EQ(failures.double_hits, 0u) << failures.text.str();
}

TEST(Watertight, TheExactSseTracerNeitherMissesNorDoubleHitsAnyEdgeOrVertexAtAnyDistanceAndSize) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    Failures failures =
        every_case([](const twinray::scene::Scene& scene) { return accuracy::sse_crossings(scene, {}); });
    EXPECT_EQ(failures.rays, rays_in_all);
    EXPECT_EQ(failures.misses, 0u) << failures.text.str();
    EXPECT_EQ(failures.double_hits, 0u) << failures.text.str();
}

// From the sphere's centre every ray meets the back of a triangle (counter-clockwise seen from outside):
// the first hit leaves the solid, in both tracers.
TEST(Watertight, RaysFromInsideAClosedMeshLeaveThroughTheBackOfItsTriangles) {
    if (!sse::cpu_supports_sse41()) {
        GTEST_SKIP() << sse::missing_sse41_message();
    }
    accuracy::WatertightCase watertight = accuracy::make_watertight_case("sphere", 1e3, 1, probes_per_case);
    reference::Tracer<double> oracle(watertight.scene);
    sse::Tracer tracer(watertight.scene);
    int entering_oracle = 0, entering_sse = 0, missed = 0;
    for (const accuracy::WatertightProbe& probe : watertight.probes) {
        auto expected = oracle.intersect({probe.origin, probe.direction});
        auto hit = tracer.intersect({probe.origin, sse::Vec3(probe.direction)});
        missed += expected && hit ? 0 : 1;
        entering_oracle += expected && expected->entering ? 1 : 0;
        entering_sse += hit && hit->entering ? 1 : 0;
    }
    EXPECT_EQ(missed, 0);
    EXPECT_EQ(entering_oracle, 0) << "of " << watertight.probes.size() << " rays from inside";
    EXPECT_EQ(entering_sse, 0) << "of " << watertight.probes.size() << " rays from inside";
}

}  // namespace
