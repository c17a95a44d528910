// Properties of the SSE tracer that conformance does not show: its CPU check, 16-byte alignment of all
// SIMD data (the thesis's lesson, heap included), and no heap allocation while tracing.
#include "reference/tracer.h"
#include "scene/loader.h"
#include "scene/portable_random.h"
#include "sse/compiled_scene.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <new>
#include <string>
#include <vector>

namespace {
std::atomic<long> heap_allocations{0};
}  // namespace

// Counts every allocation in this test binary, so a test can prove a code path allocates nothing.
// GCC flags free() inside a replaced operator delete as mismatched; here it is the matching malloc's.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t size) {
    ++heap_allocations;
    if (void* memory = std::malloc(size == 0 ? 1 : size)) {
        return memory;
    }
    throw std::bad_alloc();
}
void* operator new(std::size_t size, std::align_val_t alignment) {
    ++heap_allocations;
    std::size_t rounded = (size + static_cast<std::size_t>(alignment) - 1) & ~(static_cast<std::size_t>(alignment) - 1);
    if (void* memory = std::aligned_alloc(static_cast<std::size_t>(alignment),
                                          rounded == 0 ? static_cast<std::size_t>(alignment) : rounded)) {
        return memory;
    }
    throw std::bad_alloc();
}
// The nothrow forms too (std::stable_sort's buffer takes one), so that every delete below frees what malloc gave.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    ++heap_allocations;
    return std::malloc(size == 0 ? 1 : size);
}
void operator delete(void* memory) noexcept {
    std::free(memory);
}
void operator delete(void* memory, const std::nothrow_t&) noexcept {
    std::free(memory);
}
void operator delete(void* memory, std::size_t) noexcept {
    std::free(memory);
}
void operator delete(void* memory, std::align_val_t) noexcept {
    std::free(memory);
}
void operator delete(void* memory, std::size_t, std::align_val_t) noexcept {
    std::free(memory);
}

namespace {

namespace fs = std::filesystem;

twinray::scene::Scene load(const std::string& name) {
    return twinray::scene::load_scene(fs::path(TWINRAY_SOURCE_DIR) / "scenes" / name);
}

class SseTracerTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (!twinray::sse::cpu_supports_sse41()) {
            GTEST_SKIP() << twinray::sse::missing_sse41_message();
        }
    }
};

TEST(SseCpuCheck, SimulatedMissingSse41IsReportedAsUnsupported) {
    ASSERT_EQ(::setenv("TWINRAY_SIMULATE_NO_SSE41", "1", 1), 0);
    EXPECT_FALSE(twinray::sse::cpu_supports_sse41());
    ASSERT_EQ(::unsetenv("TWINRAY_SIMULATE_NO_SSE41"), 0);
    EXPECT_EQ(twinray::sse::cpu_supports_sse41(), static_cast<bool>(__builtin_cpu_supports("sse4.1")));
    EXPECT_NE(twinray::sse::missing_sse41_message().find("SSE4.1"), std::string::npos);
}

template <typename Primitive>
void expect_aligned(const twinray::sse::PrimitiveList<Primitive>& list, const std::string& what) {
    for (const auto& primitive : list.items) {
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(&primitive) % 16, 0u) << what;
    }
}

void expect_aligned(const twinray::sse::PrimitiveLists& lists, const std::string& what) {
    int type = 0;
    lists.for_each([&](const auto& list) { expect_aligned(list, what + " primitive type " + std::to_string(type++)); });
}

TEST_F(SseTracerTest, EveryPrimitiveRecordOnTheHeapIsSixteenByteAligned) {
    static_assert(alignof(twinray::sse::SphereShape) == 16 && alignof(twinray::sse::PlaneShape) == 16 &&
                  alignof(twinray::sse::CylinderShape) == 16 && alignof(twinray::sse::BoxShape) == 16);
    for (const char* name : {"showcase.json", "csg.json", "complete2.json"}) {
        twinray::sse::Tracer tracer(load(name));
        const twinray::sse::CompiledScene& compiled = tracer.compiled();
        expect_aligned(compiled.primitives, name);
        for (const auto& object : compiled.csg_objects) {
            expect_aligned(object.tree->leaves, std::string(name) + " csg");
            EXPECT_EQ(reinterpret_cast<std::uintptr_t>(&object.bound) % 16, 0u) << name << " csg bound";
        }
    }
}

TEST_F(SseTracerTest, TracingRaysMakesNoHeapAllocation) {
    for (const char* name : {"showcase.json", "csg.json", "complete2.json"}) {
        twinray::scene::Scene scene = load(name);
        twinray::sse::Tracer tracer(scene);
        twinray::TraceTally tally;
        long before = heap_allocations.load();
        for (int y = 0; y < scene.height; y += 7) {
            for (int x = 0; x < scene.width; x += 7) {
                tracer.trace(tracer.primary_ray(x, y, scene.width, scene.height), 1, &tally);
            }
        }
        long allocations = heap_allocations.load() - before;
        EXPECT_EQ(allocations, 0) << name << ": " << allocations << " allocations while tracing " << tally.rays
                                  << " rays";
        EXPECT_GT(tally.rays, 1000u) << name;
    }
}

// The counter itself must see allocations, or the test above could not fail.
TEST(AllocationCounter, CountsAVectorsAllocation) {
    long before = heap_allocations.load();
    std::vector<int> numbers(100);
    EXPECT_GE(heap_allocations.load() - before, 1) << numbers.size();
}

// A packet computes each lane alone, and tile culling drops only primitives no primary ray of the tile
// can hit, so a pixel rendered in a 2x2 packet of a culled tile equals its ray traced alone.
TEST_F(SseTracerTest, RenderedPixelsEqualTheSingleRayTraceOfEachPixel) {
    for (const auto& entry : fs::directory_iterator(fs::path(TWINRAY_SOURCE_DIR) / "scenes")) {
        twinray::scene::Scene scene = twinray::scene::load_scene(entry.path());
        twinray::RenderOptions options;
        options.width = 61;  // odd, so edge packets run with inactive lanes
        twinray::RenderResult result = twinray::sse::render(scene, options);
        twinray::sse::Tracer tracer(scene);
        const int width = result.image.width(), height = result.image.height();
        twinray::TraceTally tally;
        int mismatches = 0;
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                twinray::TraceTally traced;
                twinray::sse::Color c = tracer.trace(tracer.primary_ray(x, y, width, height), 1, &traced);
                tally.add(traced, static_cast<std::int64_t>(y) * width + x);
                const twinray::Rgb& pixel = result.image.at(x, y);
                if (!(pixel.r == c.x && pixel.g == c.y && pixel.b == c.z) && ++mismatches <= 3) {
                    ADD_FAILURE() << entry.path().filename() << " pixel " << x << "," << y << ": rendered " << pixel.r
                                  << "," << pixel.g << "," << pixel.b << ", traced alone " << c.x << "," << c.y << ","
                                  << c.z;
                }
            }
        }
        EXPECT_EQ(mismatches, 0) << entry.path().filename();
        EXPECT_EQ(tally.rays, result.tally.rays) << entry.path().filename();
        EXPECT_EQ(tally.dropped_rays, result.tally.dropped_rays) << entry.path().filename();
        EXPECT_EQ(tally.pixels_over_budget, result.tally.pixels_over_budget) << entry.path().filename();
        EXPECT_EQ(tally.first_pixel_over_budget, result.tally.first_pixel_over_budget) << entry.path().filename();
    }
}

TEST_F(SseTracerTest, ImageIsBitIdenticalForOneTwoAndThreeThreads) {
    twinray::scene::Scene scene = load("csg.json");
    twinray::RenderOptions options;
    options.width = 160;
    options.threads = 1;
    twinray::RenderResult one = twinray::sse::render(scene, options);
    for (int threads : {2, 3}) {
        options.threads = threads;
        twinray::RenderResult many = twinray::sse::render(scene, options);
        EXPECT_TRUE(many.image == one.image) << threads << " threads";
        EXPECT_EQ(many.tally.rays, one.tally.rays) << threads << " threads";
    }
}

// A ray made of NaNs (secondary rays off a cylinder whose radius, 1e210, overflows float, under the fast
// kernels; found by bvh_differential_fuzz) has NaN crossings, which equal nothing: the CSG sweep looped
// forever on the first one. Every operation, either operand first, must end with spans within capacity.
TEST(SseCsg, ASweepOverNanCrossingsEnds) {
    using twinray::sse::SpanArray;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    SpanArray a, b, scratch, out;
    a.push({nan, 0, 0}, {nan, 0, 0});
    b.push({1.0f, 1, 0}, {2.0f, 1, 0});
    b.push({nan, 1, 0}, {3.0f, 1, 0});
    using twinray::scene::CsgOp;
    for (CsgOp op : {CsgOp::union_, CsgOp::intersection, CsgOp::difference}) {
        twinray::sse::csg_combine(op, a, b, scratch, out);
        EXPECT_LE(out.count, a.count + b.count + 1) << static_cast<int>(op);
        twinray::sse::csg_combine(op, b, a, scratch, out);
        EXPECT_LE(out.count, a.count + b.count + 1) << static_cast<int>(op);
    }
}

// Where a packet's lanes part inside an instance, a lane alone is tested against four triangles at once
// (crossing_of_four). It must give that lane what the packet's kernel gives it, bit for bit: hit or miss, t, front,
// on triangles of a grid met through their shared edges and corners (the ties' rule) and on random ones, by packets
// whose lanes share the frame's axis and by packets whose lanes do not.
TEST(SseTriangles, OneRayAgainstFourTrianglesAgreesBitForBitWithThePacketKernel) {
    using namespace twinray::sse;
    using P = ExactPrecision;
    twinray::SplitMix64 random(20261205);
    auto coordinate = [&](double low, double high) { return static_cast<float>(random.uniform(low, high)); };
    std::vector<TriangleRecord> triangles;
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {  // a grid's two triangles a square, in the plane z = 0.5 i
            const float x = static_cast<float>(i), y = static_cast<float>(j), z = 0.5f * static_cast<float>(i);
            triangles.push_back({{x, y, z}, {x + 1, y, z}, {x + 1, y + 1, z}, 0, 0});
            triangles.push_back({{x, y, z}, {x + 1, y + 1, z}, {x, y + 1, z}, 0, 0});
        }
    }
    for (int i = 0; i < 32; ++i) {
        auto vertex = [&] { return Vec3(coordinate(-1, 5), coordinate(-1, 5), coordinate(-1, 3)); };
        triangles.push_back({vertex(), vertex(), vertex(), 0, 0});
    }
    std::uint64_t compared = 0, hits = 0, shared_axis_packets = 0;
    for (int packet = 0; packet < 4000; ++packet) {
        alignas(16) float origin[3][4], direction[3][4];
        for (int lane = 0; lane < 4; ++lane) {
            // Grid points aimed along the axes, at the grid's corners, or anywhere.
            const bool on_grid = random.next() % 2 == 0;
            const Vec3 from =
                on_grid ? Vec3(static_cast<float>(random.next() % 5), static_cast<float>(random.next() % 5), 6)
                        : Vec3(coordinate(-1, 5), coordinate(-1, 5), coordinate(4, 8));
            Vec3 towards =
                random.next() % 3 == 0 ? Vec3(coordinate(-1, 1), coordinate(-1, 1), coordinate(-1, 1)) : Vec3(0, 0, -1);
            if (random.next() % 4 == 0) {
                towards =
                    Vec3(static_cast<float>(random.next() % 5), static_cast<float>(random.next() % 5), 0.5f) - from;
            }
            const Vec3 unit = twinray::math::normalize(towards);
            for (int axis = 0; axis < 3; ++axis) {
                origin[axis][lane] = from[axis];
                direction[axis][lane] = unit[axis];
            }
        }
        const RayPacket rays({vfloat4::load(origin[0]), vfloat4::load(origin[1]), vfloat4::load(origin[2])},
                             {vfloat4::load(direction[0]), vfloat4::load(direction[1]), vfloat4::load(direction[2])},
                             all_true());
        const ShearedRays sheared = ShearedRays::of<P>(rays);
        shared_axis_packets += sheared.common_kz >= 0 ? 1 : 0;
        for (int lane = 0; lane < 4; ++lane) {
            const ShearedRays alone = sheared.lane_alone(lane);
            for (std::size_t first = 0; first + 4 <= triangles.size(); first += 4) {
                const TriangleRecord* four[4] = {&triangles[first], &triangles[first + 1], &triangles[first + 2],
                                                 &triangles[first + 3]};
                const TriangleHit4 together = crossing_of_four<P>(block_of(four), alone);
                for (int k = 0; k < 4; ++k) {
                    const TriangleHit4 packet_kernel = crossing_of<P>(*four[k], sheared);
                    const bool expected = ((movemask(packet_kernel.valid) >> lane) & 1) != 0;
                    const bool actual = ((movemask(together.valid) >> k) & 1) != 0;
                    ASSERT_EQ(expected, actual)
                        << "packet " << packet << ", lane " << lane << ", triangle " << first + k;
                    ++compared;
                    if (!expected) {
                        continue;
                    }
                    ++hits;
                    const float t_expected = packet_kernel.t.lane(lane), t_actual = together.t.lane(k);
                    ASSERT_EQ(0, std::memcmp(&t_expected, &t_actual, sizeof(float)))
                        << "t " << t_expected << " against " << t_actual << ", packet " << packet << ", lane " << lane;
                    ASSERT_EQ((movemask(packet_kernel.front) >> lane) & 1, (movemask(together.front) >> k) & 1)
                        << "front, packet " << packet << ", lane " << lane << ", triangle " << first + k;
                }
            }
        }
    }
    EXPECT_EQ(compared, 4000u * 4u * 64u);
    EXPECT_GT(hits, 20000u) << "too few hits to compare";
    EXPECT_GT(shared_axis_packets, 100u);
    EXPECT_LT(shared_axis_packets, 3900u);
}

}  // namespace

namespace {

bool same_hit(const twinray::sse::Hit& a, const twinray::sse::Hit& b) {
    return a.t == b.t && a.leaf == b.leaf && a.triangle == b.triangle && a.entering == b.entering &&
           a.normal == b.normal && a.point == b.point && a.spawn_offset == b.spawn_offset;
}

}  // namespace

// hits_along is what the tracer ABI's every-hit query and the watertightness suite read: its first hit must be the
// nearest hit intersect finds, its list ordered, and the BVH must not change it.
TEST_F(SseTracerTest, HitsAlongBeginWithTheNearestHitAreOrderedAndTheSameWithOrWithoutTheBvh) {
    using twinray::Accel;
    for (const char* name : {"complete1.json", "csg.json", "meshes.json", "transforms.json", "instances.json"}) {
        const twinray::scene::Scene scene = load(name);
        const twinray::sse::Tracer with_bvh(scene, {}, Accel::bvh), brute_force(scene, {}, Accel::none);
        int rays = 0, hits = 0, crossings = 0;
        for (int y = 0; y < 24; ++y) {
            for (int x = 0; x < 32; ++x) {
                const twinray::sse::Ray ray = with_bvh.primary_ray(x, y, 32, 24);
                const std::optional<twinray::sse::Hit> nearest = with_bvh.intersect(ray);
                const std::vector<twinray::sse::Hit> along =
                    with_bvh.hits_along(ray, std::numeric_limits<float>::infinity());
                const std::vector<twinray::sse::Hit> along_brute =
                    brute_force.hits_along(ray, std::numeric_limits<float>::infinity());
                ++rays;
                ASSERT_EQ(nearest.has_value(), !along.empty()) << name << " pixel " << x << ", " << y;
                ASSERT_EQ(along.size(), along_brute.size()) << name << " pixel " << x << ", " << y;
                for (std::size_t i = 0; i < along.size(); ++i) {
                    ASSERT_TRUE(same_hit(along[i], along_brute[i])) << name << " pixel " << x << ", " << y;
                    ASSERT_TRUE(i == 0 || along[i - 1].t <= along[i].t) << name << " pixel " << x << ", " << y;
                }
                if (nearest) {
                    ++hits;
                    crossings += static_cast<int>(along.size());
                    ASSERT_TRUE(same_hit(*nearest, along.front()))
                        << name << " pixel " << x << ", " << y << ": nearest t " << nearest->t << " leaf "
                        << nearest->leaf << ", first along t " << along.front().t << " leaf " << along.front().leaf;
                }
                if (!along.empty()) {
                    const float cut = along.front().t;
                    ASSERT_TRUE(with_bvh.hits_along(ray, cut).empty()) << "nothing lies before the first crossing";
                }
            }
        }
        EXPECT_GT(hits, 0) << name;
        EXPECT_GT(crossings, hits) << name << ": rays through closed solids cross them more than once";
        std::cout << name << ": " << rays << " rays, " << hits << " hits, " << crossings << " crossings\n";
    }
}
