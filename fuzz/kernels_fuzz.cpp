// fuzz/kernels_fuzz.cpp — the packet kernels on raw bytes (docs/reliability.md): a scene
// whose parameters come from the input (kept only when validate() passes)
// and ray packets that are the input's bytes, through intersect, occluded,
// shade and tonemap of every kernel this CPU runs (every ISA unit, every
// precision mode; exact specialized to the scene's features, as
// select_kernel picks it, the other modes general). Checked
// by tests/support/kernel_checks.hpp: no NaN in any output, the masked-lane count and
// flags exactly those computed independently, hits in range, misses and
// masked lanes shaded as background, display colour in [0, 1].
//
// Input layout (missing bytes read as zero):
//   2 bytes    what the scene has: byte 0 = spheres (bits 0-1, 0..3), boxes
//              (2-3), triangles (4-5), a plane (6), a disk (7); byte 1 = a
//              rectangle (0), ambient (1), a directional light (2), a point
//              light (3), an attenuated point light (4), shadows (5), tone
//              map (6-7: max_to_one, clamp_to_color, saturate, and saturate
//              with an orthographic camera; else the camera is a pinhole)
//   numbers    camera (its width and height one byte each: the size is
//              1 + the low 6 bits; width bit 7 = ambient occlusion, with
//              2^(height bits 6-7) samples), background, gamma, clamp
//              colour, two materials, the lights, each object (material:
//              one byte, then its geometry), then with occlusion its
//              distance and min_amount;
//              a number is a tag byte t then: t < 0x80: (t - 0x40) / 8 (no
//              more bytes); t < 0xe0: 4 bytes, a float's bits; else 8 bytes,
//              a double's bits
//   the rest   up to 4 ray packets of 288 bytes: ox oy oz dx dy dz tmin tmax
//              (8 floats each) and active (8 int32), little-endian; the
//              packet's first 96 bytes also go to tonemap as raw radiance,
//              and the bits of ox are the lanes' pixel (the occlusion key)
#include "kernel_checks.hpp"

#include <octray/kernels.hpp>
#include <octray/packet_scene.hpp>
#include <octray/scene.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

namespace {

using namespace octray;

class Bytes {
  public:
    Bytes(const std::uint8_t* p, std::size_t n) : p_(p), n_(n) {}
    std::uint8_t byte() { return n_ > 0 ? (--n_, *p_++) : 0; }
    template <class U>
    U raw() {
        unsigned char b[sizeof(U)]{};
        for (unsigned char& c : b) c = byte();
        U v;
        std::memcpy(&v, b, sizeof v);
        return v;
    }
    double number() {
        const std::uint8_t t = byte();
        if (t < 0x80) return (int(t) - 0x40) / 8.0;
        if (t < 0xe0) return double(raw<float>());
        return raw<double>();
    }
    Vec3d vec3() {
        const double x = number(), y = number();
        return {x, y, number()};
    }
    std::size_t left() const { return n_; }

  private:
    const std::uint8_t* p_;
    std::size_t n_;
};

Scene make_scene(Bytes& in) {
    const std::uint8_t has = in.byte(), more = in.byte();
    Scene s;
    Camera& c = s.camera;
    c.type = (more & 0x80) != 0 && (more & 0x40) != 0 ? CameraType::orthographic : CameraType::pinhole;
    c.eye = in.vec3(), c.look_at = in.vec3(), c.up = in.vec3();
    c.fov_y = in.number(), c.height_world = in.number();
    const std::uint8_t width = in.byte(), height = in.byte();
    c.width = 1 + width % 64, c.height = 1 + height % 64;
    s.background = in.vec3();
    s.render.tonemap = ToneMap(std::min(2, more >> 6));
    s.render.gamma = in.number();
    s.render.clamp_color = in.vec3();
    for (const char* name : {"a", "b"}) {
        const double ka = in.number(), kd = in.number();
        s.materials.push_back(Material{name, ka, kd, in.vec3()});
    }
    const bool shadows = (more & 0x20) != 0;
    if ((more & 0x02) != 0) {
        const Vec3d color = in.vec3();
        s.ambient = AmbientLight{color, in.number()};
    }
    if ((more & 0x04) != 0) {
        const Vec3d dir = in.vec3(), color = in.vec3();
        s.directional_lights.push_back({dir, color, in.number(), shadows});
    }
    for (const int bit : {0x08, 0x10}) {
        if ((more & bit) == 0) continue;
        const Vec3d pos = in.vec3(), color = in.vec3();
        s.point_lights.push_back(
            {pos, color, in.number(), bit == 0x10 ? Attenuation::inverse_square : Attenuation::none, shadows});
    }
    auto add = [&](auto make) {
        const int material = in.byte() % 2;
        s.objects.push_back(Object{make(), material});
    };
    for (int i = 0; i < (has & 3); ++i) add([&] { const Vec3d c0 = in.vec3(); return Shape{Sphere{c0, in.number()}}; });
    for (int i = 0; i < ((has >> 2) & 3); ++i) add([&] { const Vec3d lo = in.vec3(); return Shape{Box{lo, in.vec3()}}; });
    for (int i = 0; i < ((has >> 4) & 3); ++i)
        add([&] {
            const Vec3d v0 = in.vec3(), v1 = in.vec3();
            return Shape{Triangle{v0, v1, in.vec3()}};
        });
    if ((has & 0x40) != 0) add([&] { const Vec3d p = in.vec3(); return Shape{Plane{p, in.vec3()}}; });
    if ((has & 0x80) != 0)
        add([&] {
            const Vec3d center = in.vec3(), normal = in.vec3();
            return Shape{Disk{center, normal, in.number()}};
        });
    if ((more & 0x01) != 0)
        add([&] {
            const Vec3d corner = in.vec3(), a = in.vec3();
            return Shape{Rectangle{corner, a, in.vec3()}};
        });
    if ((width & 0x80) != 0) {  // without an ambient light, validate() rejects it
        const double distance = in.number();
        s.ambient_occlusion = AmbientOcclusion{1 << (height >> 6), distance, in.number()};
    }
    return s;
}

[[noreturn]] void bug(const std::string& what) {
    std::fprintf(stderr, "kernels_fuzz: %s\n", what.c_str());
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    Bytes in(data, size);
    const Scene scene = make_scene(in);
    PacketScene ps;
    try {
        ps = compile(scene);  // validate()s first
    } catch (const std::invalid_argument&) {
        return 0;  // not a scene the kernels are promised
    }
    const test::SceneFacts facts = test::scene_facts(scene);

    constexpr int kMaxPackets = 4;
    RayPacket8 packets[kMaxPackets];
    ColorPacket8 colours[kMaxPackets];
    int n = 0;
    do {
        RayPacket8& r = packets[n];
        for (float* field : {r.ox, r.oy, r.oz, r.dx, r.dy, r.dz, r.tmin, r.tmax})
            for (int i = 0; i < kPacketWidth; ++i) field[i] = in.raw<float>();
        for (int i = 0; i < kPacketWidth; ++i) r.active[i] = in.raw<std::int32_t>();
        std::memcpy(r.pixel, r.ox, sizeof r.pixel);
        std::memcpy(colours[n].r, r.ox, sizeof r.ox);
        std::memcpy(colours[n].g, r.oy, sizeof r.oy);
        std::memcpy(colours[n].b, r.oz, sizeof r.oz);
        ++n;
    } while (n < kMaxPackets && in.left() > 0);

    for (const Kernel& k : test::every_kernel(ps.features().bits)) {
        for (int p = 0; p < n; ++p) {
            const std::string e = test::run_and_check(k, ps, facts, packets[p], colours[p]);
            if (!e.empty()) bug(k.name() + ", packet " + std::to_string(p) + ": " + e);
        }
        // The scene's own camera rays: first and last tile of the middle row.
        RayPacket8 camera;
        for (const int x0 : {0, (ps.width() - 1) / kPacketWidth * kPacketWidth}) {
            k.camera(ps, x0, ps.height() / 2, camera);
            const std::string e = test::run_and_check(k, ps, facts, camera, colours[0]);
            if (!e.empty()) bug(k.name() + ", camera tile " + std::to_string(x0) + ": " + e);
        }
    }
    return 0;
}
