"""--scale: the cost curve against Embree (octray_bench_scale): its rows, the build-time and memory rows,
DIR/scale.md and the scale keys merged into DIR/summary.json."""

import json
import os
import shutil
import subprocess
import sys
import time

from bench_report.keys import (ANY_HIT_SCENE, DEFINITIONS, MESH_SCENES, SCALE_KEYS, SPHERE_SCENES, target_json,
                               target_text)
from bench_report.runs import TOOLS_DIR, load_medians, run
from bench_report.tables import fnum, rate, ratio, table

SCALE_SCENES = ["spheres:16", "spheres:256", "spheres:4k", "spheres:64k", "spheres:1M",
                "heightfield:1k", "heightfield:16k", "heightfield:256k", "heightfield:1M", "model"]


def scale_rows(rows):
    """The cost-curve rows: one per scene, ray kind and query."""
    out = []
    for scene in SCALE_SCENES:
        for rays in ("camera", "incoherent"):
            for query in ("closest", "any"):
                pre = f"scale/{scene}/{rays}/{query}/"
                got = {k[len(pre):]: v for k, v in rows.items() if k.startswith(pre)}
                if not got:
                    continue
                r = {k: rate(v) for k, v in got.items()}
                e8 = [v for k, v in r.items() if k.startswith("embree8") and v]
                e1 = [v for k, v in r.items() if k.startswith("embree1") and v]
                best = max(e8 + e1) if e8 + e1 else None
                best_name = max((k for k in r if k.startswith("embree") and r[k]), key=lambda k: r[k], default=None)
                prims = next((v.get("primitives") for v in got.values() if "primitives" in v), None)
                xm = min((v.get("xcheck_match", 1.0) for v in got.values() if "xcheck_match" in v), default=None)
                out.append({"scene": scene, "primitives": int(prims) if prims else None, "rays": rays, "query": query,
                            "octray_simd_mrays": r.get("octray_simd") and r["octray_simd"] / 1e6,
                            "octray_scalar_mrays": r.get("octray_scalar") and r["octray_scalar"] / 1e6,
                            "embree8_mrays": max(e8) / 1e6 if e8 else None,
                            "embree1_mrays": max(e1) / 1e6 if e1 else None,
                            "embree_best": best_name,
                            "octray_over_embree": ratio(r.get("octray_simd"), best),
                            "simd_over_scalar": ratio(r.get("octray_simd"), r.get("octray_scalar")),
                            "xcheck_match_min": xm})
    return out


def build_rows(rows):
    out = []
    for scene in SCALE_SCENES:
        # "scale_build/SCENE/VARIANT[/iterations:1]/manual_time"
        find = lambda v: next((r for k, r in rows.items() if k.startswith(f"scale_build/{scene}/{v}/")), None)
        o, h, m = (find(v) for v in ("octray", "embree_high", "embree_medium"))
        if not o or "error" in o:
            continue
        sec = lambda r: r["real_time"] / 1e3 if r and "real_time" in r else None  # ms -> s
        bpp = lambda r: r.get("bytes_per_primitive") if r else None
        e_time = min([t for t in (sec(h), sec(m)) if t], default=None)
        e_bytes = min([b for b in (bpp(h), bpp(m)) if b], default=None)
        out.append({"scene": scene, "primitives": int(o.get("primitives", 0)),
                    "octray_build_s": sec(o), "embree_high_build_s": sec(h), "embree_medium_build_s": sec(m),
                    "build_time_over_embree": ratio(sec(o), e_time),
                    "octray_bytes_per_primitive": bpp(o), "embree_high_bytes_per_primitive": bpp(h),
                    "embree_medium_bytes_per_primitive": bpp(m),
                    "bytes_per_primitive_over_embree": ratio(bpp(o), e_bytes)})
    return out


def extreme(f, key, sel):
    vals = [r[key] for r in sel if r.get(key) is not None]
    return f(vals) if vals else None


def scale_keys(curve, builds):
    """The summary keys of keys.SCALE_KEYS, from the cost-curve and build rows (None where a row is missing)."""
    closest = [r for r in curve if r["query"] == "closest"]

    def rows(rays, scenes=None):
        return [r for r in closest if r["rays"] == rays and (scenes is None or r["scene"].startswith(scenes))]

    def pass_time(query):  # octray SIMD's time over the row's rays, as 1 / (rays/s)
        r = next((r for r in curve if (r["scene"], r["rays"], r["query"]) == (ANY_HIT_SCENE, "camera", query)), None)
        return 1 / r["octray_simd_mrays"] if r and r.get("octray_simd_mrays") else None

    keys = {
        "scale_camera_octray_over_embree_min": extreme(min, "octray_over_embree", rows("camera")),
        "scale_incoherent_octray_over_embree_min": extreme(min, "octray_over_embree", rows("incoherent")),
        "scale_camera_spheres_min": extreme(min, "octray_over_embree", rows("camera", SPHERE_SCENES)),
        "scale_camera_mesh_min": extreme(min, "octray_over_embree", rows("camera", MESH_SCENES)),
        "scale_incoherent_mesh_min": extreme(min, "octray_over_embree", rows("incoherent", MESH_SCENES)),
        "closest_over_any_hit_time": ratio(pass_time("closest"), pass_time("any")),
        "scale_simd_over_scalar_camera_min": extreme(min, "simd_over_scalar", rows("camera")),
        "scale_build_time_over_embree_max": extreme(max, "build_time_over_embree", builds),
        "scale_bytes_per_primitive_over_embree_max": extreme(max, "bytes_per_primitive_over_embree", builds),
    }
    assert list(keys) == list(SCALE_KEYS), "scale.py computes keys.SCALE_KEYS, in that order"
    return keys


def scale_main(a):
    build = os.environ.get("OCTRAY_BUILD_DIR", "build")
    binary = os.path.join(build, "bench", "octray_bench_scale")
    raw = os.path.join(a.out, "raw")
    os.makedirs(raw, exist_ok=True)
    t_start = time.time()
    reps = a.repetitions if a.repetitions != 7 else 5  # the everyday default, 7, is too long here
    rev = subprocess.run(["git", "describe", "--always", "--dirty"], capture_output=True, text=True,
                         cwd=TOOLS_DIR).stdout.strip()
    pin = ["taskset", "-c", a.cpu] if a.cpu != "none" and shutil.which("taskset") else []
    common = ["--benchmark_report_aggregates_only=true", f"--benchmark_min_time={a.min_time}",
              "--benchmark_enable_random_interleaving=true", "--benchmark_format=json"]
    small = "^scale(_build)?/(spheres:(16|256|4k|64k)|heightfield:(1k|16k|256k)|model)/"
    big = "^scale(_build)?/(spheres|heightfield):1M/"
    parts = [("scale", small, reps), ("scale_1M", big, a.big_repetitions)]
    if not a.reuse:
        if not os.path.exists(binary):
            sys.exit(f"bench-report: {binary} not found: build with cmake -S . -B {build} -DOCTRAY_BUILD_BENCH=ON && "
                     f"cmake --build {build} --target octray_bench_scale (needs Embree 3)")
        for tag, flt, n in parts:
            rc = run(pin + [binary, f"--benchmark_filter={a.filter or flt}", f"--benchmark_repetitions={n}"] + common,
                     os.path.join(raw, f"{tag}.json"))
            if rc != 0:
                sys.exit(f"bench-report: {binary} exited with {rc}")
    context, rows = {}, {}
    for tag, _, _ in parts:
        p = os.path.join(raw, f"{tag}.json")
        if os.path.exists(p):
            c, r = load_medians(p)
            context.update(c)
            rows.update(r)
    curve, builds = scale_rows(rows), build_rows(rows)

    summary_path = os.path.join(a.out, "summary.json")
    summary = {}
    if os.path.exists(summary_path):
        with open(summary_path) as f:
            summary = json.load(f)
    new = scale_keys(curve, builds)
    summary.update(new)
    summary["scale"] = curve
    summary["scale_build"] = builds
    summary["targets"] = target_json()  # one set for the file, whichever run wrote it last
    summary["definitions"] = dict(DEFINITIONS)
    summary["scale_context"] = {k: context.get(k) for k in ("date", "host_name", "embree_version", "scale_model",
                                                            "octray_simd_kernel", "mhz_per_cpu") if k in context}
    summary["scale_context"]["revision"] = rev
    with open(summary_path, "w") as f:
        json.dump(summary, f, indent=2)

    md = ["# The cost curve against Embree (octray_bench_scale)\n\n",
          f"`scripts/bench-report --scale --out {a.out}` at {rev} (medians: {reps} repetitions, the 1M scenes "
          f"{a.big_repetitions}; one thread, pinned; CPU time per pass), Embree {context.get('embree_version', '?')}. "
          "Mrays/s; *ratio* = octray SIMD over the fastest Embree variant of the row (`embree8*`: rtcIntersect8/"
          "rtcOccluded8, `embree1*`: rtcIntersect1/rtcOccluded1; spheres: the faster of native and user); "
          "*match* = the smallest fraction of rays on which a variant gave octray SIMD's answer.\n\n"]
    md.append(table(["scene", "prims", "rays", "query", "octray simd", "octray scalar", "Embree 8", "Embree 1",
                     "best Embree", "ratio", "match"],
                    [[f"`{r['scene']}`", r["primitives"], r["rays"], r["query"], fnum(r["octray_simd_mrays"]),
                      fnum(r["octray_scalar_mrays"]), fnum(r["embree8_mrays"]), fnum(r["embree1_mrays"]),
                      r["embree_best"] or "—", f"{fnum(r['octray_over_embree'])}×",
                      fnum(r["xcheck_match_min"], 5)] for r in curve], left=4))
    md.append("\n## Build time and memory\n\n"
              "octray: `compile()` (validation, SoA arrays, BVH build); Embree: `rtcCommitScene` alone (spheres "
              "native). Bytes per primitive: octray's BVH and per-primitive arrays; Embree's device memory after "
              "the commit (its memory monitor: BVH and geometry buffers). Ratios against the faster (smaller) "
              "Embree quality.\n\n")
    md.append(table(["scene", "prims", "octray ms", "Embree high ms", "Embree medium ms", "time ratio",
                     "octray B/prim", "Embree high B/prim", "Embree medium B/prim", "bytes ratio"],
                    [[f"`{r['scene']}`", r["primitives"], fnum(r["octray_build_s"] and r["octray_build_s"] * 1e3),
                      fnum(r["embree_high_build_s"] and r["embree_high_build_s"] * 1e3),
                      fnum(r["embree_medium_build_s"] and r["embree_medium_build_s"] * 1e3),
                      f"{fnum(r['build_time_over_embree'])}×", fnum(r["octray_bytes_per_primitive"]),
                      fnum(r["embree_high_bytes_per_primitive"]), fnum(r["embree_medium_bytes_per_primitive"]),
                      f"{fnum(r['bytes_per_primitive_over_embree'])}×"] for r in builds], left=2))
    md.append("\n## Summary\n\n")
    md.append(table(["key", "value", "target"], [[f"`{k}`", fnum(v), target_text(SCALE_KEYS[k])]
                                                 for k, v in new.items()]))
    md.append(f"\nTotal run time: {time.time() - t_start:.0f} s.\n")
    with open(os.path.join(a.out, "scale.md"), "w") as f:
        f.write("".join(md))
    print(f"bench-report: wrote {a.out}/scale.md, {summary_path} in {time.time() - t_start:.0f} s", file=sys.stderr)
    print(json.dumps(new, indent=2))
