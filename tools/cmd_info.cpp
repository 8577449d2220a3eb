// tools/cmd_info.cpp — `octray info SCENE`: what the scene uses and which
// kernel variant runs it.
#include "commands.hpp"
#include "scene_loader.hpp"

#include <octray/kernels.hpp>

#include <algorithm>
#include <cstdio>

namespace octray::cli {

int run_info(const InfoArgs& args) {
    const Scene scene = load_scene(args.scene);
    const PacketScene packet = compile(scene);
    const Features& f = packet.features();
    std::printf("scene        %s\n", args.scene.c_str());
    std::printf("image        %dx%d %s\n", scene.camera.width, scene.camera.height,
                camera_type_name(scene.camera.type));
    std::printf("primitives   sphere %d, plane %d, disk %d, rectangle %d, box %d, triangle %d\n",
                packet.count(PrimitiveType::sphere), packet.count(PrimitiveType::plane),
                packet.count(PrimitiveType::disk), packet.count(PrimitiveType::rectangle),
                packet.count(PrimitiveType::box), packet.count(PrimitiveType::triangle));
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
        const Mesh& m = scene.meshes[i];
        Vec3d lo = m.vertices.front(), hi = lo;
        for (const Vec3d& v : m.vertices)
            lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)},
            hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
        std::printf("mesh %-7zu %zu triangles, %zu vertices, %zu degenerate dropped, bounds [%g %g %g] - [%g %g %g]\n", i,
                    m.triangle_count(), m.vertices.size(), m.dropped_degenerate, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
    }
    int attenuated = 0;
    for (const PointLight& l : scene.point_lights) attenuated += l.attenuation == Attenuation::inverse_square;
    std::printf("lights       ambient %s, directional %zu, point %zu, point inverse_square %d\n",
                scene.ambient ? "yes" : "no", scene.directional_lights.size(), scene.point_lights.size() - attenuated,
                attenuated);
    std::printf("features     %s\n", feature_string(f.bits).c_str());
    std::printf("tone map     %s, gamma %s\n", tonemap_name(f.tonemap), f.gamma ? "yes" : "no (1)");
    std::printf("simd         %s\n", !simd_supported()   ? "AVX2+FMA not available: scalar fallback"
                                     : avx512_supported() ? "AVX2+FMA and AVX-512 F+VL available: both paths run the AVX-512 units"
                                                          : "AVX2+FMA available");
    for (Path path : {Path::simd, Path::scalar})
        std::printf("kernel %-6s %s\n", path_name(path), select_kernel(packet, path).name().c_str());
    return kExitOk;
}

}  // namespace octray::cli
