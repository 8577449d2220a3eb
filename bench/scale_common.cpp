// bench/scale_common.cpp — see scale_common.hpp.
#include "scale_common.hpp"

#include "embree_spheres.hpp"
#include "mesh_generators.hpp"
#include "model_loader.hpp"
#include "kernels/scene_data.hpp"

#include <octray/constants.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>

namespace octray::scale {

struct UserData : bench::UserSpheres {};

World::World() = default;
World::World(World&&) noexcept = default;
World::~World() {
    for (auto& [key, s] : embree)
        if (s) rtcReleaseScene(s);
}

const char* family_name(Family f) {
    return f == Family::spheres ? "spheres" : f == Family::heightfield ? "heightfield" : "model";
}

std::string model_path() { return "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"; }

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

Scene base_scene(int image, const Vec3d& eye, const Vec3d& look_at) {
    Scene s;
    s.camera.eye = eye;
    s.camera.look_at = look_at;
    s.camera.fov_y = 45;
    s.camera.width = s.camera.height = image;
    s.materials.push_back(Material{"m", 0.3, 0.7, {0.8, 0.6, 0.4}});
    return s;
}

Scene mesh_scene(MeshData m, int image, bool terrain) {
    Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const Vec3d& v : m.vertices)
        lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)},
        hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    const Vec3d c{(lo.x + hi.x) / 2, (lo.y + hi.y) / 2, (lo.z + hi.z) / 2};
    const double d = std::sqrt((hi.x - lo.x) * (hi.x - lo.x) + (hi.y - lo.y) * (hi.y - lo.y) + (hi.z - lo.z) * (hi.z - lo.z));
    // A terrain seen from above and in front; a model from the front, a little above and to the side.
    const Vec3d dir = terrain ? Vec3d{0, 0.55, 1} : Vec3d{0.4, 0.5, 1};
    const double k = (terrain ? 0.85 : 0.8) * d / std::sqrt(dir.x * dir.x + dir.y * dir.y + dir.z * dir.z);
    Scene s = base_scene(image, {c.x + dir.x * k, c.y + dir.y * k, c.z + dir.z * k},
                         {c.x, terrain ? lo.y : c.y, c.z});
    Mesh mesh;
    mesh.vertices = std::move(m.vertices);
    mesh.indices = std::move(m.indices);
    s.meshes.push_back(std::move(mesh));
    return s;
}

// A counter-based uniform in [0, 1) (SplitMix64 of key).
double uniform(std::uint64_t key) {
    std::uint64_t z = key + 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return double(z >> 11) * 0x1p-53;
}

void finish_rays(Rays& r) {
    r.e8.resize(r.packets.size());
    r.valid8.resize(r.packets.size());
    r.e1.clear();
    r.active = 0;
    for (std::size_t k = 0; k < r.packets.size(); ++k) {
        bench::to_embree(r.packets[k], k, r.e8[k], r.valid8[k], r.e1);
        for (int i = 0; i < 8; ++i) r.active += r.packets[k].active[i] != 0;
    }
}

Rays camera_rays(const PacketScene& scene) {
    Rays r;
    const Kernel k = select_kernel(scene, Path::simd);
    for (int y = 0; y < scene.height(); ++y)
        for (int x0 = 0; x0 < scene.width(); x0 += 8) {
            r.packets.emplace_back();
            k.camera(scene, x0, y, r.packets.back());
            for (int i = 0; i < 8; ++i) r.pixel.push_back(r.packets.back().active[i] ? std::int64_t(y) * scene.width() + x0 + i : -1);
        }
    finish_rays(r);
    return r;
}

Rays incoherent_rays(const PacketScene& scene, const Rays& cam, float size) {
    Rays r;
    const Kernel k = select_kernel(scene, Path::simd);
    RayPacket8 out{};
    int fill = 0;
    auto flush = [&] {
        for (int i = fill; i < 8; ++i) {
            out.ox[i] = out.oy[i] = out.oz[i] = 0, out.dx[i] = 1, out.dy[i] = out.dz[i] = 0;
            out.tmin[i] = 0, out.tmax[i] = size, out.active[i] = 0;
            r.pixel.push_back(-1);
        }
        r.packets.push_back(out);
        fill = 0;
    };
    for (std::size_t p = 0; p < cam.packets.size(); ++p) {
        const RayPacket8& c = cam.packets[p];
        HitPacket8 h;
        k.intersect(scene, c, h);
        for (int i = 0; i < 8; ++i) {
            if (!c.active[i] || !h.hit[i]) continue;
            const double t = h.t[i];
            const double n[3] = {h.nx[i], h.ny[i], h.nz[i]};
            // An orthonormal basis about n (Duff et al. 2017).
            const double sgn = std::copysign(1.0, n[2]), a = -1.0 / (sgn + n[2]), b = n[0] * n[1] * a;
            const double t1[3] = {1 + sgn * n[0] * n[0] * a, sgn * b, -sgn * n[0]};
            const double t2[3] = {b, sgn + n[1] * n[1] * a, -n[1]};
            const std::uint64_t key = std::uint64_t(cam.pixel[p * 8 + std::size_t(i)]) * 2;
            const double u1 = uniform(key), u2 = uniform(key + 1);
            const double rr = std::sqrt(u1), phi = 2 * kPi * u2, z = std::sqrt(std::max(0.0, 1 - u1));
            const double lx = rr * std::cos(phi), ly = rr * std::sin(phi);
            const double off = 1e-4 * size;
            out.ox[fill] = float(c.ox[i] + c.dx[i] * t + n[0] * off);
            out.oy[fill] = float(c.oy[i] + c.dy[i] * t + n[1] * off);
            out.oz[fill] = float(c.oz[i] + c.dz[i] * t + n[2] * off);
            out.dx[fill] = float(lx * t1[0] + ly * t2[0] + z * n[0]);
            out.dy[fill] = float(lx * t1[1] + ly * t2[1] + z * n[1]);
            out.dz[fill] = float(lx * t1[2] + ly * t2[2] + z * n[2]);
            out.tmin[fill] = 0, out.tmax[fill] = size, out.active[fill] = -1;
            r.pixel.push_back(cam.pixel[p * 8 + std::size_t(i)]);
            if (++fill == 8) flush();
        }
    }
    if (fill) flush();
    finish_rays(r);
    return r;
}

std::atomic<std::int64_t> g_embree_bytes{0};

bool on_memory(void*, ssize_t bytes, bool) {
    g_embree_bytes += bytes;
    return true;
}

void on_error(void*, RTCError code, const char* message) {
    std::fprintf(stderr, "embree: error %d: %s\n", int(code), message ? message : "");
}

template <class V>
std::size_t held(const V& v) {
    return v.capacity() * sizeof(typename V::value_type);
}

}  // namespace

Scene make_scene(Family f, int n, int image) {
    if (f == Family::spheres) {
        Scene s = base_scene(image, {0, 3, 14}, {0, 0, 0});
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> pos(-4, 4), rad(0.5, 1.0);
        const double r = 4.0 / std::cbrt(double(n));
        s.objects.reserve(std::size_t(n));
        for (int i = 0; i < n; ++i) {
            const double x = pos(rng), y = pos(rng), z = pos(rng);
            s.objects.push_back(Object{Sphere{{x, y, z}, r * rad(rng)}, 0});
        }
        return s;
    }
    if (f == Family::heightfield) {
        const int k = std::max(1, int(std::lround(std::sqrt(n / 2.0))));
        MeshData m = height_field(k);
        for (Vec3d& v : m.vertices) v = {4 * v.x, 4 * v.y, 4 * v.z};
        return mesh_scene(std::move(m), image, true);
    }
    return mesh_scene(load_model(model_path()), image, false);
}

CompileOptions compile_options() {
    CompileOptions o;
    if (const char* v = std::getenv("OCTRAY_SCALE_LEAF")) o.sah.max_leaf_size = std::atoi(v);
    if (const char* v = std::getenv("OCTRAY_SCALE_ICOST")) o.sah.intersection_cost = float(std::atof(v));
    if (const char* v = std::getenv("OCTRAY_SCALE_TCOST")) o.sah.traversal_cost = float(std::atof(v));
    if (const char* v = std::getenv("OCTRAY_SCALE_BLOCK")) o.sah.leaf_block = std::atoi(v);
    return o;
}

World& world(Family f, int n, int image) {
    static std::map<std::tuple<int, int, int>, std::unique_ptr<World>> cache;
    auto& slot = cache[{int(f), n, image}];
    if (slot) return *slot;
    slot = std::make_unique<World>();
    World& w = *slot;
    w.family = f;
    w.authored = make_scene(f, n, image);
    w.scene = compile(w.authored, compile_options());
    w.primitives = w.scene.primitive_count();
    w.name = std::string(family_name(f)) + ":" + std::to_string(f == Family::model ? w.primitives : n);
    const bvh::Box& b = scene_data(w.scene).bvh.bounds;
    w.size = std::sqrt((b.hi[0] - b.lo[0]) * (b.hi[0] - b.lo[0]) + (b.hi[1] - b.lo[1]) * (b.hi[1] - b.lo[1]) +
                       (b.hi[2] - b.lo[2]) * (b.hi[2] - b.lo[2]));
    if (f == Family::spheres) {
        w.user = std::make_unique<UserData>();
        for (const Object& o : w.authored.objects) {
            const Sphere& s = std::get<Sphere>(o.shape);
            w.xyzr.insert(w.xyzr.end(), {float(s.center.x), float(s.center.y), float(s.center.z), float(s.radius)});
        }
        w.user->xyzr = w.xyzr;
    } else {
        const Mesh& m = w.authored.meshes.at(0);
        for (const Vec3d& v : m.vertices) w.verts.insert(w.verts.end(), {float(v.x), float(v.y), float(v.z)});
        w.tris.assign(m.indices.begin(), m.indices.end());
    }
    w.camera = camera_rays(w.scene);
    w.incoherent = incoherent_rays(w.scene, w.camera, w.size);
    return w;
}

bool is_mesh(const World& w) { return w.family != Family::spheres; }

RTCDevice device() {
    static RTCDevice d = [] {
        RTCDevice dev = rtcNewDevice("threads=1");
        if (dev) {
            rtcSetDeviceErrorFunction(dev, on_error, nullptr);
            rtcSetDeviceMemoryMonitorFunction(dev, on_memory, nullptr);
        }
        return dev;
    }();
    return d;
}

std::int64_t embree_bytes_now() { return g_embree_bytes.load(); }

RTCScene build_embree(const World& w, bool user, RTCBuildQuality quality, double* commit_seconds) {
    RTCDevice dev = device();
    if (!dev) return nullptr;
    RTCScene scene = rtcNewScene(dev);
    rtcSetSceneBuildQuality(scene, quality);
    RTCGeometry g;
    if (is_mesh(w)) {
        g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), w.verts.size() / 3));
        std::memcpy(v, w.verts.data(), w.verts.size() * sizeof(float));
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), w.tris.size() / 3));
        std::memcpy(idx, w.tris.data(), w.tris.size() * sizeof(unsigned));
    } else if (user) {
        g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(g, unsigned(w.xyzr.size() / 4));
        rtcSetGeometryUserData(g, w.user.get());
        rtcSetGeometryBoundsFunction(g, bench::user_bounds, nullptr);
        rtcSetGeometryIntersectFunction(g, bench::user_intersect);
        rtcSetGeometryOccludedFunction(g, bench::user_occluded);
    } else {
        g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                              4 * sizeof(float), w.xyzr.size() / 4));
        std::memcpy(v, w.xyzr.data(), w.xyzr.size() * sizeof(float));
    }
    rtcSetGeometryBuildQuality(g, quality);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(scene, g, 0);
    rtcReleaseGeometry(g);
    const auto t0 = std::chrono::steady_clock::now();
    rtcCommitScene(scene);
    if (commit_seconds) *commit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return scene;
}

RTCScene embree_scene(World& w, bool user) {
    const int key = is_mesh(w) ? 0 : int(user);
    if (auto it = w.embree.find(key); it != w.embree.end()) return it->second;
    return w.embree[key] = build_embree(w, user, RTC_BUILD_QUALITY_HIGH);
}

std::size_t octray_bytes(const PacketScene& scene) {
    const SceneData& d = scene_data(scene);
    std::size_t b = d.bvh.bytes();
    const auto& s = d.spheres;
    for (const Floats* f : {&s.cx, &s.cy, &s.cz, &s.radius, &s.cx_lo, &s.cy_lo, &s.cz_lo}) b += held(*f);
    for (const auto* q : {&s.cx_q, &s.cy_q, &s.cz_q}) b += held(*q);
    b += held(d.triangles.block_of);  // the blocks themselves are in the BVH's node array
    const PrimitiveOwners& o = d.owners;
    for (const Floats* f : {&o.material_of, &o.mesh_first, &o.mesh_material}) b += held(*f);
    b += d.object_of.bytes() + d.compiled_of.bytes();
    return b;
}

Work make_work(const Rays& r) {
    Work w;
    w.e8 = r.e8;
    w.e1 = r.e1;
    w.occ.resize(r.packets.size() * 8);
    w.hits.resize(r.packets.size());
    return w;
}

void pass_octray(const Kernel& k, const PacketScene& s, const Rays& r, Work& w, bool any) {
    const std::size_t n = r.packets.size();
    if (any)
        for (std::size_t p = 0; p < n; ++p) k.occluded(s, r.packets[p], &w.occ[p * 8]);
    else
        for (std::size_t p = 0; p < n; ++p) k.intersect(s, r.packets[p], w.hits[p]);
}

namespace {
RTCIntersectContext context(bool coherent) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    return ctx;
}
}  // namespace

void pass_embree8(RTCScene scene, const Rays& r, Work& w, bool any, bool coherent) {
    RTCIntersectContext ctx = context(coherent);
    const std::size_t n = w.e8.size();
    for (std::size_t k = 0; k < n; ++k) {
        RTCRayHit8& e = w.e8[k];
        std::memcpy(e.ray.tfar, r.e8[k].ray.tfar, sizeof e.ray.tfar);
        if (any) {
            rtcOccluded8(r.valid8[k].data(), scene, &ctx, &e.ray);
        } else {
            for (int i = 0; i < 8; ++i) e.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect8(r.valid8[k].data(), scene, &ctx, &e);
        }
    }
}

void pass_embree1(RTCScene scene, const Rays& r, Work& w, bool any, bool coherent) {
    RTCIntersectContext ctx = context(coherent);
    const std::size_t n = w.e1.size();
    for (std::size_t k = 0; k < n; ++k) {
        if (r.pixel[k] < 0) continue;
        RTCRayHit& e = w.e1[k];
        e.ray.tfar = r.e1[k].ray.tfar;
        if (any) {
            rtcOccluded1(scene, &ctx, &e.ray);
        } else {
            e.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &e);
        }
    }
}

Answers closest(World& w, const Rays& r, Engine e, bool user) {
    Answers a;
    Work work = make_work(r);
    const std::size_t lanes = r.packets.size() * 8;
    a.prim.assign(lanes, -1);
    a.t.assign(lanes, kInf);
    if (e == Engine::octray_simd || e == Engine::octray_scalar) {
        const Kernel k = select_kernel(w.scene, e == Engine::octray_simd ? Path::simd : Path::scalar);
        pass_octray(k, w.scene, r, work, false);
        for (std::size_t l = 0; l < lanes; ++l) {
            const HitPacket8& h = work.hits[l / 8];
            if (r.pixel[l] >= 0 && h.hit[l % 8]) a.prim[l] = h.primitive[l % 8], a.t[l] = h.t[l % 8];
        }
        return a;
    }
    RTCScene s = embree_scene(w, user);
    if (!s) throw std::runtime_error("no Embree scene");
    const bool coherent = &r == &w.camera;
    if (e == Engine::embree8) pass_embree8(s, r, work, false, coherent);
    else pass_embree1(s, r, work, false, coherent);
    for (std::size_t l = 0; l < lanes; ++l) {
        if (r.pixel[l] < 0) continue;
        const unsigned geom = e == Engine::embree8 ? work.e8[l / 8].hit.geomID[l % 8] : work.e1[l].hit.geomID;
        if (geom == RTC_INVALID_GEOMETRY_ID) continue;
        a.prim[l] = int(e == Engine::embree8 ? work.e8[l / 8].hit.primID[l % 8] : work.e1[l].hit.primID);
        a.t[l] = e == Engine::embree8 ? work.e8[l / 8].ray.tfar[l % 8] : work.e1[l].ray.tfar;
    }
    return a;
}

std::vector<int> occluded(World& w, const Rays& r, Engine e, bool user) {
    Work work = make_work(r);
    const std::size_t lanes = r.packets.size() * 8;
    std::vector<int> out(lanes, -1);
    if (e == Engine::octray_simd || e == Engine::octray_scalar) {
        const Kernel k = select_kernel(w.scene, e == Engine::octray_simd ? Path::simd : Path::scalar);
        pass_octray(k, w.scene, r, work, true);
        for (std::size_t l = 0; l < lanes; ++l)
            if (r.pixel[l] >= 0) out[l] = work.occ[l] != 0;
        return out;
    }
    RTCScene s = embree_scene(w, user);
    if (!s) throw std::runtime_error("no Embree scene");
    const bool coherent = &r == &w.camera;
    if (e == Engine::embree8) pass_embree8(s, r, work, true, coherent);
    else pass_embree1(s, r, work, true, coherent);
    for (std::size_t l = 0; l < lanes; ++l) {
        if (r.pixel[l] < 0) continue;
        const float tfar = e == Engine::embree8 ? work.e8[l / 8].ray.tfar[l % 8] : work.e1[l].ray.tfar;
        out[l] = tfar == -kInf;
    }
    return out;
}

}  // namespace octray::scale
