// bench/embree_spheres.hpp — octray rays as Embree 3 rays (to_embree), and
// spheres as Embree 3 user geometry, with octray's
// stable quadratic (kernels/geometry/sphere.hpp): the callbacks bench_embree.cpp and
// the scale benchmark (bench_scale.cpp) and aobench (bench_aobench.cpp) give
// Embree, closest hit and any hit.
// Eight lanes with AVX2 + FMA when Embree hands the callback a packet of 8
// (and this CPU runs AVX2), one lane at a time otherwise.
//
//     UserSpheres s{{cx, cy, cz, r, ...}};
//     RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
//     rtcSetGeometryUserPrimitiveCount(g, n);
//     rtcSetGeometryUserData(g, &s);
//     rtcSetGeometryBoundsFunction(g, user_bounds, nullptr);
//     rtcSetGeometryIntersectFunction(g, user_intersect);
//     rtcSetGeometryOccludedFunction(g, user_occluded);
#pragma once

#include <octray/kernels.hpp>
#include <octray/packet.hpp>

#include <embree3/rtcore.h>
#include <immintrin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace octray::bench {

struct UserSpheres {
    std::vector<float> xyzr;  // center and radius per sphere
};

inline void user_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* s = static_cast<const UserSpheres*>(args->geometryUserPtr);
    const float* c = &s->xyzr[4 * std::size_t(args->primID)];
    RTCBounds* b = args->bounds_o;
    b->lower_x = c[0] - c[3], b->lower_y = c[1] - c[3], b->lower_z = c[2] - c[3];
    b->upper_x = c[0] + c[3], b->upper_y = c[1] + c[3], b->upper_z = c[2] + c[3];
}

// One lane of the ray array `ray` (N lanes): t of the hit in (tnear, tfar), or
// NaN. `f` receives origin - center (for the normal).
inline float user_sphere_t1(const float* c, RTCRayN* ray, unsigned N, unsigned i, float f[3]) {
    const float ox = RTCRayN_org_x(ray, N, i), oy = RTCRayN_org_y(ray, N, i), oz = RTCRayN_org_z(ray, N, i);
    const float dx = RTCRayN_dir_x(ray, N, i), dy = RTCRayN_dir_y(ray, N, i), dz = RTCRayN_dir_z(ray, N, i);
    const float fx = ox - c[0], fy = oy - c[1], fz = oz - c[2], r2 = c[3] * c[3];
    f[0] = fx, f[1] = fy, f[2] = fz;
    const float b = fx * dx + fy * dy + fz * dz, dd = dx * dx + dy * dy + dz * dz;
    const float inv_dd = 1.0f / dd, s_ = b * inv_dd;
    const float px = fx - dx * s_, py = fy - dy * s_, pz = fz - dz * s_;
    const float disc = r2 - (px * px + py * py + pz * pz);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    if (!(disc >= 0.0f)) return nan;
    const float sd = std::sqrt(disc * dd);
    const float cc = fx * fx + fy * fy + fz * fz - r2;
    const float q = -(b + std::copysign(sd, b));
    const float t0 = q * inv_dd, t1 = cc / q;
    const float tnear = std::min(t0, t1), tfar = std::max(t0, t1);
    const float tmin = RTCRayN_tnear(ray, N, i);
    const float t = tnear > tmin ? tnear : tfar;
    return t > tmin && t < RTCRayN_tfar(ray, N, i) ? t : nan;
}

inline void user_intersect1(const RTCIntersectFunctionNArguments* args, unsigned i) {
    const auto* s = static_cast<const UserSpheres*>(args->geometryUserPtr);
    const float* c = &s->xyzr[4 * std::size_t(args->primID)];
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
    const unsigned N = args->N;
    float f[3];
    const float t = user_sphere_t1(c, ray, N, i, f);
    if (std::isnan(t)) return;
    const float dx = RTCRayN_dir_x(ray, N, i), dy = RTCRayN_dir_y(ray, N, i), dz = RTCRayN_dir_z(ray, N, i);
    RTCRayN_tfar(ray, N, i) = t;
    RTCHitN_Ng_x(hit, N, i) = f[0] + dx * t, RTCHitN_Ng_y(hit, N, i) = f[1] + dy * t, RTCHitN_Ng_z(hit, N, i) = f[2] + dz * t;
    RTCHitN_u(hit, N, i) = 0, RTCHitN_v(hit, N, i) = 0;
    RTCHitN_primID(hit, N, i) = args->primID;
    RTCHitN_geomID(hit, N, i) = args->geomID;
    RTCHitN_instID(hit, N, i, 0) = args->context->instID[0];
}

// dst[i] = v[i] where mask lane i is set.
__attribute__((target("avx2,fma"), always_inline)) inline void put8(float* dst, __m256 v, __m256 mask) {
    _mm256_store_ps(dst, _mm256_blendv_ps(_mm256_load_ps(dst), v, mask));
}
__attribute__((target("avx2,fma"), always_inline)) inline void put8(unsigned* dst, unsigned v, __m256 mask) {
    put8(reinterpret_cast<float*>(dst), _mm256_castsi256_ps(_mm256_set1_epi32(int(v))), mask);
}

// Eight lanes of an RTCRay8 at once, the same arithmetic with AVX2 + FMA:
// the hit mask (zero when none), t in `t_out`, origin - center in f.
__attribute__((target("avx2,fma"))) inline __m256 user_sphere_t8(const float* c, const int* valid_in, const RTCRay8& ray,
                                                                 __m256& t_out, __m256 f[3]) {
    const __m256 valid = _mm256_castsi256_ps(_mm256_cmpeq_epi32(
        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(valid_in)), _mm256_set1_epi32(-1)));
    const __m256 dx = _mm256_load_ps(ray.dir_x), dy = _mm256_load_ps(ray.dir_y), dz = _mm256_load_ps(ray.dir_z);
    const __m256 fx = _mm256_sub_ps(_mm256_load_ps(ray.org_x), _mm256_set1_ps(c[0]));
    const __m256 fy = _mm256_sub_ps(_mm256_load_ps(ray.org_y), _mm256_set1_ps(c[1]));
    const __m256 fz = _mm256_sub_ps(_mm256_load_ps(ray.org_z), _mm256_set1_ps(c[2]));
    f[0] = fx, f[1] = fy, f[2] = fz;
    const __m256 r2 = _mm256_set1_ps(c[3] * c[3]);
    const __m256 b = _mm256_fmadd_ps(fx, dx, _mm256_fmadd_ps(fy, dy, _mm256_mul_ps(fz, dz)));
    const __m256 dd = _mm256_fmadd_ps(dx, dx, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dz, dz)));
    const __m256 inv_dd = _mm256_div_ps(_mm256_set1_ps(1.0f), dd);
    const __m256 sb = _mm256_mul_ps(b, inv_dd);
    const __m256 px = _mm256_fnmadd_ps(dx, sb, fx), py = _mm256_fnmadd_ps(dy, sb, fy), pz = _mm256_fnmadd_ps(dz, sb, fz);
    const __m256 disc = _mm256_sub_ps(r2, _mm256_fmadd_ps(px, px, _mm256_fmadd_ps(py, py, _mm256_mul_ps(pz, pz))));
    const __m256 any = _mm256_and_ps(valid, _mm256_cmp_ps(disc, _mm256_setzero_ps(), _CMP_GE_OQ));
    if (_mm256_movemask_ps(any) == 0) return _mm256_setzero_ps();
    const __m256 sd = _mm256_sqrt_ps(_mm256_max_ps(_mm256_mul_ps(disc, dd), _mm256_setzero_ps()));
    const __m256 cc = _mm256_sub_ps(_mm256_fmadd_ps(fx, fx, _mm256_fmadd_ps(fy, fy, _mm256_mul_ps(fz, fz))), r2);
    const __m256 sign = _mm256_set1_ps(-0.0f);
    const __m256 q = _mm256_xor_ps(_mm256_add_ps(b, _mm256_or_ps(sd, _mm256_and_ps(b, sign))), sign);
    const __m256 t0 = _mm256_mul_ps(q, inv_dd), t1 = _mm256_div_ps(cc, q);
    const __m256 tn = _mm256_min_ps(t0, t1), tf = _mm256_max_ps(t0, t1);
    const __m256 tmin = _mm256_load_ps(ray.tnear), tmax = _mm256_load_ps(ray.tfar);
    const __m256 t = _mm256_blendv_ps(tf, tn, _mm256_cmp_ps(tn, tmin, _CMP_GT_OQ));
    t_out = t;
    return _mm256_and_ps(_mm256_and_ps(any, _mm256_cmp_ps(t, tmin, _CMP_GT_OQ)), _mm256_cmp_ps(t, tmax, _CMP_LT_OQ));
}

__attribute__((target("avx2,fma"))) inline void user_intersect8(const RTCIntersectFunctionNArguments* args) {
    const auto* s = static_cast<const UserSpheres*>(args->geometryUserPtr);
    const float* c = &s->xyzr[4 * std::size_t(args->primID)];
    RTCRayHit8* rh = reinterpret_cast<RTCRayHit8*>(args->rayhit);
    __m256 t, f[3];
    const __m256 hit = user_sphere_t8(c, args->valid, rh->ray, t, f);
    if (_mm256_movemask_ps(hit) == 0) return;
    const __m256 dx = _mm256_load_ps(rh->ray.dir_x), dy = _mm256_load_ps(rh->ray.dir_y), dz = _mm256_load_ps(rh->ray.dir_z);
    put8(rh->ray.tfar, t, hit);
    put8(rh->hit.Ng_x, _mm256_fmadd_ps(dx, t, f[0]), hit);
    put8(rh->hit.Ng_y, _mm256_fmadd_ps(dy, t, f[1]), hit);
    put8(rh->hit.Ng_z, _mm256_fmadd_ps(dz, t, f[2]), hit);
    put8(rh->hit.u, _mm256_setzero_ps(), hit);
    put8(rh->hit.v, _mm256_setzero_ps(), hit);
    put8(rh->hit.primID, args->primID, hit);
    put8(rh->hit.geomID, args->geomID, hit);
    put8(rh->hit.instID[0], args->context->instID[0], hit);
}

inline void user_intersect(const RTCIntersectFunctionNArguments* args) {
    static const bool avx2 = simd_supported();
    if (args->N == 8 && avx2) return user_intersect8(args);
    for (unsigned i = 0; i < args->N; ++i)
        if (args->valid[i] == -1) user_intersect1(args, i);
}

// Any hit: a blocked lane's tfar becomes -inf (Embree's convention).
__attribute__((target("avx2,fma"))) inline void user_occluded8(const RTCOccludedFunctionNArguments* args) {
    const auto* s = static_cast<const UserSpheres*>(args->geometryUserPtr);
    const float* c = &s->xyzr[4 * std::size_t(args->primID)];
    RTCRay8* ray = reinterpret_cast<RTCRay8*>(args->ray);
    __m256 t, f[3];
    const __m256 hit = user_sphere_t8(c, args->valid, *ray, t, f);
    if (_mm256_movemask_ps(hit) != 0) put8(ray->tfar, _mm256_set1_ps(-std::numeric_limits<float>::infinity()), hit);
}

inline void user_occluded(const RTCOccludedFunctionNArguments* args) {
    static const bool avx2 = simd_supported();
    if (args->N == 8 && avx2) return user_occluded8(args);
    const auto* s = static_cast<const UserSpheres*>(args->geometryUserPtr);
    const float* c = &s->xyzr[4 * std::size_t(args->primID)];
    for (unsigned i = 0; i < args->N; ++i) {
        float f[3];
        if (args->valid[i] == -1 && !std::isnan(user_sphere_t1(c, args->ray, args->N, i, f)))
            RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
    }
}

// Embree's copies of one octray packet (packet number k): `e` for
// rtcIntersect8, `valid` its lane mask, and eight RTCRayHit appended to `ones`
// for rtcIntersect1; ray ids k * 8 + lane, geomID invalid.
inline void to_embree(const RayPacket8& r, std::size_t k, RTCRayHit8& e, std::array<int, 8>& valid,
                      std::vector<RTCRayHit>& ones) {
    std::memset(&e, 0, sizeof e);
    for (int i = 0; i < 8; ++i) {
        e.ray.org_x[i] = r.ox[i], e.ray.org_y[i] = r.oy[i], e.ray.org_z[i] = r.oz[i];
        e.ray.dir_x[i] = r.dx[i], e.ray.dir_y[i] = r.dy[i], e.ray.dir_z[i] = r.dz[i];
        e.ray.tnear[i] = r.tmin[i], e.ray.tfar[i] = r.tmax[i];
        e.ray.mask[i] = ~0u, e.ray.id[i] = unsigned(k * 8 + std::size_t(i));
        e.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID, e.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
        valid[std::size_t(i)] = r.active[i] ? -1 : 0;
        RTCRayHit one{};
        one.ray.org_x = r.ox[i], one.ray.org_y = r.oy[i], one.ray.org_z = r.oz[i];
        one.ray.dir_x = r.dx[i], one.ray.dir_y = r.dy[i], one.ray.dir_z = r.dz[i];
        one.ray.tnear = r.tmin[i], one.ray.tfar = r.tmax[i];
        one.ray.mask = ~0u, one.ray.id = e.ray.id[i];
        one.hit.geomID = RTC_INVALID_GEOMETRY_ID, one.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        ones.push_back(one);
    }
}

inline RTCIntersectContext intersect_context(RTCIntersectContextFlags flags) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = flags;
    return ctx;
}

// For bench_aobench.cpp: a scene of build quality HIGH with geometry 0 the spheres, as user
// geometry (with whichever of the callbacks is given) or as Embree's native
// RTC_GEOMETRY_TYPE_SPHERE_POINT, and, when `floor_half` > 0, geometry 1 a
// square quad of that half side in the plane y = floor_y (Embree's native
// quad). Committed; nullptr without a device.
inline RTCScene sphere_scene(RTCDevice dev, UserSpheres& spheres, bool user, RTCIntersectFunctionN intersect,
                             RTCOccludedFunctionN occluded, float floor_y, float floor_half) {
    if (!dev) return nullptr;
    RTCScene scene = rtcNewScene(dev);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    const unsigned n = unsigned(spheres.xyzr.size() / 4);
    RTCGeometry g;
    if (user) {
        g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(g, n);
        rtcSetGeometryUserData(g, &spheres);
        rtcSetGeometryBoundsFunction(g, user_bounds, nullptr);
        if (intersect) rtcSetGeometryIntersectFunction(g, intersect);
        if (occluded) rtcSetGeometryOccludedFunction(g, occluded);
    } else {
        g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), n));
        std::memcpy(v, spheres.xyzr.data(), spheres.xyzr.size() * sizeof(float));
    }
    rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_HIGH);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(scene, g, 0);
    rtcReleaseGeometry(g);
    if (floor_half > 0) {
        RTCGeometry q = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_QUAD);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(q, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4));
        const float h = floor_half, y = floor_y;
        const float corners[12] = {-h, y, -h, -h, y, h, h, y, h, h, y, -h};
        std::memcpy(v, corners, sizeof corners);
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(q, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), 1));
        idx[0] = 0, idx[1] = 1, idx[2] = 2, idx[3] = 3;
        rtcCommitGeometry(q);
        rtcAttachGeometryByID(scene, q, 1);
        rtcReleaseGeometry(q);
    }
    rtcCommitScene(scene);
    return scene;
}

}  // namespace octray::bench
