"""The benchmark rows in suite order (Report) and the sections of bench.md built from them: per stage,
AVX-512 against AVX2, the Embree peer, aobench."""

from bench_report.keys import AO_EMBREE1, AO_EMBREE8, E2E, EMBREE1, EMBREE8, SHADE
from bench_report.tables import fnum, mrays, rate, ratio, table


class Report:
    def __init__(self, rows, peak, order):
        # Registration order (from --benchmark_list_tests), so tables follow the suite, not
        # the random interleaving of the run.
        rank = {name: i for i, name in enumerate(order)}
        self.rows = dict(sorted(rows.items(), key=lambda kv: rank.get(kv[0], len(rank))))
        self.peak = peak

    def get(self, name):
        return self.rows.get(name)

    def frac(self, row):
        if not row or "error" in row or not self.peak or "GFLOPS" not in row:
            return None
        return row["GFLOPS"] / self.peak

    def stage_rows(self, prefix_cases):
        out = []
        for case in prefix_cases:
            s, v = self.get(case + "/scalar"), self.get(case + "/simd")
            if s is None and v is None:
                continue
            fr = self.frac(v)
            out.append([f"`{case}`", mrays(s), mrays(v), fnum(ratio(rate(v), rate(s))) + "×" if ratio(rate(v), rate(s)) else "—",
                        fnum(v.get("ns_per_ray")) if v and "ns_per_ray" in v else "—",
                        fnum(v.get("flops_per_ray")) if v and "flops_per_ray" in v else "—",
                        fnum(v.get("GFLOPS")) if v and "GFLOPS" in v else "—",
                        f"{100 * fr:.1f}%" if fr is not None else "—"])
        return out

    def cases(self, prefix):
        seen = []
        for name in self.rows:
            if name.startswith(prefix) and name.rsplit("/", 1)[-1] in ("scalar", "simd"):
                case = name.rsplit("/", 1)[0]
                if case not in seen:
                    seen.append(case)
        return seen

    def peer_scenes(self):
        seen = []
        for name in self.rows:
            if name.startswith("peer/"):
                scene = name.split("/")[1]
                if scene not in seen:
                    seen.append(scene)
        return seen

    def peer(self, scene, variant):
        return self.get(f"peer/{scene}/{variant}")

    def best(self, scene, variants):
        best, which = None, None
        for v in variants:
            r = rate(self.peer(scene, v))
            if r is not None and (best is None or r > best):
                best, which = r, v
        return best, which


def stage_section(rep):
    md = []
    header = ["case", "scalar Mrays/s", "simd Mrays/s", "SIMD/scalar", "simd ns/ray", "FLOP/ray", "simd GFLOP/s", "simd % of peak"]
    groups = [
        ("End to end, scenes/default.json", rep.cases("e2e/")),
        ("Camera ray generation (128×128)", rep.cases("camera/")),
        ("Intersect, one primitive type (N primitives, 128×128 rays)",
         [c for c in rep.cases("intersect/") if not c.startswith("intersect/mixed")]),
        ("Intersect, mixed scenes (six types cycled)", rep.cases("intersect/mixed")),
        ("Shade, per light type and light count (16 spheres + floor, every ray hits)", rep.cases("shade/")),
        ("Tone map, per mode", rep.cases("tonemap/")),
    ]
    for title, cases in groups:
        if not cases:
            continue
        md.append(f"### {title}\n\n")
        md.append(table(header, rep.stage_rows(cases)))
        md.append("\n")
    return "".join(md)


ISA_TWINS = [E2E, SHADE, "intersect/sphere:256_full_tests"]  # each has a CASE_avx2 twin on AVX-512 CPUs


def isa_ratios(rows):
    """{case: {path: AVX-512 unit rays/s over AVX2 unit rays/s}} for the cases timed on both."""
    out = {}
    for case in ISA_TWINS:
        for path in ("scalar", "simd"):
            r = ratio(rate(rows.get(f"{case}/{path}")), rate(rows.get(f"{case}_avx2/{path}")))
            if r is not None:
                out.setdefault(case, {})[path] = r
    return out


def isa_section(rows):
    ratios = isa_ratios(rows)
    if not ratios:
        return ("The CPU does not run the AVX-512 unit (or its rows were not run): every row above is the "
                "AVX2 unit's.\n")
    out = []
    for case, by_path in ratios.items():
        label = lambda row: (row.get("label", "").split(" [")[0] if row else "—")
        out.append([f"`{case}`", label(rows.get(f"{case}/simd")), mrays(rows.get(f"{case}_avx2/scalar")),
                    mrays(rows.get(f"{case}_avx2/simd")), mrays(rows.get(f"{case}/scalar")),
                    mrays(rows.get(f"{case}/simd")),
                    fnum(by_path.get("scalar")) + "×" if by_path.get("scalar") else "—",
                    fnum(by_path.get("simd")) + "×" if by_path.get("simd") else "—"])
    return ("Every row above runs the unit dispatch prefers: on this CPU the AVX-512 F+VL one (the same "
            "8-lane ymm code as the AVX2 unit, with 32 registers and mask compares), for both paths. "
            "The `_avx2` rows time the AVX2 unit on the same data in the same run.\n\n" +
            table(["case", "preferred kernel", "avx2 scalar", "avx2 simd", "avx512 scalar", "avx512 simd",
                   "scalar avx512/avx2", "simd avx512/avx2"], out, left=2))


def peer_section(rep, crosscheck_text):
    scenes = rep.peer_scenes()
    if not scenes:
        return "Embree peer: not built (Embree 3 not found) or not run.\n"
    header = ["scene", "octray simd", "octray scalar", "Embree8 native", "Embree8 user", "Embree8 native isa=avx2",
              "Embree8 user isa=avx2", "Embree1 native", "Embree1 user", "octray simd / best Embree8",
              "octray scalar / best Embree1", "same hit (min)"]
    rows = []
    for sc in scenes:
        b8, w8 = rep.best(sc, EMBREE8)
        b1, w1 = rep.best(sc, EMBREE1)
        o, os_ = rate(rep.peer(sc, "octray_simd")), rate(rep.peer(sc, "octray_scalar"))
        matches = [rep.peer(sc, v).get("xcheck_match") for v in ["octray_scalar"] + EMBREE8 + EMBREE1
                   if rep.peer(sc, v) and "xcheck_match" in rep.peer(sc, v)]
        r8, r1 = ratio(o, b8), ratio(os_, b1)
        rows.append([f"`{sc}`", mrays(rep.peer(sc, "octray_simd")), mrays(rep.peer(sc, "octray_scalar"))] +
                    [mrays(rep.peer(sc, v)) for v in EMBREE8 + EMBREE1] +
                    [(fnum(r8) + f"× (vs {w8})") if r8 else "—", (fnum(r1) + f"× (vs {w1})") if r1 else "—",
                     f"{100 * min(matches):.3f}%" if matches else "—"])
    md = ["Mrays/s, medians; 256×256 camera rays, closest hit, one thread, FTZ/DAZ on for both. "
          "\"same hit\": the fraction of rays on which every variant hits the same primitive as octray simd "
          "(timing counts only at ≥ 99.99%).\n\n", table(header, rows)]
    if crosscheck_text:
        lines = crosscheck_text.strip().splitlines()
        verdicts = [l for l in lines[1:-1] if l.split()]
        failed = [l for l in verdicts if " FAIL" in l]
        md.append(f"\nCross-check (`octray_bench_embree --crosscheck`, full table in `raw/crosscheck.txt`): "
                  f"{len(verdicts)} comparisons (variant × scene, and a control with radii 2% too large that "
                  f"must be rejected), {len(failed)} failed. Last line: `{lines[-1]}`\n")
        for l in failed:
            md.append(f"    {l}\n")
    return "".join(md)


def aobench_section(rep, crosscheck_text):
    rows = rep.rows  # in registration order
    names = [n for n in rows if n.startswith("ao/")]
    if not names:
        return "Not built or not run (build/bench/octray_bench_aobench).\n"
    out = []
    for n in names:
        r = rows[n]
        out.append([f"`{n}`", mrays(r), r.get("label", "").replace("|", "\\|") if "error" not in r else "",
                    f"{100 * r['xcheck_match']:.3f}%" if "xcheck_match" in r else ""])
    pairs = [("ao/render/simd", "ao/render/scalar", "whole render, SIMD / scalar"),
             ("ao/shade/pixels/simd", "ao/shade/pixels/scalar", "shade stage (AVX2), SIMD / scalar"),
             ("ao/shade/pixels/simd", "ao/shade/samples/simd", "layout: 8 pixels' k-th samples / one pixel's 8 samples"),
             ("ao/occluded/octray_simd", "ao/occluded/octray_scalar", "occluded, SIMD / scalar")]
    pairs += [("ao/occluded/octray_simd", f"ao/occluded/{v}", f"occluded, octray SIMD / {v}") for v in AO_EMBREE8 + AO_EMBREE1]
    ratios = [[what, fnum(ratio(rate(rows.get(a)), rate(rows.get(b)))) + "×"] for a, b, what in pairs
              if ratio(rate(rows.get(a)), rate(rows.get(b)))]
    md = ["Occlusion rays per second (millions), medians; `scenes/aobench.json` (512×512, 64 samples per hit) for "
          "`ao/render` and `ao/shade`, its 256×256 image's occlusion rays for `ao/occluded` (every variant the same "
          "rays; \"same answer\": the fraction of rays on which it agrees with octray SIMD, timing counts only at "
          "≥ 99.99%).\n\n", table(["benchmark", "Mrays/s", "kernel", "same answer"], out, left=3), "\n",
          table(["ratio (same run)", "value"], ratios)]
    if crosscheck_text:
        md.append(f"\nCross-check (`octray_bench_aobench --crosscheck`, `raw/crosscheck_aobench.txt`): "
                  f"`{crosscheck_text.strip().splitlines()[-1]}`\n")
    return "".join(md)
