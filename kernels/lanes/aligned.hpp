// kernels/lanes/aligned.hpp — aligned arrays for the SoA scene and the BVH: 64-byte
// aligned, so a packet's loads of 8 consecutive elements never split a cache
// line; and large ones in transparent huge pages, where the kernel has them.
//
// Why huge pages: a compile() touches every array it makes once, right away,
// and on a virtual machine each 4 KiB page's first touch is a fault through
// the hypervisor (docs/history/performance-2026.md measures it: about a third of a
// 262k-triangle build). An array of at least kHugeBytes starts on a 2 MiB
// boundary and its whole 2 MiB blocks are marked MADV_HUGEPAGE, so one fault
// maps 2 MiB; the tail past the last whole block keeps small pages (no
// memory is added). Embree's allocator does the same for its BVH.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace octray {

inline constexpr std::size_t kHugePage = std::size_t(2) << 20;
inline constexpr std::size_t kHugeBytes = kHugePage;

#if defined(__linux__) && defined(MADV_HUGEPAGE)
// What allocate_aligned maps for an array of `bytes` (whole small pages), or
// 0 where it takes the array from malloc: both ends ask this one question.
inline std::size_t mapped_bytes(std::size_t bytes) {
    if (bytes < kHugeBytes) return 0;
    const std::size_t page = std::size_t(sysconf(_SC_PAGESIZE));
    return (bytes + page - 1) / page * page;
}
#endif

// `bytes` aligned to `align` (a power of two, a multiple of sizeof(void*), at
// most kHugePage); free with free_aligned(p, bytes). Large arrays are mapped
// on their own (not from malloc's heap, whose pages it may return and fault
// in again), start on a huge page and ask for huge pages: advice only, where
// the kernel has none to give it maps small ones.
inline void* allocate_aligned(std::size_t bytes, std::size_t align) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (const std::size_t size = mapped_bytes(bytes); size != 0) {  // align <= kHugePage (the callers' static_asserts)
        const std::size_t span = size + kHugePage;
        void* base = mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (base == MAP_FAILED) throw std::bad_alloc();
        const std::uintptr_t b = reinterpret_cast<std::uintptr_t>(base);
        const std::uintptr_t p = (b + kHugePage - 1) / kHugePage * kHugePage;
        if (p > b) munmap(base, p - b);  // the slack before
        if (b + span > p + size) munmap(reinterpret_cast<void*>(p + size), b + span - (p + size));  // and after
        (void)madvise(reinterpret_cast<void*>(p), size, MADV_HUGEPAGE);
        return reinterpret_cast<void*>(p);
    }
#endif
    void* p = nullptr;
    if (posix_memalign(&p, align, bytes == 0 ? align : bytes) != 0) throw std::bad_alloc();
    return p;
}
inline void free_aligned(void* p, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (const std::size_t size = mapped_bytes(bytes); size != 0) {
        if (p != nullptr) munmap(p, size);
        return;
    }
#endif
    std::free(p);
}

template <class T, std::size_t Align = 64>
struct AlignedAllocator {
    using value_type = T;
    static constexpr std::size_t kAlign = Align < alignof(T) ? alignof(T) : Align;
    static_assert(kAlign <= kHugePage, "free_aligned unmaps what allocate_aligned maps");
    template <class U>
    struct rebind { using other = AlignedAllocator<U, Align>; };
    AlignedAllocator() = default;
    template <class U>
    AlignedAllocator(const AlignedAllocator<U, Align>&) noexcept {}
    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
        return static_cast<T*>(allocate_aligned(n * sizeof(T), kAlign));
    }
    void deallocate(T* p, std::size_t n) noexcept { free_aligned(p, n * sizeof(T)); }
    friend bool operator==(const AlignedAllocator&, const AlignedAllocator&) { return true; }
    friend bool operator!=(const AlignedAllocator&, const AlignedAllocator&) { return false; }
};
template <class T>
using AlignedVector = std::vector<T, AlignedAllocator<T>>;
using Floats = AlignedVector<float>;

// An array of n T (trivial: left uninitialized, so only the pages written are
// ever touched), aligned and in huge pages as above.
template <class T>
class RawArray {
    static_assert(std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>, "trivial");
    static constexpr std::size_t kAlign = alignof(T) < 64 ? 64 : alignof(T);
    static_assert(kAlign <= kHugePage, "free_aligned unmaps what allocate_aligned maps");
    T* data_ = nullptr;
    std::size_t bytes_ = 0;

public:
    explicit RawArray(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
        bytes_ = n * sizeof(T);
        data_ = static_cast<T*>(allocate_aligned(bytes_, kAlign));
        std::uninitialized_default_construct_n(data_, n);  // no code: T is trivial
    }
    RawArray(const RawArray&) = delete;
    RawArray& operator=(const RawArray&) = delete;
    ~RawArray() { free_aligned(data_, bytes_); }
    T* get() const { return data_; }
};

}  // namespace octray
