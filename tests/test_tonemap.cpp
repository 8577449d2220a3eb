// tonemap_packet: NaN and infinite radiance map into gamut on every path.
#include <doctest/doctest.h>

#include "support.hpp"

#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/kernels.hpp>
#include <octray/reference.hpp>

#include <cmath>
#include <string>
#include <vector>

using namespace octray;
using namespace octray::test;

TEST_CASE("tone mapping maps NaN and infinite radiance into gamut on every path") {
    Scene scene = one_object_scene(Sphere{{0, 0, 0}, 1});
    for (ToneMap mode : {ToneMap::max_to_one, ToneMap::clamp_to_color, ToneMap::saturate})
        for (double gamma : {1.0, 2.2}) {
            scene.render.tonemap = mode;
            scene.render.gamma = gamma;
            const PacketScene ps = compile(scene);
            for (Path path : {Path::scalar, Path::simd}) {
                const Kernel k = select_kernel(ps, path);
                ColorPacket8 in{}, out{};
                const float special[8][3] = {{NAN, 0.5f, 0.25f}, {INFINITY, 2, 0.5f}, {INFINITY, INFINITY, 0},
                                             {-INFINITY, 0.5f, 0.5f}, {3e38f, 3e38f, 1}, {0.2f, 0.4f, 0.8f},
                                             {2, 4, 8}, {-1, -NAN, 0}};
                for (int i = 0; i < 8; ++i) in.r[i] = special[i][0], in.g[i] = special[i][1], in.b[i] = special[i][2];
                k.tonemap(ps, in, out);
                for (int i = 0; i < 8; ++i) {
                    CAPTURE(i);
                    for (float c : {out.r[i], out.g[i], out.b[i]}) {
                        CHECK(c >= 0.0f);
                        CHECK(c <= 1.0f);
                    }
                    // Finite input: the packet tone map is the reference's, to float rounding.
                    const Vec3d hdr{special[i][0], special[i][1], special[i][2]};
                    if (std::isfinite(hdr.x) && std::isfinite(hdr.y) && std::isfinite(hdr.z) && hdr.x >= 0 && hdr.y >= 0 && hdr.z >= 0) {
                        const Vec3d ref = reference::tonemap(hdr, scene.render);
                        CHECK(std::fabs(out.r[i] - ref.x) <= 1e-6);
                        CHECK(std::fabs(out.g[i] - ref.y) <= 1e-6);
                        CHECK(std::fabs(out.b[i] - ref.z) <= 1e-6);
                    }
                }
            }
        }
}
