// kernels/trace/any_hit.hpp — whether anything blocks a ray in (tmin, tmax):
// shadow and occlusion rays (any_hit), and the packet entry point
// occluded_packet. Stops at the first blocker a lane meets.
#pragma once

#include "kernels/trace/primitive_tests.hpp"

namespace octray::kernels::OCTRAY_ISA {

// The valid lanes of `live` blocked in (tmin, tmax). live.valid narrows as
// lanes are blocked (the walk stops when none is left); the ray is the
// caller's, not copied: a copy of the whole Ray costs more than a shadow
// ray's walk.
template <class T, Precision P, unsigned F>
inline Mask<T> any_hit(const SceneData& s, Ray<T, P>& live) {
    const Mask<T> valid = live.valid;
    LaneRay<T, P> lanes(live);
    if constexpr ((F & kPlane) != 0) {
        for (int k = 0; k < s.count[int(PrimitiveType::plane)] && lane::any(live.valid); ++k) {
            Mask<T> hit;
            test_primitive<PrimitiveType::plane, T, P>(s, k, Run{}, live, hit, live.tmax);
            live.valid = live.valid && lane::not_(hit);
        }
    }
    if (lane::any(live.valid))
        for_each_candidate<false, F>(s, live, live.valid, live.tmax, [&](auto tag, int k, const Run& run) OCTRAY_HOT_LAMBDA {
            constexpr PrimitiveType type = decltype(tag)::value;
            Mask<T> hit;
            test_primitive<type, T, P>(s, k, run, live, hit, live.tmax);
            live.valid = live.valid && lane::not_(hit);
        }, [&](auto tag, const Run& run, int i) OCTRAY_HOT_LAMBDA {
            constexpr PrimitiveType type = decltype(tag)::value;
            const Ray<T, P>& one = lanes.at(i, type == PrimitiveType::triangle);
            for (int j = 0; j < run.n; j += lane::width<T>) {
                Mask<T> hit, near;
                test_run<type>(s, run, j, one, hit, one.tmax, near);
                if (lane::any(hit && run_lanes<T>(run.n - j))) {
                    live.valid = live.valid && lane::not_(bvh::detail::lane_alone<T>(i));
                    return;
                }
            }
        });
    return valid && lane::not_(live.valid);
}

template <class T, Precision P, unsigned F>
void occluded_packet(const PacketScene& scene, const RayPacket8& rp, std::int32_t* occluded) noexcept {
    const SceneData& s = scene_data(scene);
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) {
        int masked = 0;
        Ray<T, P> r = load_ray<T, P>(rp, lane, masked);
        store_mask<T>(occluded, lane, any_hit<T, P, F & kAllPrimitives>(s, r));
    }
}

}  // namespace octray::kernels::OCTRAY_ISA
