// bench/embree_spheres.hpp — spheres as Embree user geometry, for the Embree
// peers (bench_embree.cpp: closest hit; bench_aobench.cpp: occlusion). The
// test is octray's stable quadratic (kernels/sphere.hpp, without its
// compensated and rescaled paths): one lane, and eight with AVX2 + FMA for
// when Embree hands the callback a packet.
#pragma once

#include <embree3/rtcore.h>
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
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

// One ray against sphere c = (x, y, z, r): the hit t in (tnear, tfar), and f = o - centre; false on a miss.
struct SphereHit1 {
    float t, fx, fy, fz;
};
inline bool sphere_hit1(const float* c, const float o[3], const float d[3], float tnear, float tfar, SphereHit1& h) {
    const float fx = o[0] - c[0], fy = o[1] - c[1], fz = o[2] - c[2], r2 = c[3] * c[3];
    const float b = fx * d[0] + fy * d[1] + fz * d[2], dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const float inv_dd = 1.0f / dd, s = b * inv_dd;
    const float px = fx - d[0] * s, py = fy - d[1] * s, pz = fz - d[2] * s;
    const float disc = r2 - (px * px + py * py + pz * pz);
    if (!(disc >= 0.0f)) return false;
    const float sd = std::sqrt(disc * dd);
    const float cc = fx * fx + fy * fy + fz * fz - r2;
    const float q = -(b + std::copysign(sd, b));
    const float t0 = q * inv_dd, t1 = cc / q;
    const float tn = std::min(t0, t1), tf = std::max(t0, t1);
    const float t = tn > tnear ? tn : tf;
    if (!(t > tnear && t < tfar)) return false;
    h = {t, fx, fy, fz};
    return true;
}

// Eight rays (an RTCRay8's, lanes of `valid`) against sphere c: the hit mask
// and t, and f = o - centre.
struct SphereHit8 {
    __m256 hit, t, fx, fy, fz;
};
__attribute__((target("avx2,fma"))) inline SphereHit8 sphere_hit8(const float* c, const RTCRay8& ray, __m256 valid) {
    const __m256 dx = _mm256_load_ps(ray.dir_x), dy = _mm256_load_ps(ray.dir_y), dz = _mm256_load_ps(ray.dir_z);
    const __m256 fx = _mm256_sub_ps(_mm256_load_ps(ray.org_x), _mm256_set1_ps(c[0]));
    const __m256 fy = _mm256_sub_ps(_mm256_load_ps(ray.org_y), _mm256_set1_ps(c[1]));
    const __m256 fz = _mm256_sub_ps(_mm256_load_ps(ray.org_z), _mm256_set1_ps(c[2]));
    const __m256 r2 = _mm256_set1_ps(c[3] * c[3]);
    const __m256 b = _mm256_fmadd_ps(fx, dx, _mm256_fmadd_ps(fy, dy, _mm256_mul_ps(fz, dz)));
    const __m256 dd = _mm256_fmadd_ps(dx, dx, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dz, dz)));
    const __m256 inv_dd = _mm256_div_ps(_mm256_set1_ps(1.0f), dd);
    const __m256 sb = _mm256_mul_ps(b, inv_dd);
    const __m256 px = _mm256_fnmadd_ps(dx, sb, fx), py = _mm256_fnmadd_ps(dy, sb, fy), pz = _mm256_fnmadd_ps(dz, sb, fz);
    const __m256 disc = _mm256_sub_ps(r2, _mm256_fmadd_ps(px, px, _mm256_fmadd_ps(py, py, _mm256_mul_ps(pz, pz))));
    const __m256 any = _mm256_and_ps(valid, _mm256_cmp_ps(disc, _mm256_setzero_ps(), _CMP_GE_OQ));
    if (_mm256_movemask_ps(any) == 0) return {any, any, fx, fy, fz};
    const __m256 sd = _mm256_sqrt_ps(_mm256_max_ps(_mm256_mul_ps(disc, dd), _mm256_setzero_ps()));
    const __m256 cc = _mm256_sub_ps(_mm256_fmadd_ps(fx, fx, _mm256_fmadd_ps(fy, fy, _mm256_mul_ps(fz, fz))), r2);
    const __m256 sign = _mm256_set1_ps(-0.0f);
    const __m256 q = _mm256_xor_ps(_mm256_add_ps(b, _mm256_or_ps(sd, _mm256_and_ps(b, sign))), sign);
    const __m256 t0 = _mm256_mul_ps(q, inv_dd), t1 = _mm256_div_ps(cc, q);
    const __m256 tn = _mm256_min_ps(t0, t1), tf = _mm256_max_ps(t0, t1);
    const __m256 tmin = _mm256_load_ps(ray.tnear), tmax = _mm256_load_ps(ray.tfar);
    const __m256 t = _mm256_blendv_ps(tf, tn, _mm256_cmp_ps(tn, tmin, _CMP_GT_OQ));
    const __m256 hit = _mm256_and_ps(_mm256_and_ps(any, _mm256_cmp_ps(t, tmin, _CMP_GT_OQ)), _mm256_cmp_ps(t, tmax, _CMP_LT_OQ));
    return {hit, t, fx, fy, fz};
}

// An Embree `valid` array of 8 as a lane mask.
__attribute__((target("avx2,fma"))) inline __m256 valid_mask8(const int* valid) {
    return _mm256_castsi256_ps(
        _mm256_cmpeq_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(valid)), _mm256_set1_epi32(-1)));
}

inline RTCIntersectContext intersect_context(RTCIntersectContextFlags flags) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = flags;
    return ctx;
}

// A scene of build quality HIGH with geometry 0 the spheres, as user
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
