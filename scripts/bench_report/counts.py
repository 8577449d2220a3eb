"""bench-report --counts: instructions and last-level cache misses a ray, octray against Embree on the
same rays, counted by callgrind (valgrind's cache model) where timings are noisy: DIR/counts.md,
DIR/raw/counts.json and the keys of keys.COUNT_KEYS merged into DIR/summary.json.

The settings are fixed so runs compare: valgrind has no AVX-512, so both libraries run their AVX2 code;
one last-level cache (COUNT_LL: 32 MiB, 16-way, 64-byte lines, a Zen 4/5 CCD's L3), D1 and I1 as
callgrind's defaults for the host. build/bench/octray_cache_probe (bench/cache_probe.cpp) runs one
uncounted warm-up pass and one counted pass (--toggle-collect=*measured_pass*) per engine."""

import json
import os
import re
import subprocess
import sys
import tempfile
import time

from bench_report.keys import COUNT_CASES, COUNT_ENGINES, COUNT_KEYS, COUNT_LL, DEFINITIONS, target_json, target_text
from bench_report.runs import TOOLS_DIR
from bench_report.tables import fnum, table


def count(probe, scene, rays, engine, ll=COUNT_LL):
    """One counted pass: {rays, instructions_per_ray, d1_misses_per_ray, llc_misses_per_ray}."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "cg.out")
        cmd = ["valgrind", "--tool=callgrind", "--cache-sim=yes", f"--LL={ll}", "--toggle-collect=*measured_pass*",
               f"--callgrind-out-file={out}", probe, scene, rays, engine]
        run = subprocess.run(cmd, capture_output=True, text=True)
        if run.returncode != 0:
            sys.exit(f"bench-report: {' '.join(cmd)} failed:\n{run.stderr[-2000:]}")
        m = re.search(r"^rays (\d+)", run.stdout, re.M)
        if not m:
            sys.exit(f"bench-report: no ray count from {probe}")
        n = int(m.group(1))
        text = open(out).read()
        events = re.search(r"^events: (.*)$", text, re.M).group(1).split()
        totals = [int(v) for v in re.search(r"^totals: (.*)$", text, re.M).group(1).split()]
        t = dict(zip(events, totals))
        return {"rays": n, "instructions_per_ray": t["Ir"] / n,
                "d1_misses_per_ray": (t.get("D1mr", 0) + t.get("D1mw", 0)) / n,
                "llc_misses_per_ray": (t.get("ILmr", 0) + t.get("DLmr", 0) + t.get("DLmw", 0)) / n}


def count_all(probe, cases, log=True):
    results = {}
    for case in cases:
        scene, rays = case.rsplit(":", 1)
        results[case] = {}
        for e in COUNT_ENGINES:
            results[case][e] = r = count(probe, scene, rays, e)
            if log:
                print(f"bench-report: {case} {e}: {r['instructions_per_ray']:.1f} instructions, "
                      f"{r['llc_misses_per_ray']:.3f} LL misses a ray", file=sys.stderr, flush=True)
    return results


def over_best(results, case, field):
    """octray_simd's figure over the smaller of Embree's variants (None without the case)."""
    if case not in results:
        return None
    best = min(results[case][e][field] for e in COUNT_ENGINES if e != "octray_simd")
    return results[case]["octray_simd"][field] / best if best > 0 else None


def count_keys(results):
    keys = {"llc_misses_per_ray_over_embree": over_best(results, COUNT_CASES[0], "llc_misses_per_ray"),
            "instructions_per_ray_over_embree": over_best(results, COUNT_CASES[1], "instructions_per_ray")}
    assert list(keys) == list(COUNT_KEYS), "counts.py computes keys.COUNT_KEYS, in that order"
    return keys


def counts_main(a):
    build = os.environ.get("OCTRAY_BUILD_DIR", "build")
    probe = os.path.join(build, "bench", "octray_cache_probe")
    raw = os.path.join(a.out, "raw")
    os.makedirs(raw, exist_ok=True)
    raw_path = os.path.join(raw, "counts.json")
    t_start = time.time()
    rev = subprocess.run(["git", "describe", "--always", "--dirty"], capture_output=True, text=True,
                         cwd=TOOLS_DIR).stdout.strip()
    if a.reuse:
        with open(raw_path) as f:
            saved = json.load(f)
        results, rev = saved["results"], saved.get("revision", rev)
    else:
        if not os.path.exists(probe):
            sys.exit(f"bench-report: {probe} not found: build with cmake -S . -B {build} -DOCTRAY_BUILD_BENCH=ON && "
                     f"cmake --build {build} --target octray_cache_probe (needs Embree 3 and valgrind)")
        results = count_all(probe, COUNT_CASES)
        with open(raw_path, "w") as f:
            json.dump({"revision": rev, "LL": COUNT_LL, "results": results}, f, indent=1)
    new = count_keys(results)
    summary_path = os.path.join(a.out, "summary.json")
    summary = {}
    if os.path.exists(summary_path):
        with open(summary_path) as f:
            summary = json.load(f)
    summary.update(new)
    summary["counts"] = results
    summary["targets"] = target_json()
    summary["definitions"] = dict(DEFINITIONS)
    summary["counts_context"] = {"revision": rev, "LL": COUNT_LL, "unit": "AVX2 (valgrind has no AVX-512)"}
    with open(summary_path, "w") as f:
        json.dump(summary, f, indent=2)

    md = ["# Counted passes (callgrind)\n\n",
          f"`scripts/bench-report --counts --out {a.out}` at {rev}: one pass of the cost curve's rays "
          f"(bench/cache_probe.cpp) after a warm-up pass, counted by `valgrind --tool=callgrind --cache-sim=yes "
          f"--LL={COUNT_LL}`; AVX2 code on both sides. A ray's share of the pass.\n\n"]
    rows = []
    for case, per in results.items():
        for e, r in per.items():
            rows.append([f"`{case}`", e, r["rays"], fnum(r["instructions_per_ray"]), fnum(r["d1_misses_per_ray"]),
                         fnum(r["llc_misses_per_ray"])])
    md.append(table(["case", "engine", "rays", "instructions", "D1 misses", "LL misses"], rows, left=2))
    md.append("\n## Summary\n\n")
    md.append(table(["key", "value", "target"], [[f"`{k}`", fnum(v), target_text(COUNT_KEYS[k])]
                                                 for k, v in new.items()]))
    with open(os.path.join(a.out, "counts.md"), "w") as f:
        f.write("".join(md))
    print(f"bench-report: wrote {a.out}/counts.md, {summary_path} in {time.time() - t_start:.0f} s", file=sys.stderr)
    print(json.dumps(new, indent=2))
