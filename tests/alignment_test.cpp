// The thesis's aligned-memory lesson: SSE data on the heap must be 16-byte aligned, or the first
// aligned load of it faults. What demonstrates it here, and why each part is needed:
//
// 1. Misalignment is fatal, not slow. The kernels read records with aligned loads: MOVAPS, and
//    arithmetic with a memory operand, which without AVX (we build with -msse4.1 only) requires 16-byte
//    alignment. A record copied to an address 4 bytes off makes the real sphere kernel die: SIGSEGV
//    (#GP) in an optimised build, a UBSan "misaligned address" report under the asan-ubsan preset.
//    Without this part a check like the next one could pass vacuously, e.g. if the compiler ever
//    loaded records with MOVUPS.
// 2. Every record is aligned, wherever it lives: the top-level and CSG primitive arrays of every
//    scene in scenes/ (compiled on the heap), a copy of a compiled scene, and lists grown one record at
//    a time as the tile culling builds them (push_back_from: every reallocation). Each 16-byte group of
//    every record is read with MOVAPS itself, so a misaligned one crashes the test whatever the
//    compiler, optimisation level or sanitizer; under UBSan the same holds for the typed loads.
//
// Why the heap is aligned at all: every record type is alignas(16) (a vfloat4 is a __m128), so C++17's
// std::allocator gets storage aligned for it — from plain operator new, whose guarantee
// (__STDCPP_DEFAULT_NEW_ALIGNMENT__) is 16 bytes on x86-64, or from aligned new where the guarantee is
// smaller. glibc's malloc also returns 16-byte aligned blocks here, which is exactly why a record stored
// in storage that does not honour alignof (a byte buffer, a packed struct, a pool) would often work on
// this platform and fail elsewhere: part 1 makes such a record fail here too.
#include "scene/loader.h"
#include "sse/compiled_scene.h"
#include "sse/cpu.h"
#include "sse/sphere.h"
#include "sse/tracer.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace twinray::sse;

// Every SSE record is a whole number of 16-byte groups, so each element of an aligned array is aligned.
static_assert(alignof(PlaneShape) == 16 && sizeof(PlaneShape) % 16 == 0);
static_assert(alignof(SphereShape) == 16 && sizeof(SphereShape) % 16 == 0);
static_assert(alignof(CylinderShape) == 16 && sizeof(CylinderShape) % 16 == 0);
static_assert(alignof(BoxShape) == 16 && sizeof(BoxShape) % 16 == 0);
static_assert(alignof(CsgObject) >= 16, "CsgObject holds a BoxShape bound");

// MOVAPS from `address`, whatever the compiler would have chosen: the CPU faults unless it is a
// multiple of 16.
__m128 load_with_movaps(const void* address) {
    __m128 value;
    __asm__ __volatile__("movaps %1, %0" : "=x"(value) : "m"(*static_cast<const float(*)[4]>(address)));
    return value;
}

// Loads every 16-byte group of every record; returns how many records were read.
template <typename Record, typename Allocator>
std::size_t load_every_group(const std::vector<Record, Allocator>& records) {
    for (const Record& record : records) {
        const auto* bytes = reinterpret_cast<const unsigned char*>(&record);
        for (std::size_t offset = 0; offset < sizeof(Record); offset += 16) {
            __m128 group = load_with_movaps(bytes + offset);
            // The group read is the record's own bytes (the load is not optimised away or elsewhere).
            alignas(16) float lanes[4];
            _mm_store_ps(lanes, group);
            EXPECT_EQ(std::memcmp(lanes, bytes + offset, 16), 0);
        }
    }
    return records.size();
}

std::size_t load_every_group(const PrimitiveLists& lists) {
    std::size_t records = 0;
    lists.for_each([&](const auto& list) { records += load_every_group(list.items); });
    return records;
}

std::size_t load_every_group(const CompiledScene& compiled) {
    std::size_t records = load_every_group(compiled.primitives);
    for (const CsgObject& object : compiled.csg_objects) {
        records += load_every_group(object.tree->leaves);
        load_with_movaps(&object.bound);  // in place, inside the heap array of CsgObject
        ++records;
    }
    return records;
}

// The tile culling's path: a list that grows one record at a time from empty, so it reallocates.
template <typename Record>
void grow_one_by_one(const PrimitiveList<Record>& from, PrimitiveList<Record>& into) {
    for (int copy = 0; copy < 9; ++copy) {
        for (std::size_t i = 0; i < from.items.size(); ++i) {
            into.push_back_from(from, i);
        }
    }
}

std::vector<fs::path> every_scene() {
    std::vector<fs::path> scenes;
    for (const auto& entry : fs::directory_iterator(fs::path(TWINRAY_SOURCE_DIR) / "scenes")) {
        if (entry.path().extension() == ".json") {
            scenes.push_back(entry.path());
        }
    }
    return scenes;
}

class AlignmentTest : public ::testing::Test {
protected:
    void SetUp() override {
        if (!cpu_supports_sse41()) {
            GTEST_SKIP() << missing_sse41_message();
        }
    }
};

SphereShape sphere_record() {
    Tracer tracer(twinray::scene::load_scene(fs::path(TWINRAY_SOURCE_DIR) / "scenes" / "spheres.json"));
    const auto& spheres = tracer.compiled().primitives.of<twinray::scene::Sphere>().items;
    return spheres.empty() ? SphereShape{} : spheres.front();
}

RayPacket packet_towards_minus_z() {
    return RayPacket(broadcast(Vec3{0, 0, 10}), broadcast(Vec3{0, 0, -1}),
                     vbool4{_mm_castsi128_ps(_mm_set1_epi32(-1))});
}

// Kept out of line, fed through an opaque pointer and its result stored to a volatile, so the kernel
// really runs and loads from `sphere` (a call whose result is unused may be removed as pure).
volatile float kernel_result = 0;
__attribute__((noinline)) float first_entry(const SphereShape* sphere, const RayPacket& rays) {
    float entry = span_of<twinray::sse::ExactPrecision>(*sphere, rays).enter.lane(0);
    kernel_result = entry;
    return entry;
}

TEST_F(AlignmentTest, AMisalignedRecordKillsTheSphereKernel) {
#if defined(__clang__) && !defined(__OPTIMIZE__)
    GTEST_SKIP() << "clang without optimisation copies vfloat4 values with unaligned moves; "
                    "the MOVAPS test below still shows the fault";
#endif
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    SphereShape sphere = sphere_record();
    RayPacket rays = packet_towards_minus_z();
    auto storage = std::make_unique<unsigned char[]>(sizeof(SphereShape) + 32);
    unsigned char* aligned = storage.get() + (16 - reinterpret_cast<std::uintptr_t>(storage.get()) % 16) % 16;
    std::memcpy(aligned, &sphere, sizeof sphere);
    std::memcpy(aligned + 20, &sphere, sizeof sphere);  // 16 + 4: off by one float
    const SphereShape* volatile at_aligned = reinterpret_cast<const SphereShape*>(aligned);
    const SphereShape* volatile at_misaligned = reinterpret_cast<const SphereShape*>(aligned + 20);
    // The same bytes, correctly aligned, work: the failure below is the address alone.
    EXPECT_EQ(first_entry(at_aligned, rays), first_entry(&sphere, rays));
    EXPECT_DEATH(first_entry(at_misaligned, rays), "");
}

TEST_F(AlignmentTest, MovapsFaultsOnAnAddressFourBytesOffAndNotOnAnAlignedOne) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    alignas(16) float buffer[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    const float* volatile off_by_one_float = buffer + 1;
    load_with_movaps(buffer);
    EXPECT_DEATH(load_with_movaps(off_by_one_float), "");
}

TEST_F(AlignmentTest, EveryRecordOfEveryCompiledSceneIsReadWithAlignedLoads) {
    std::size_t records = 0;
    for (const fs::path& file : every_scene()) {
        SCOPED_TRACE(file.filename().string());
        Tracer tracer(twinray::scene::load_scene(file));
        const CompiledScene& compiled = tracer.compiled();
        records += load_every_group(compiled);
        // A copy is new storage: aligned too.
        CompiledScene copy = compiled;
        records += load_every_group(copy);
        // Lists grown one record at a time, as the tile culling fills its per-thread lists.
        PrimitiveLists grown;
        compiled.primitives.for_each_pair(grown,
                                          [](const auto& all, auto& one_by_one) { grow_one_by_one(all, one_by_one); });
        records += load_every_group(grown);
    }
    EXPECT_GT(records, 100u) << "the scenes should hold records of every kind";
}

}  // namespace
