// kernels/trace/packet_io.hpp — what every kernel header builds on: the lane
// vocabulary, the packet <-> lane loads and stores, and per-lane reads of the
// scene's arrays.
//
// Every kernel header lives in the namespace octray::kernels::OCTRAY_ISA: each
// translation unit that includes them names its instruction set (OCTRAY_ISA,
// set by the generated unit, see dispatch/isa_unit.cpp.in), so instantiations compiled
// with different -m flags never merge at link time (one ISA per translation
// unit).
#pragma once

#ifndef OCTRAY_ISA
#error "define OCTRAY_ISA before including a kernel header (see dispatch/isa_unit.cpp.in)"
#endif

#include "kernels/lanes/lane.hpp"
#include "kernels/scene_data.hpp"

#include <octray/packet.hpp>
#include <octray/vec3.hpp>

#include <cassert>
#include <cstdint>
#include <limits>
#include <type_traits>

// The hot path of a primitive test must inline into its loop (GCC otherwise
// keeps the sphere test out of line and reloads the ray from memory for every
// sphere); the rare robust paths stay out of line to keep that loop small.
#ifndef OCTRAY_HOT
#define OCTRAY_HOT inline __attribute__((always_inline))
#define OCTRAY_COLD __attribute__((noinline, cold))
// The per-primitive lambdas handed to for_each_candidate: left to the
// inliner, a translation unit may keep one out of line, a call per test.
#define OCTRAY_HOT_LAMBDA __attribute__((always_inline))
#define OCTRAY_WALK __attribute__((noinline))
#endif

namespace octray::kernels::OCTRAY_ISA {

using lane::Mask;

// ---- packet <-> lane I/O ---------------------------------------------------
// A packet of 8 is processed as 8 / width<T> groups; `lane` is the first lane.
template <class T>
inline T load(const float* p, int lane) {
    if constexpr (lane::width<T> == 1) return T(p[lane]);
    else return lane::load_floats<T>(p + lane);
}
template <class T>
inline T load_index(const std::int32_t* p, int lane) {
    if constexpr (lane::width<T> == 1) return T(p[lane]);
    else return lane::load_ints<T>(p + lane);  // converts int32 -> float (or double) lanes
}
template <class T>
inline void store(float* p, int lane, const T& v) {
    if constexpr (lane::width<T> == 1) p[lane] = float(v);
    else lane::store_floats(p + lane, v);
}
// Stores a small integer carried as an exact float.
template <class T>
inline void store_index(std::int32_t* p, int lane, const T& v) {
    if constexpr (lane::width<T> == 1) {
        p[lane] = std::int32_t(v);
#if defined(__AVX__)
    } else if constexpr (std::is_same_v<lane::Scalar<T>, float> && lane::width<T> == 8) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(p + lane), _mm256_cvttps_epi32(v));
#endif
    } else {
        alignas(64) lane::Scalar<T> tmp[lane::width<T>];
        v.store_aligned(tmp);
        for (int i = 0; i < lane::width<T>; ++i) p[lane + i] = std::int32_t(tmp[i]);
    }
}
template <class T>
inline void store_mask(std::int32_t* p, int lane, const Mask<T>& m) {
    store_index(p, lane, lane::keep(m, T(-1)));
}
template <class T>
inline Mask<T> load_mask(const std::int32_t* p, int lane) {
    return load_index<T>(p, lane) != T(0);
}
template <class T>
inline T broadcast(const Floats& a, int k) { return T(a[std::size_t(k)]); }
template <class T>
inline Vec3<T> broadcast3(const Floats& x, const Floats& y, const Floats& z, int k) {
    return {T(x[std::size_t(k)]), T(y[std::size_t(k)]), T(z[std::size_t(k)])};
}
template <class T>
inline Vec3<T> gather3(const Floats& x, const Floats& y, const Floats& z, const T& idx) {
    return {lane::gather(x.data(), idx), lane::gather(y.data(), idx), lane::gather(z.data(), idx)};
}

// Per-lane reads of scene arrays at `idx` (exact small integers), where only
// the lanes of `m` matter: one broadcast load when those lanes agree on the
// index, which a packet of coherent rays mostly does, else a gather. Lanes
// outside `m` then read the agreed element instead of their own: callers
// select them away.
template <class T>
struct Lookup {
    T idx;
    int first;
    bool uniform;
    Lookup(const T& index, const Mask<T>& m) : idx(index), uniform(lane::uniform_on(index, m, first)) {}
    // Every lane reads element k.
    static Lookup at_index(int k) { return Lookup(k); }
    T operator()(const Floats& a) const { return uniform ? T(a[std::size_t(first)]) : lane::gather(a.data(), idx); }
    T operator()(const IdMap& m) const {
        if (m.narrow_ids.empty()) return (*this)(m.wide);
        return uniform ? T(lane::Scalar<T>(m.narrow_ids[std::size_t(first)])) : lane::gather16(m.narrow_ids.data(), idx);
    }
    Vec3<T> operator()(const Floats& x, const Floats& y, const Floats& z) const {
        if (uniform) return broadcast3<T>(x, y, z, first);
        return gather3(x, y, z, idx);
    }

  private:
    explicit Lookup(int k) : idx(T(float(k))), first(k), uniform(true) {}
};

// Fields f, f + 1, f + 2 (TriangleField) of the lanes' triangles (indices
// within the type, read through `at`): from their blocks (TriangleBlocks),
// a lane at a time where the lanes differ (once per hit lane).
template <class T>
inline Vec3<T> triangle_fields3(const SceneData& s, const Lookup<T>& at, int f) {
    if (at.uniform)
        return {T(triangle_field(s, at.first, f)), T(triangle_field(s, at.first, f + 1)),
                T(triangle_field(s, at.first, f + 2))};
    if constexpr (lane::width<T> == 1) {
        const int k = int(at.idx);
        return {T(triangle_field(s, k, f)), T(triangle_field(s, k, f + 1)), T(triangle_field(s, k, f + 2))};
    } else {
        using S = lane::Scalar<T>;
        constexpr int W = lane::width<T>;
        alignas(64) S idx[W], x[W], y[W], z[W];
        at.idx.store_aligned(idx);
        for (int i = 0; i < W; ++i) {
            const int k = int(idx[i]);
            x[i] = S(triangle_field(s, k, f)), y[i] = S(triangle_field(s, k, f + 1)), z[i] = S(triangle_field(s, k, f + 2));
        }
        return {T::load_aligned(x), T::load_aligned(y), T::load_aligned(z)};
    }
}

template <class T>
inline T fdot(const Vec3<T>& a, const Vec3<T>& b) { return lane::fma(a.x, b.x, lane::fma(a.y, b.y, a.z * b.z)); }

template <class T>
inline T inf() { return T(std::numeric_limits<float>::infinity()); }

}  // namespace octray::kernels::OCTRAY_ISA
