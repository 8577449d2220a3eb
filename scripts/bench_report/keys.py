"""The benchmarks the summary numbers are read from, and the summary keys with their definitions and the
targets of the open issues (fixed before measuring).

A target is (AT_LEAST, x): the key must be >= x, or (AT_MOST, x): <= x. A key no open issue targets has
None: the reports print it with "no target". summary.json holds every target below, as
{"at_least": x} or {"at_most": x}, and every definition, whichever run wrote the file; a key whose value
the summary lacks (PENDING_KEYS, or a run not made) is a target with no value, never an error."""

AT_LEAST, AT_MOST = "at_least", "at_most"

E2E = "e2e/default/render_rows"       # render_rows(): camera..tone map + image writes
SHADE = "shade/default"               # scenes/default.json's lights on its own hits
PEAK = "fma_peak/8lanes/chains:12"
PEAK_INTERSECT = "intersect/sphere:256_full_tests/simd"  # every test runs in full: FLOPs = work done
EMBREE8 = ["embree8_native", "embree8_user", "embree8_native_isa_avx2", "embree8_user_isa_avx2"]
EMBREE1 = ["embree1_native", "embree1_user"]
AO_RENDER = "ao/render"              # scenes/aobench.json, whole render (bench/bench_aobench.cpp)
AO_EMBREE8 = ["embree8_native", "embree8_user"]
AO_EMBREE1 = ["embree1_native", "embree1_user"]

# The everyday run's keys (summary.py), in the order bench.md lists them.
SUITE_KEYS = {
    "simd_over_scalar_end_to_end": None,
    "simd_over_scalar_shade": None,
    "octray_over_embree_intersect8": (AT_LEAST, 1.0),
    "intersect_fraction_of_peak": None,
    "aobench_simd_over_scalar": None,
    "aobench_occluded_over_embree": (AT_LEAST, 2.5),
}

# The cost curve's keys (--scale, scale.py), merged into the same summary.json.
SPHERE_SCENES = ("spheres:",)               # the cost curve's rows by scene name prefix
MESH_SCENES = ("heightfield:", "model")
ANY_HIT_SCENE = "spheres:16"                # closest_over_any_hit_time's row (camera rays)
SCALE_KEYS = {
    "scale_camera_octray_over_embree_min": (AT_LEAST, 1.0),
    "scale_incoherent_octray_over_embree_min": (AT_LEAST, 0.9),
    "scale_camera_spheres_min": (AT_LEAST, 1.0),
    "scale_camera_mesh_min": (AT_LEAST, 1.0),
    "scale_incoherent_mesh_min": (AT_LEAST, 0.8),
    "closest_over_any_hit_time": (AT_MOST, 1.1),
    "scale_simd_over_scalar_camera_min": None,
    "scale_build_time_over_embree_max": (AT_MOST, 1.5),
    "scale_bytes_per_primitive_over_embree_max": (AT_MOST, 1.0),
}

# The counted passes' keys (--counts, counts.py): callgrind on bench/cache_probe.cpp, one case each.
COUNT_LL = "33554432,16,64"                 # --LL: 32 MiB, 16-way, 64-byte lines
COUNT_ENGINES = ["octray_simd", "embree8", "embree1"]
COUNT_CASES = ["heightfield:1M:camera", "heightfield:16k:incoherent"]
COUNT_KEYS = {
    "llc_misses_per_ray_over_embree": (AT_MOST, 1.0),
    "instructions_per_ray_over_embree": (AT_MOST, 1.0),
}

# Targets of the work ahead that no script of bench-report computes yet (python_intersect_over_cpp is
# scripts/python-overhead's): in summary.json's targets and definitions, without a value.
PENDING_KEYS = {
    "record_instructions_per_packet": (AT_MOST, 150),
    "refit_time_over_embree_refit": (AT_MOST, 1.0),
    "refit_time_over_full_build": (AT_MOST, 0.25),
    "instanced_bytes_over_flattened": (AT_MOST, 0.01),
    "instanced_camera_over_embree_instances": (AT_LEAST, 1.0),
    "build_2_threads_over_1": (AT_LEAST, 1.7),
    "render_1M_ply_2_threads_over_1": (AT_LEAST, 1.65),
    "python_intersect_over_cpp": (AT_LEAST, 0.9),
}

TARGETS = {k: t for keys in (SUITE_KEYS, SCALE_KEYS, COUNT_KEYS, PENDING_KEYS) for k, t in keys.items() if t}

_OVER_EMBREE = "octray_simd rays/s over the fastest Embree variant (rtcIntersect8/1, native or user spheres)"
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
    "scale_camera_octray_over_embree_min": "min over every scene of octray_simd rays/s over the fastest Embree "
                                           "variant (rtcIntersect8/1, native or user spheres), camera rays, closest hit",
    "scale_incoherent_octray_over_embree_min": "the same for incoherent rays",
    "scale_camera_spheres_min": f"min over the sphere scenes (spheres:16 to spheres:1M) of {_OVER_EMBREE}, "
                                "camera rays, closest hit",
    "scale_camera_mesh_min": f"min over the mesh scenes (heightfield:1k to heightfield:1M, the model) of {_OVER_EMBREE}, "
                             "camera rays, closest hit",
    "scale_incoherent_mesh_min": f"min over the mesh scenes of {_OVER_EMBREE}, incoherent rays, closest hit",
    "closest_over_any_hit_time": f"time of octray_simd's closest-hit pass over its own any-hit pass on the same rays, "
                                 f"{ANY_HIT_SCENE}, camera rays (the cost curve's rows)",
    "scale_simd_over_scalar_camera_min": "min over every scene of octray_simd rays/s over octray_scalar rays/s "
                                         "(the same kernel at one float lane), camera rays, closest hit",
    "scale_build_time_over_embree_max": "max over every scene of octray compile() time over rtcCommitScene at "
                                        "Embree's faster build quality (medium)",
    "scale_bytes_per_primitive_over_embree_max": "max over every scene of octray bytes per primitive (BVH + "
                                                 "per-primitive arrays) over Embree's (device memory monitor, "
                                                 "the smaller of qualities high and medium)",
    "record_instructions_per_packet": "instructions a packet of the closest-hit record (callgrind, AVX2 unit); "
                                      "not computed by a script yet",
    "llc_misses_per_ray_over_embree": "last-level cache misses a ray of octray_simd over the fewer of Embree's "
                                      "rtcIntersect8 and rtcIntersect1, heightfield:1M camera rays, one pass after a "
                                      "warm-up, callgrind's cache model (--LL=32 MiB, 16-way), AVX2 code on both sides",
    "instructions_per_ray_over_embree": "instructions a ray of octray_simd over the fewer of Embree's rtcIntersect8 and "
                                        "rtcIntersect1, heightfield:16k incoherent rays, one pass after a warm-up "
                                        "(callgrind), AVX2 code on both sides",
    "refit_time_over_embree_refit": "time of octray's BVH refit over Embree's refit of the same scene; "
                                    "no benchmark yet",
    "refit_time_over_full_build": "time of octray's BVH refit over its full build of the same scene; no benchmark yet",
    "instanced_bytes_over_flattened": "bytes of a scene of instances over the same scene flattened; no benchmark yet",
    "instanced_camera_over_embree_instances": "camera rays/s on a scene of instances, octray over Embree's "
                                              "instances; no benchmark yet",
    "build_2_threads_over_1": "BVH build speed on 2 threads over 1 thread; no benchmark yet",
    "render_1M_ply_2_threads_over_1": "render speed of a 1M-triangle PLY model on 2 threads over 1 thread; "
                                      "no benchmark yet",
    "python_intersect_over_cpp": "rays/s of the Python module's Scene.intersect over the same SIMD kernel "
                                 "looped from C++ (scripts/python-overhead, not bench-report)",
}


def target_json():
    """summary.json's "targets": {key: {"at_least": x} or {"at_most": x}}."""
    return {k: {op: x} for k, (op, x) in TARGETS.items()}


def target_text(target, fmt=str):
    """'≥ 1.0', '≤ 1.5' or 'no target'; fmt formats the threshold."""
    if not target:
        return "no target"
    op, x = target
    return f"{'≥' if op == AT_LEAST else '≤'} {fmt(x)}"


def meets(value, target):
    """True/False against the target; None without a value or a target."""
    if value is None or not target:
        return None
    op, x = target
    return value >= x if op == AT_LEAST else value <= x
