// kernels/aligned.hpp — 64-byte aligned float arrays for the SoA scene, so a
// packet's loads of 8 consecutive elements never split a cache line.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

namespace octray {

template <class T, std::size_t Align = 64>
struct AlignedAllocator {
    using value_type = T;
    template <class U>
    struct rebind { using other = AlignedAllocator<U, Align>; };
    AlignedAllocator() = default;
    template <class U>
    AlignedAllocator(const AlignedAllocator<U, Align>&) noexcept {}
    T* allocate(std::size_t n) {
        std::size_t bytes = (n * sizeof(T) + Align - 1) / Align * Align;
        if (void* p = std::aligned_alloc(Align, bytes == 0 ? Align : bytes)) return static_cast<T*>(p);
        throw std::bad_alloc();
    }
    void deallocate(T* p, std::size_t) noexcept { std::free(p); }
    friend bool operator==(const AlignedAllocator&, const AlignedAllocator&) { return true; }
    friend bool operator!=(const AlignedAllocator&, const AlignedAllocator&) { return false; }
};
template <class T>
using AlignedVector = std::vector<T, AlignedAllocator<T>>;
using Floats = AlignedVector<float>;

}  // namespace octray
