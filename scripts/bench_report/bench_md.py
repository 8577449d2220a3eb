"""DIR/bench.md of the everyday run: how it was produced, the targets, the FMA peak, the divider, the
stages, the ISA units, the Embree peer and aobench."""

import datetime
import os
import time

from bench_report.keys import DEFINITIONS, SUITE_KEYS, meets, target_text
from bench_report.report import aobench_section, isa_section, peer_section, stage_section
from bench_report.summary import divider_ratio
from bench_report.tables import err, fnum, table


def write_bench_md(a, build, pin, rev, context, rows, peak, summary, rep, raw, crosscheck_text, t_start):
    """Writes DIR/bench.md from the rows of this run (or of DIR/raw/*.json with --reuse)."""
    md = ["# octray benchmarks\n\n"]
    cmd = f"OCTRAY_BUILD_DIR={build} scripts/bench-report --out {a.out} --repetitions {a.repetitions} --min-time {a.min_time}"
    if a.filter:
        cmd += f" --filter '{a.filter}'"
    md.append(f"Produced by `{cmd}` on {datetime.datetime.now().strftime('%Y-%m-%d %H:%M')}"
              f"{' (pinned: ' + ' '.join(pin) + ')' if pin else ''}. ")
    md.append(f"Source: git {rev.stdout.strip() if rev.returncode == 0 else 'revision unknown (not a git checkout)'}. ")
    md.append(f"Host: {context.get('host_name', '?')}, {context.get('num_cpus', '?')} CPUs, "
              f"{context.get('mhz_per_cpu', '?')} MHz nominal; benchmark library build: "
              f"{context.get('library_build_type', '?')} (as the distribution's libbenchmark reports itself; "
              f"octray and these benchmarks are built -O3); FTZ/DAZ: {context.get('octray_ftz_daz', '?')}; "
              f"Embree: {context.get('embree_version', 'not built')} ({context.get('embree_default_isa', '-')}). ")
    md.append("Medians over the repetitions; every ratio is two medians of this one run. "
              "FLOP/ray is counted from the kernel source (bench/bench_common.cpp explains the count); "
              "% of peak = GFLOP/s over the FMA peak below.\n\n")

    md.append("## Targets\n\n")
    trows = []
    for key, target in SUITE_KEYS.items():
        v = summary.get(key)
        percent = key == "intersect_fraction_of_peak"
        shown = "—" if v is None else (f"{100 * v:.1f}%" if percent else f"{fnum(v)}×")
        need = target_text(target, (lambda x: f"{100 * x:.0f}%") if percent else (lambda x: f"{x}×"))
        ok = meets(v, target)
        trows.append([f"`{key}`", shown, need, "—" if ok is None else ("met" if ok else "**missed**"), DEFINITIONS[key]])
    md.append(table(["summary key", "measured", "target", "verdict", "definition"], trows, left=5))

    md.append("\n## Peak: sustained FP32 FMA throughput, 8 lanes\n\n")
    prow = []
    for c in (1, 4, 8, 12):
        r = rows.get(f"fma_peak/8lanes/chains:{c}")
        if r:
            prow.append([f"`fma_peak/8lanes/chains:{c}`", fnum(r.get("GFLOPS")) if "GFLOPS" in r else err(r)])
    md.append("Independent chains of `vfmadd231ps ymm` (16 FLOPs each). The peak used for every \"% of peak\" "
              f"is the 12-chain median: **{fnum(peak)} GFLOP/s**.\n\n")
    md.append(table(["benchmark", "GFLOP/s"], prow))

    md.append("\n## The divide/sqrt unit: 8 lanes against 1\n\n")
    drow = []
    for op in ("div", "sqrt"):
        r8, r1 = rows.get(f"divider/{op}/8lanes"), rows.get(f"divider/{op}/1lane")
        if r8 and r1:
            drow.append([f"`{op}`", fnum(r1.get("Glane_results_per_s")), fnum(r8.get("Glane_results_per_s")),
                         f"{fnum(divider_ratio(rows, op))}×"])
    md.append("Eight independent chains of `divss`/`sqrtss` against `vdivps`/`vsqrtps ymm` "
              "(`divider/*`), in lane results per ns. Exact precision divides and takes square roots in "
              "IEEE arithmetic, so wherever a kernel waits on this unit, 8 lanes gain at most this ratio "
              "over the scalar path, not 8×.\n\n")
    md.append(table(["operation", "1 lane (G/s)", "8 lanes (G lane results/s)", "8 lanes / 1 lane"], drow))

    md.append("\n## Scalar vs SIMD, per stage and end to end\n\n")
    md.append(stage_section(rep))
    md.append("### The instruction set: AVX-512 unit against AVX2 unit (Mrays/s)\n\n")
    md.append(isa_section(rows))
    md.append("\n")
    md.append("## Peer: Intel Embree 3 vs octray intersect, same scenes, same rays\n\n")
    md.append(peer_section(rep, crosscheck_text))
    md.append("\n## aobench: ambient occlusion, incoherent rays in packets\n\n")
    ao_check = os.path.join(raw, "crosscheck_aobench.txt")
    md.append(aobench_section(rep, open(ao_check).read() if os.path.exists(ao_check) else ""))
    md.append(f"\nTotal run time: {time.time() - t_start:.0f} s.\n")
    with open(os.path.join(a.out, "bench.md"), "w") as f:
        f.write("".join(md))
