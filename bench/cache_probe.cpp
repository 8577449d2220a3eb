// bench/cache_probe.cpp — one pass of a cost-curve ray set through one
// engine, for callgrind to count (scripts/cache-per-ray): the world is made
// and one warm-up pass run uncounted, then measured_pass() runs exactly one
// pass, so a callgrind run with --toggle-collect=*measured_pass* counts one
// pass's instructions and cache misses, whatever the engine; the active rays
// are printed to divide by.
//
//   octray_cache_probe SCENE RAYS ENGINE
//     SCENE   spheres:N, heightfield:N or model (the cost curve's families)
//     RAYS    camera | incoherent
//     ENGINE  octray_simd | octray_scalar | embree8 | embree1 (spheres: Embree's native spheres)
//
// Prints "rays N". Exit 2 on bad arguments.
#include "scale_common.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

using namespace octray;
using namespace octray::scale;

constexpr int kImage = 256;  // bench_scale.cpp's image: the same rays

struct Probe {
    World* world;
    const Rays* rays;
    Engine engine;
    bool coherent;
    Kernel kernel;
    RTCScene embree = nullptr;
    Work work;
};

void one_pass(Probe& p) {
    if (p.engine == Engine::octray_simd || p.engine == Engine::octray_scalar)
        pass_octray(p.kernel, p.world->scene, *p.rays, p.work, false);
    else if (p.engine == Engine::embree8)
        pass_embree8(p.embree, *p.rays, p.work, false, p.coherent);
    else
        pass_embree1(p.embree, *p.rays, p.work, false, p.coherent);
}

// The counted pass: out of line, so callgrind's --toggle-collect finds it.
[[gnu::noinline]] void measured_pass(Probe& p) { one_pass(p); }

int usage() {
    std::fprintf(stderr, "usage: octray_cache_probe spheres:N|heightfield:N|model camera|incoherent "
                         "octray_simd|octray_scalar|embree8|embree1\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 4) return usage();
    const std::string scene = argv[1], rays = argv[2], engine = argv[3];
    Family family;
    int n = 0;
    if (scene == "model") {
        family = Family::model;
    } else if (scene.rfind("spheres:", 0) == 0 || scene.rfind("heightfield:", 0) == 0) {
        family = scene[0] == 's' ? Family::spheres : Family::heightfield;
        const std::string count = scene.substr(scene.find(':') + 1);
        const long base = std::atol(count.c_str());
        const char unit = count.empty() ? '\0' : count.back();
        n = int(unit == 'M' ? base << 20 : unit == 'k' ? base << 10 : base);
        if (n <= 0) return usage();
    } else {
        return usage();
    }
    if (rays != "camera" && rays != "incoherent") return usage();
    Probe p;
    if (engine == "octray_simd") p.engine = Engine::octray_simd;
    else if (engine == "octray_scalar") p.engine = Engine::octray_scalar;
    else if (engine == "embree8") p.engine = Engine::embree8;
    else if (engine == "embree1") p.engine = Engine::embree1;
    else return usage();

    World& w = world(family, n, kImage);
    p.world = &w;
    p.rays = rays == "camera" ? &w.camera : &w.incoherent;
    p.coherent = rays == "camera";
    p.work = make_work(*p.rays);
    if (p.engine == Engine::octray_simd || p.engine == Engine::octray_scalar) {
        p.kernel = select_kernel(w.scene, p.engine == Engine::octray_simd ? Path::simd : Path::scalar);
    } else {
        p.embree = embree_scene(w, false);
        if (!p.embree) {
            std::fprintf(stderr, "octray_cache_probe: no Embree scene\n");
            return 1;
        }
    }
    one_pass(p);  // warm-up, uncounted: the counted pass starts from a used cache, as a benchmark's do
    measured_pass(p);
    std::printf("rays %lld\nkernel %s\n", static_cast<long long>(p.rays->active),
                p.engine == Engine::octray_simd || p.engine == Engine::octray_scalar ? p.kernel.name().c_str()
                                                                                     : "embree");
    return 0;
}
