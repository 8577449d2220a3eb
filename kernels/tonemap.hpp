// kernels/tonemap.hpp — HDR radiance to display colour: max_to_one,
// clamp_to_color or saturate, then gamma (docs/shading-model.md, tone mapping).
#pragma once

#include "lane_pow.hpp"
#include "packet_io.hpp"

namespace octray::kernels::OCTRAY_ISA {

// ---- tone mapping (docs/shading-model.md) ---------------------------------
// c^y for c > 0: on float lanes lane_pow.hpp's, the same code on both paths
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
template <class T, Precision P, ToneMap M>
inline void tonemap_lanes(const SceneData& s, const ColorPacket8& in, ColorPacket8& out, int lane) {
    // max(x, 0) flushes NaN to 0 (lane::max returns its second operand on NaN).
    T r = lane::max(load<T>(in.r, lane), T(0));
    T g = lane::max(load<T>(in.g, lane), T(0));
    T b = lane::max(load<T>(in.b, lane), T(0));
    if constexpr (M == ToneMap::max_to_one) {
        const T mx = lane::max(r, lane::max(g, b));
        const Mask<T> over = mx > T(1);
        const Mask<T> infinite = mx == inf<T>();
        const T scale = lane::rcp<P>(lane::select(over && lane::not_(infinite), mx, T(1)));
        auto fix = [&](const T& c) {
            return lane::select(infinite, lane::keep(c == inf<T>(), T(1)), lane::select(over, lane::min(c * scale, T(1)), c));
        };
        r = fix(r), g = fix(g), b = fix(b);
    } else if constexpr (M == ToneMap::clamp_to_color) {
        const Mask<T> over = r > T(1) || g > T(1) || b > T(1);
        r = lane::select(over, T(s.clamp_color[0]), r);
        g = lane::select(over, T(s.clamp_color[1]), g);
        b = lane::select(over, T(s.clamp_color[2]), b);
    } else {
        r = lane::min(r, T(1)), g = lane::min(g, T(1)), b = lane::min(b, T(1));
    }
    if (s.inv_gamma != 1.0f) {
        const T ig(s.inv_gamma);
        // c = 0 computes a finite value that the select drops.
        auto gam = [&](const T& c) { return lane::keep(c > T(0), gamma_pow(c, ig)); };
        r = gam(r), g = gam(g), b = gam(b);
    }
    store(out.r, lane, r);
    store(out.g, lane, g);
    store(out.b, lane, b);
}

template <class T, Precision P>
void tonemap_packet(const PacketScene& scene, const ColorPacket8& in, ColorPacket8& out) noexcept {
    const SceneData& s = scene.data();
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) {
        switch (s.tonemap) {
        case ToneMap::max_to_one: tonemap_lanes<T, P, ToneMap::max_to_one>(s, in, out, lane); break;
        case ToneMap::clamp_to_color: tonemap_lanes<T, P, ToneMap::clamp_to_color>(s, in, out, lane); break;
        case ToneMap::saturate: tonemap_lanes<T, P, ToneMap::saturate>(s, in, out, lane); break;
        }
    }
}

}  // namespace octray::kernels::OCTRAY_ISA
