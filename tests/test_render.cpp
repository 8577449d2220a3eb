// The packet render (scalar and SIMD paths, every ISA unit) against the double
// reference, scene by scene of scenes/.
#include <doctest/doctest.h>

#include "scene_files.hpp"
#include "support.hpp"

#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/kernels.hpp>
#include <octray/reference.hpp>

#include <string>
#include <vector>

using namespace octray;
using namespace octray::test;

TEST_CASE("every scene in scenes/ agrees with the reference on the scalar and SIMD paths, on every ISA") {
    const Tolerance tol;
    for_each_scene_file([&](const Scene&, const PacketScene& packet, const ReferenceRender& ref) {
        std::vector<PacketRender> renders;
        for (Isa isa : simd_isas()) {
            for (Path path : {Path::scalar, Path::simd}) {
                const Kernel k = select_kernel(packet, path, Precision::exact, isa);
                CAPTURE(k.name());
                if (isa != Isa::best) CHECK(std::string(k.isa) == isa_name(isa));
                const PacketRender& out = renders.emplace_back(render_packet(k, packet));
                const Agreement a = compare(ref, out.radiance, out.primitive);
                CHECK(a.nonfinite == 0);
                CHECK(a.max_scaled <= tol.scaled_error);
                CHECK(a.mismatched == a.mismatched_silhouette);
                CHECK(double(a.mismatched) <= tol.silhouette_fraction * double(a.lanes));
                CHECK(a.within(tol));
                CHECK(out.counters.masked == 0);
            }
        }
        // Same kernel, same operations, same order: both paths on every ISA agree to the bit.
        for (std::size_t i = 1; i < renders.size(); ++i) {
            CAPTURE(i);
            CHECK(renders[0].radiance.rgb == renders[i].radiance.rgb);
            CHECK(renders[0].primitive == renders[i].primitive);
        }
    });
}
