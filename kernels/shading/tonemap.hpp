// kernels/shading/tonemap.hpp — HDR radiance to display colour: max_to_one,
// clamp_to_color or saturate, then gamma (docs/shading-model.md, tone mapping).
#pragma once

#include "kernels/lanes/lane_pow.hpp"
#include "kernels/trace/packet_io.hpp"

namespace octray::kernels::OCTRAY_ISA {

// ---- tone mapping (docs/shading-model.md) ---------------------------------
// c^y for c > 0: on float lanes kernels/lanes/lane_pow.hpp's, the same code on both paths
// (libm's powf and xsimd's pow differ, and xsimd's is ~100 cycles per batch);
// double lanes (the f64 mode) keep libm's / xsimd's double pow.
template <class T>
inline T gamma_pow(const T& c, const T& y) {
    if constexpr (std::is_same_v<lane::Scalar<T>, float>) {
        return lane::pow_positive(c, y);
    } else {
        // xsimd's double pow is exp(y log c), and its exp converts (y log c)
        // / ln 2 to an integer before its range check: past 2^63 (y = +inf,
        // a gamma below 2^-128 whose 1/gamma rounds to +inf in float; c =
        // +inf, a clamp colour past the float range) that is undefined
        // behaviour (UBSan, found by fuzz/kernels_fuzz.cpp). y <= 2^40 and
        // c <= FLT_MAX keep |y log c| < 2^47 and change no float result:
        // c^(2^40) is already 0 for c < 1 and +inf for c > 1; +inf stays +inf.
        const T finite_c = lane::min(c, T(std::numeric_limits<float>::max()));
        return lane::select(c == inf<T>(), c, lane::pow(finite_c, lane::min(y, T(0x1p40))));
    }
}

// NaN radiance becomes 0. Under max_to_one an infinite component becomes 1
// and the finite ones 0 (the limit of c / max as max -> inf); clamp_to_color
// treats inf as out of gamut; saturate clamps it to 1.
template <class T, Precision P, ToneMap M, int K>
inline void tonemap_lanes(const SceneData& s, const ColorPacket8* in, ColorPacket8* out, int lane) {
    // K packets in lockstep: each step for all K before the next, so their
    // dependent chains (the reciprocal, pow's divide and polynomials) overlap.
    T r[K], g[K], b[K];
    for (int k = 0; k < K; ++k) {
        // max(x, 0) flushes NaN to 0 (lane::max returns its second operand on NaN).
        r[k] = lane::max(load<T>(in[k].r, lane), T(0));
        g[k] = lane::max(load<T>(in[k].g, lane), T(0));
        b[k] = lane::max(load<T>(in[k].b, lane), T(0));
    }
    if constexpr (M == ToneMap::max_to_one) {
        T scale[K];
        Mask<T> over[K], infinite[K];
        for (int k = 0; k < K; ++k) {
            const T mx = lane::max(r[k], lane::max(g[k], b[k]));
            over[k] = mx > T(1);
            infinite[k] = mx == inf<T>();
            scale[k] = lane::rcp<P>(lane::select(over[k] && lane::not_(infinite[k]), mx, T(1)));
        }
        auto fix = [&](const T& c, int k) {
            return lane::select(infinite[k], lane::keep(c == inf<T>(), T(1)), lane::select(over[k], lane::min(c * scale[k], T(1)), c));
        };
        for (int k = 0; k < K; ++k) r[k] = fix(r[k], k), g[k] = fix(g[k], k), b[k] = fix(b[k], k);
    } else if constexpr (M == ToneMap::clamp_to_color) {
        for (int k = 0; k < K; ++k) {
            const Mask<T> over = r[k] > T(1) || g[k] > T(1) || b[k] > T(1);
            r[k] = lane::select(over, T(s.clamp_color[0]), r[k]);
            g[k] = lane::select(over, T(s.clamp_color[1]), g[k]);
            b[k] = lane::select(over, T(s.clamp_color[2]), b[k]);
        }
    } else {
        for (int k = 0; k < K; ++k) r[k] = lane::min(r[k], T(1)), g[k] = lane::min(g[k], T(1)), b[k] = lane::min(b[k], T(1));
    }
    if (s.inv_gamma != 1.0f) {
        const T ig(s.inv_gamma);
        // c = 0 computes a finite value that the select drops.
        auto gam = [&](const T& c) { return lane::keep(c > T(0), gamma_pow(c, ig)); };
        for (int k = 0; k < K; ++k) r[k] = gam(r[k]), g[k] = gam(g[k]), b[k] = gam(b[k]);
    }
    for (int k = 0; k < K; ++k) {
        store(out[k].r, lane, r[k]);
        store(out[k].g, lane, g[k]);
        store(out[k].b, lane, b[k]);
    }
}

template <class T, Precision P, int K>
inline void tonemap_k(const SceneData& s, const ColorPacket8* in, ColorPacket8* out) {
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) {
        switch (s.tonemap) {
        case ToneMap::max_to_one: tonemap_lanes<T, P, ToneMap::max_to_one, K>(s, in, out, lane); break;
        case ToneMap::clamp_to_color: tonemap_lanes<T, P, ToneMap::clamp_to_color, K>(s, in, out, lane); break;
        case ToneMap::saturate: tonemap_lanes<T, P, ToneMap::saturate, K>(s, in, out, lane); break;
        }
    }
}

template <class T, Precision P>
void tonemap_group(const PacketScene& scene, const ColorPacket8* in, ColorPacket8* out, int count) noexcept {
    const SceneData& s = scene_data(scene);
    int i = 0;
    for (; i + 2 <= count; i += 2) tonemap_k<T, P, 2>(s, in + i, out + i);
    if (i < count) tonemap_k<T, P, 1>(s, in + i, out + i);
}

template <class T, Precision P>
void tonemap_packet(const PacketScene& scene, const ColorPacket8& in, ColorPacket8& out) noexcept {
    tonemap_k<T, P, 1>(scene_data(scene), &in, &out);
}

}  // namespace octray::kernels::OCTRAY_ISA
