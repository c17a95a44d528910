// std::vector for the arrays that grow with the scene (a tracer's compiled primitives, its BVH): every block
// starts on a cache line (64 bytes; a BVH keeps two sibling nodes in one), and blocks of 2 MiB and more are
// 2 MiB aligned and offered to the kernel as transparent huge pages (madvise), so that a
// million primitives take some fifty pages instead of some fifty thousand. On this machine's VM that halved
// compiling and building a BVH over 1 000 000 spheres and cut first-hit time by a quarter to a third, all of
// it page faults and TLB misses (docs/performance.md, "The BVH"). Where the kernel declines (THP `never`),
// the memory is ordinary memory; nothing else changes.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

namespace twinray {

template <typename T>
struct HugePageAllocator {
    using value_type = T;
    static constexpr std::size_t huge_page = std::size_t{2} << 20;
    static constexpr std::align_val_t cache_line{64};

    HugePageAllocator() = default;
    template <typename U>
    HugePageAllocator(const HugePageAllocator<U>&) {}

    T* allocate(std::size_t count) {
        if (count > (std::size_t{1} << 48) / sizeof(T)) {
            throw std::bad_array_new_length();
        }
        std::size_t bytes = count * sizeof(T);
        if (bytes < huge_page) {
            return static_cast<T*>(::operator new(bytes, cache_line));
        }
        std::size_t rounded = (bytes + huge_page - 1) / huge_page * huge_page;
        void* block = std::aligned_alloc(huge_page, rounded);
        if (block == nullptr) {
            throw std::bad_alloc();
        }
        // The whole pages only: a huge page under the tail would be resident whole once touched (1 MiB an array on
        // average, some 12 MiB at the peak of compiling a million primitives), where 4 KiB pages cost what is used.
        ::madvise(block, bytes / huge_page * huge_page, MADV_HUGEPAGE);
        return static_cast<T*>(block);
    }

    void deallocate(T* block, std::size_t count) {
        if (count * sizeof(T) < huge_page) {
            ::operator delete(block, cache_line);
        } else {
            std::free(block);
        }
    }

    template <typename U>
    bool operator==(const HugePageAllocator<U>&) const {
        return true;
    }
};

template <typename T>
using LargeArray = std::vector<T, HugePageAllocator<T>>;

}  // namespace twinray
