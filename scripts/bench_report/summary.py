"""DIR/summary.json of the everyday run: its keys (keys.SUITE_KEYS), the details behind them, every target and
definition of keys.py."""

from bench_report.keys import AO_EMBREE1, AO_EMBREE8, AO_RENDER, DEFINITIONS, E2E, EMBREE8, PEAK_INTERSECT, SHADE, target_json
from bench_report.report import isa_ratios
from bench_report.tables import rate, ratio


def divider_ratio(rows, op):
    """divider/OP: 8 lanes' results per second over 1 lane's."""
    r8, r1 = rows.get(f"divider/{op}/8lanes"), rows.get(f"divider/{op}/1lane")
    if not r8 or not r1:
        return None
    return ratio(r8.get("Glane_results_per_s"), r1.get("Glane_results_per_s"))


def build_summary(a, rows, rep, peak):
    """The summary dict, in the order summary.json lists it."""
    def stage_ratio(case):
        return ratio(rate(rows.get(case + "/simd")), rate(rows.get(case + "/scalar")))

    peer_ratios = {}
    for sc in rep.peer_scenes():
        if sc.startswith("spheres:") and int(sc.split(":")[1]) <= 64:
            b8, w8 = rep.best(sc, EMBREE8)
            r = ratio(rate(rep.peer(sc, "octray_simd")), b8)
            if r is not None:
                peer_ratios[sc] = {"ratio": r, "embree_variant": w8}

    def best_of(prefix, variants):
        found = [(rate(rows.get(prefix + v)), v) for v in variants]
        found = [f for f in found if f[0] is not None]
        return max(found) if found else (None, None)

    ao_e8, ao_w8 = best_of("ao/occluded/", AO_EMBREE8)
    ao_e1, ao_w1 = best_of("ao/occluded/", AO_EMBREE1)
    ao_simd = rate(rows.get("ao/occluded/octray_simd"))
    summary = {
        "aobench_simd_over_scalar": stage_ratio(AO_RENDER),
        "aobench_occluded_over_embree": ratio(ao_simd, ao_e8),
        # Not targets: the aobench details behind the two keys above.
        "aobench": {
            "occluded_simd_over_scalar": ratio(ao_simd, rate(rows.get("ao/occluded/octray_scalar"))),
            "occluded_over_embree1": ratio(ao_simd, ao_e1),
            "embree8_variant": ao_w8,
            "embree1_variant": ao_w1,
            "shade_pixels_over_samples": ratio(rate(rows.get("ao/shade/pixels/simd")),
                                               rate(rows.get("ao/shade/samples/simd"))),
        },
        "simd_over_scalar_end_to_end": stage_ratio(E2E),
        "simd_over_scalar_shade": stage_ratio(SHADE),
        "octray_over_embree_intersect8": min((v["ratio"] for v in peer_ratios.values()), default=None),
        "intersect_fraction_of_peak": rep.frac(rows.get(PEAK_INTERSECT)),
        "fma_peak_gflops": peak,
        # Not targets: how far 8 lanes can take divider-bound code (vdivps/vsqrtps ymm over divss/sqrtss).
        "divider_8lanes_over_1lane_div": divider_ratio(rows, "div"),
        "divider_8lanes_over_1lane_sqrt": divider_ratio(rows, "sqrt"),
        "octray_over_embree_intersect8_per_scene": peer_ratios,
        # Not targets: the preferred (AVX-512) unit over the AVX2 unit, same run, per path.
        "avx512_over_avx2": isa_ratios(rows),
        "definitions": DEFINITIONS,
        "targets": target_json(),
        "repetitions": a.repetitions,
        "min_time_s": a.min_time,
    }
    return summary
