"""The benchmarks the summary numbers are read from, and the summary keys with their targets and
definitions (fixed before measuring)."""

E2E = "e2e/default/render_rows"       # render_rows(): camera..tone map + image writes
SHADE = "shade/default"               # scenes/default.json's lights on its own hits
PEAK = "fma_peak/8lanes/chains:12"
PEAK_INTERSECT = "intersect/sphere:256_full_tests/simd"  # every test runs in full: FLOPs = work done
EMBREE8 = ["embree8_native", "embree8_user", "embree8_native_isa_avx2", "embree8_user_isa_avx2"]
EMBREE1 = ["embree1_native", "embree1_user"]
AO_RENDER = "ao/render"              # scenes/aobench.json, whole render (bench/bench_aobench.cpp)
AO_EMBREE8 = ["embree8_native", "embree8_user"]
AO_EMBREE1 = ["embree1_native", "embree1_user"]
TARGETS = {
    "simd_over_scalar_end_to_end": 7.0,
    "simd_over_scalar_shade": 7.5,
    "octray_over_embree_intersect8": 3.0,
    "intersect_fraction_of_peak": 0.5,
    "aobench_simd_over_scalar": 6.2,
    "aobench_occluded_over_embree": 1.0,
}
DEFINITIONS = {
    "simd_over_scalar_end_to_end": f"rays/s of {E2E}/simd over {E2E}/scalar (scenes/default.json, exact, tone-mapped)",
    "simd_over_scalar_shade": f"rays/s of {SHADE}/simd over {SHADE}/scalar",
    "octray_over_embree_intersect8": "min over the sphere scenes of <= 64 spheres of octray_simd rays/s over the "
                                     "fastest Embree rtcIntersect8 variant (native or user spheres, default or avx2 ISA)",
    "intersect_fraction_of_peak": f"GFLOP/s of {PEAK_INTERSECT} (256 nested spheres, culling off, every test runs "
                                  f"in full, FLOPs counted from the code) over {PEAK}",
    "aobench_simd_over_scalar": f"occlusion rays/s of {AO_RENDER}/simd over {AO_RENDER}/scalar (scenes/aobench.json, "
                                "512x512, 64 samples per hit, the whole render)",
    "aobench_occluded_over_embree": "rays/s of ao/occluded/octray_simd (Kernel::occluded) over the faster Embree "
                                    "rtcOccluded8 variant (native or user spheres) on the same occlusion rays "
                                    "(aobench at 256x256)",
}

# The cost curve (--scale): merged into the same summary.json.
SCALE_TARGETS = {
    "scale_camera_octray_over_embree_min": 1.0,
    "scale_incoherent_octray_over_embree_min": 0.8,
    "scale_simd_over_scalar_camera_min": 2.5,
    "scale_build_time_over_embree_max": 1.5,
    "scale_bytes_per_primitive_over_embree_max": 1.0,
}
SCALE_DEFINITIONS = {
    "scale_camera_octray_over_embree_min": "min over every scene of octray_simd rays/s over the fastest Embree "
                                           "variant (rtcIntersect8/1, native or user spheres), camera rays, closest hit",
    "scale_incoherent_octray_over_embree_min": "the same for incoherent rays",
    "scale_simd_over_scalar_camera_min": "min over every scene of octray_simd rays/s over octray_scalar rays/s "
                                         "(the same kernel at one float lane), camera rays, closest hit",
    "scale_build_time_over_embree_max": "max over every scene of octray compile() time over rtcCommitScene at "
                                        "Embree's faster build quality (medium)",
    "scale_bytes_per_primitive_over_embree_max": "max over every scene of octray bytes per primitive (BVH + "
                                                 "per-primitive arrays) over Embree's (device memory monitor, "
                                                 "the smaller of qualities high and medium)",
}
