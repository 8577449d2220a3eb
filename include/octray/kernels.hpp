// octray/kernels.hpp — the packet kernels' entry points and run-time dispatch.
//
// A Kernel is a table of functions for one (path, precision, feature variant,
// ISA) choice. Obtain one with select_kernel() for a compiled scene, then call
// its stages on your own packets:
//
//     octray::PacketScene scene = octray::compile(authoring_scene);
//     octray::Kernel k = octray::select_kernel(scene, octray::Path::simd);
//     int masked = k.intersect(scene, rays, hits);   // lanes masked off for bad input
//     k.intersect_fields(scene, rays, hits, fields);   // the same, plus u, v and the geometric normal
//     k.shade(scene, rays, hits, radiance);            // HDR radiance
//     k.tonemap(scene, radiance, display);             // display colour in [0,1]
//     k.tonemap_group(scene, radiance_array, display_array, n);  // n packets: n tonemap calls' bits
//
// All stages are noexcept, allocate nothing, touch no global state and only
// read the PacketScene, so any number of threads may share one scene.
#pragma once

#include <octray/features.hpp>
#include <octray/image.hpp>
#include <octray/packet.hpp>
#include <octray/packet_scene.hpp>
#include <octray/precision.hpp>

#include <cstdint>
#include <string>

namespace octray {

enum class Path {
    scalar,  // the kernel at one float lane, run lane by lane: the speed baseline
    simd,    // the same kernel at 8 float lanes, one ymm register, built for AVX2 + FMA and for
             // AVX-512 F+VL (see Isa: the CPU's best unless pinned); Precision::f64: 8 double
             // lanes (two ymm registers on AVX2, one zmm on AVX-512)
};
inline constexpr const char* path_name(Path p) { return p == Path::scalar ? "scalar" : "simd"; }

// The instruction set a kernel is compiled for. `best` is the first this CPU
// runs of avx512 (AVX-512 F+VL: the same 8-lane ymm code with 32 registers,
// and the 14-bit estimate modes), avx2 (AVX2 + FMA) and generic (baseline
// x86-64, scalar path only). Asking for one the CPU lacks gives `best`
// instead, and Kernel::isa names what was given. Both paths of a comparison
// get the same ISA, so a SIMD/scalar ratio compares the same flags.
enum class Isa { best, avx512, avx2, generic };
inline constexpr const char* isa_name(Isa i) {
    return i == Isa::avx512 ? "avx512" : i == Isa::avx2 ? "avx2" : i == Isa::generic ? "generic" : "best";
}

using IntersectFn = int (*)(const PacketScene&, const RayPacket8&, HitPacket8&) noexcept;
using IntersectFieldsFn = int (*)(const PacketScene&, const RayPacket8&, HitPacket8&, HitFields8&) noexcept;
using OccludedFn = void (*)(const PacketScene&, const RayPacket8&, std::int32_t* occluded) noexcept;
using ShadeFn = void (*)(const PacketScene&, const RayPacket8&, const HitPacket8&, ColorPacket8&) noexcept;
using TonemapFn = void (*)(const PacketScene&, const ColorPacket8&, ColorPacket8&) noexcept;
using CameraFn = void (*)(const PacketScene&, int x0, int y, RayPacket8&) noexcept;
using TonemapGroupFn = void (*)(const PacketScene&, const ColorPacket8* in, ColorPacket8* out, int count) noexcept;

struct Kernel {
    IntersectFn intersect = nullptr;  // closest hit; returns lanes masked off (active but invalid)
    // intersect's hits, bit for bit, and the fields a caller asks for
    // (HitFields8: u, v, the geometric normal); always the general variant of
    // the kernel's path, precision and ISA, whatever the scene's features.
    IntersectFieldsFn intersect_fields = nullptr;
    OccludedFn occluded = nullptr;    // any hit in (tmin, tmax); occluded[i] = -1 or 0
    ShadeFn shade = nullptr;          // HDR radiance; misses and inactive lanes get the background
    TonemapFn tonemap = nullptr;      // scene's tone map and gamma; NaN/inf map into gamut
    TonemapGroupFn tonemap_group = nullptr;  // tonemap of in[0..count) into out[]; two packets' work interleaved
    CameraFn camera = nullptr;        // pixels (x0..x0+7, y); lanes past the width are inactive
    Path path = Path::simd;
    Precision precision = Precision::exact;
    const char* isa = "";             // instruction set the code was compiled for
    unsigned primitive_bits = 0;      // primitive types compiled into intersect
    unsigned light_bits = 0;          // light features compiled into shade

    std::string name() const;         // e.g. "simd/avx512/exact [sphere+plane | directional]"
};

// Kernel specialized to exactly the scene's features (see features.hpp);
// exact precision only: the other modes (precision.hpp) always run the
// general kernel. Path::simd needs AVX2+FMA at run time; without them it
// returns the scalar path's kernel and says so in Kernel::isa ("generic"),
// never silently. fast14/approx14 need AVX-512 F+VL; without it the kernel
// is the `fast` one and Kernel::precision says so (`fast` meets approx14's
// bounds, and fast14's within a factor 2: precision.hpp). `isa` pins the
// instruction set (see Isa; e.g. avx2 on a CPU that slows its clock for
// AVX-512 code, or to compare the two).
Kernel select_kernel(const PacketScene& scene, Path path, Precision precision = Precision::exact, Isa isa = Isa::best);
// The kernel compiled with every feature, whatever the scene uses.
Kernel general_kernel(Path path, Precision precision = Precision::exact, Isa isa = Isa::best);
// True when this CPU runs the AVX2+FMA code.
bool simd_supported();
// True when this CPU runs the AVX-512 F+VL code (preferred for every mode; fast14, approx14 need it).
bool avx512_supported();
// True when this CPU runs `precision` as asked (no fallback).
bool precision_supported(Precision precision);

}  // namespace octray
