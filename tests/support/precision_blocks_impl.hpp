// tests/support/precision_blocks_impl.hpp — the precision building blocks of one
// ISA unit, for tests/support/precision_unit.cpp.in (after kernels/packet_kernels.hpp and
// dispatch/isa_instantiate.hpp, inside the same OCTRAY_ISA namespace scheme): the same
// lane functions and dot product the kernels use, over arrays whose length is
// a multiple of the packet width, one lane group at a time.
#pragma once

#include "precision_blocks.hpp"

namespace octray::kernels::OCTRAY_ISA {

template <class T>
inline T load_lanes(const float* p) {
    if constexpr (lane::width<T> == 1) return T(*p);
    else return T::load_unaligned(p);
}
template <class T>
inline void store_lanes(float* p, const T& v) {
    if constexpr (lane::width<T> == 1) *p = float(v);
    else v.store_unaligned(p);
}

template <class T, Precision P>
struct BlockImpl {
    static constexpr int W = lane::width<T>;
    static void rcp(const float* x, float* out, int n) noexcept {
        for (int i = 0; i < n; i += W) store_lanes(out + i, lane::rcp<P>(load_lanes<T>(x + i)));
    }
    static void rsqrt(const float* x, float* out, int n) noexcept {
        for (int i = 0; i < n; i += W) store_lanes(out + i, lane::rsqrt<P>(load_lanes<T>(x + i)));
    }
    static void div(const float* a, const float* b, float* out, int n) noexcept {
        for (int i = 0; i < n; i += W) store_lanes(out + i, lane::div<P>(load_lanes<T>(a + i), load_lanes<T>(b + i)));
    }
    // As the pinhole camera normalizes its ray directions.
    static void normalize(const float* const v[3], float* const out[3], int n) noexcept {
        for (int i = 0; i < n; i += W) {
            const Vec3<T> d{load_lanes<T>(v[0] + i), load_lanes<T>(v[1] + i), load_lanes<T>(v[2] + i)};
            const Vec3<T> u = d * lane::rsqrt<P>(fdot(d, d));
            store_lanes(out[0] + i, u.x), store_lanes(out[1] + i, u.y), store_lanes(out[2] + i, u.z);
        }
    }
    // As point-light shading computes n.l: (n.v) / |v| for v = light - p.
    static void ndotl(const float* const nv[3], const float* const v[3], float* out, int n) noexcept {
        for (int i = 0; i < n; i += W) {
            const Vec3<T> nn{load_lanes<T>(nv[0] + i), load_lanes<T>(nv[1] + i), load_lanes<T>(nv[2] + i)};
            const Vec3<T> vv{load_lanes<T>(v[0] + i), load_lanes<T>(v[1] + i), load_lanes<T>(v[2] + i)};
            store_lanes(out + i, fdot(nn, vv) * lane::rsqrt<P>(fdot(vv, vv)));
        }
    }
    static void pow(const float* x, const float* y, float* out, int n) noexcept {
        for (int i = 0; i < n; i += W) store_lanes(out + i, gamma_pow(load_lanes<T>(x + i), load_lanes<T>(y + i)));
    }
};

template <class T, Precision P>
Blocks make_blocks_at() {
    using B = BlockImpl<T, P>;
    return {&B::rcp, &B::rsqrt, &B::div, &B::normalize, &B::ndotl, &B::pow};
}

template <class F, class D, unsigned Modes>
Blocks make_blocks(Precision precision) {
    return with_precision(precision, [](auto mode) -> Blocks {
        constexpr Precision P = decltype(mode)::value;
        if constexpr ((Modes & mode_bit(P)) == 0) return {};
        else if constexpr (P == Precision::f64) return make_blocks_at<D, P>();
        else return make_blocks_at<F, P>();
    });
}

}  // namespace octray::kernels::OCTRAY_ISA
