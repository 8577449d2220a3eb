// bench/python_overhead.cpp — the C++ side of scripts/python-overhead: the
// scale benchmark's height field and camera rays (scale_common.hpp), the
// octray SIMD kernel driven from C++ over them, Kernel::intersect into
// HitPacket8s and Kernel::intersect_fields into HitPacket8s and HitFields8s
// (barycentrics and geometric normals: the fields the Python side's
// Scene.intersect returns, its ids being the binding's own work), and
// Embree's rtcIntersect8 / rtcIntersect1 on the same rays, one thread.
// Prints JSON: the seconds of every timed pass (after one warm-up pass each).
//
//   octray_bench_python_overhead --n 1048576 --image 512 --repetitions 15
//   octray_bench_python_overhead --n 8192 --image 64 --dump answers.bin
//
// --dump writes what the script checks the Python module against, bit for
// bit: int64 lanes (active, in packet order), then float32 origins (lanes x 3),
// directions (lanes x 3), t (lanes; inf on a miss) and int32 primitive ids
// (lanes; -1 on a miss), little-endian.
#include "scale_common.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace octray;
using namespace octray::scale;

namespace {

template <class Fn>
std::vector<double> timed(int repetitions, Fn&& fn) {
    fn();  // warm-up
    std::vector<double> s;
    for (int r = 0; r < repetitions; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        fn();
        s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return s;
}

std::string list(const std::vector<double>& v) {
    std::string out = "[";
    char buf[32];
    for (std::size_t i = 0; i < v.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%s%.9g", i ? ", " : "", v[i]);
        out += buf;
    }
    return out + "]";
}

}  // namespace

int main(int argc, char** argv) {
    int n = 1 << 20, image = 512, repetitions = 15;
    std::string dump;
    bool embree = true;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> const char* {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "python_overhead: %s needs a value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--n") n = std::atoi(next());
        else if (a == "--image") image = std::atoi(next());
        else if (a == "--repetitions") repetitions = std::atoi(next());
        else if (a == "--dump") dump = next();
        else if (a == "--no-embree") embree = false;
        else {
            std::fprintf(stderr, "python_overhead: unknown argument %s\n", a.c_str());
            return 2;
        }
    }
    World& w = world(Family::heightfield, n, image);
    const Rays& r = w.camera;
    const Kernel k = select_kernel(w.scene, Path::simd);

    if (!dump.empty()) {
        const Answers ans = closest(w, r, Engine::octray_simd, false);
        std::vector<float> o, d, t;
        std::vector<std::int32_t> prim;
        for (std::size_t l = 0; l < r.pixel.size(); ++l) {
            if (r.pixel[l] < 0) continue;
            const RayPacket8& p = r.packets[l / 8];
            const std::size_t i = l % 8;
            o.insert(o.end(), {p.ox[i], p.oy[i], p.oz[i]});
            d.insert(d.end(), {p.dx[i], p.dy[i], p.dz[i]});
            t.push_back(ans.t[l]);
            prim.push_back(ans.prim[l]);
        }
        std::FILE* f = std::fopen(dump.c_str(), "wb");
        if (!f) {
            std::perror(dump.c_str());
            return 2;
        }
        const std::int64_t lanes = std::int64_t(t.size());
        std::fwrite(&lanes, sizeof lanes, 1, f);
        std::fwrite(o.data(), sizeof(float), o.size(), f);
        std::fwrite(d.data(), sizeof(float), d.size(), f);
        std::fwrite(t.data(), sizeof(float), t.size(), f);
        std::fwrite(prim.data(), sizeof(std::int32_t), prim.size(), f);
        std::fclose(f);
    }

    Work work = make_work(r);
    const std::vector<double> octray_s = timed(repetitions, [&] { pass_octray(k, w.scene, r, work, false); });
    AVec<HitFields8> fields(r.packets.size());
    const std::vector<double> fields_s = timed(repetitions, [&] {
        for (std::size_t p = 0; p < r.packets.size(); ++p) k.intersect_fields(w.scene, r.packets[p], work.hits[p], fields[p]);
    });
    std::vector<double> e8, e1;
    if (embree) {
        if (RTCScene s = embree_scene(w, false)) {
            e8 = timed(repetitions, [&] { pass_embree8(s, r, work, false, true); });
            e1 = timed(repetitions, [&] { pass_embree1(s, r, work, false, true); });
        }
    }
    std::printf("{\"scene\": \"%s\", \"primitives\": %d, \"image\": %d, \"rays\": %lld, \"kernel\": \"%s\",\n"
                " \"octray_simd_seconds\": %s,\n \"octray_fields_seconds\": %s,\n \"embree8_seconds\": %s,\n"
                " \"embree1_seconds\": %s,\n"
                " \"embree_version\": \"%s\"}\n",
                w.name.c_str(), w.primitives, image, (long long)r.active, k.name().c_str(), list(octray_s).c_str(),
                list(fields_s).c_str(), list(e8).c_str(), list(e1).c_str(), RTC_VERSION_STRING);
    return 0;
}
