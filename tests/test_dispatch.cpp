// Run-time dispatch: the ISA unit and the feature variant select_kernel picks.
#include <doctest/doctest.h>

#include "scene_files.hpp"
#include "support.hpp"

#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/kernels.hpp>
#include <octray/reference.hpp>

#include <random>
#include <string>
#include <vector>

using namespace octray;
using namespace octray::test;

namespace {
// The feature bits of the variant dispatch runs for a scene's: its own,
// but with occlusion the ambient-only variant for spheres and planes or the
// general shade (dispatch/isa_instantiate.hpp).
unsigned compiled_bits(unsigned bits) {
    const unsigned lights = bits & ~kAllPrimitives;
    const bool own = lights == (kAmbient | kOcclusion) && (bits & kAllPrimitives & ~(kSphere | kPlane)) == 0;
    if ((bits & kOcclusion) == 0 || own) return bits;
    return (bits & kAllPrimitives) | (kAllFeatures & ~kAllPrimitives);
}
}  // namespace

TEST_CASE("select_kernel's Isa pins the instruction set this CPU runs, and falls back to the best otherwise") {
    const std::vector<std::string> files = scene_files();
    REQUIRE(!files.empty());
    const PacketScene ps = compile(load_scene(files.front()));
    for (Path path : {Path::scalar, Path::simd}) {
        CAPTURE(path_name(path));
        const std::string best = select_kernel(ps, path).isa;
        CHECK(best == (avx512_supported() ? "avx512" : simd_supported() ? "avx2" : "generic"));
        CHECK(std::string(select_kernel(ps, path, Precision::exact, Isa::avx512).isa) ==
              (avx512_supported() ? "avx512" : best));
        CHECK(std::string(select_kernel(ps, path, Precision::exact, Isa::avx2).isa) ==
              (simd_supported() ? "avx2" : best));
        // generic is the scalar path's baseline unit; the SIMD path has none.
        CHECK(std::string(select_kernel(ps, path, Precision::exact, Isa::generic).isa) ==
              (path == Path::scalar ? "generic" : best));
        // fast14 is compiled for AVX-512 only: pinned to avx2 it runs where it is compiled.
        if (avx512_supported())
            CHECK(std::string(general_kernel(path, Precision::fast14, Isa::avx2).isa) == "avx512");
        // Pinned or not, the variant is the scene's.
        const Kernel k = select_kernel(ps, path, Precision::exact, Isa::avx2);
        CHECK((k.primitive_bits | k.light_bits) == compiled_bits(ps.features().bits));
    }
}

TEST_CASE("dispatch picks the variant compiled for exactly the scene's features, for every scene in scenes/") {
    const std::vector<std::string> files = scene_files();
    REQUIRE(!files.empty());
    for (const std::string& file : files) {
        CAPTURE(file);
        const PacketScene ps = compile(load_scene(file));
        for (Path path : {Path::scalar, Path::simd}) {
            const Kernel k = select_kernel(ps, path);
            CHECK((k.primitive_bits | k.light_bits) == compiled_bits(ps.features().bits));
            const bool specialized = k.intersect != general_kernel(path).intersect;
            CHECK(specialized);
        }
    }
}

TEST_CASE("sampled feature variants agree with the reference (each variant on a scene that exercises it)") {
    std::mt19937 rng(7);
    const Tolerance tol;
    unsigned covered = 0;  // every feature bit some sampled variant has
    for (int trial = 0; trial < 48; ++trial) {
        unsigned bits = rng() & kAllFeatures;
        if ((bits & kAllPrimitives) == 0) bits |= kSphere;
        // Shadows need a light that casts them.
        if ((bits & (kDirectional | kPoint | kPointAttenuated)) == 0) bits &= ~kShadows;
        if ((bits & kAmbient) == 0) bits &= ~kOcclusion;  // occlusion occludes the ambient light
        CAPTURE(feature_string(bits));
        const Scene scene = scene_with_features(bits, rng);
        const PacketScene ps = compile(scene);
        REQUIRE(ps.features().bits == bits);
        const ReferenceRender ref = render_reference(scene);
        for (Isa isa : simd_isas()) {
            for (Path path : {Path::scalar, Path::simd}) {
                const Kernel k = select_kernel(ps, path, Precision::exact, isa);
                CAPTURE(k.name());
                CHECK((k.primitive_bits | k.light_bits) == compiled_bits(bits));
                const PacketRender out = render_packet(k, ps);
                const Agreement a = compare(ref, out.radiance, out.primitive);
                CHECK(a.within(tol));
            }
        }
        covered |= bits;
    }
    CHECK(covered == kAllFeatures);
}
