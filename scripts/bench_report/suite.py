"""The everyday run: octray_bench and, when built, octray_bench_embree and octray_bench_aobench, pinned,
into DIR/raw/*.json (or those files as they are, with --reuse and --plot-only); then DIR/summary.json,
DIR/bench.md and the chart."""

import json
import os
import shutil
import subprocess
import sys
import time

from bench_report.bench_md import write_bench_md
from bench_report.chart import plot_chart
from bench_report.keys import PEAK, SUITE_KEYS
from bench_report.report import Report
from bench_report.runs import TOOLS_DIR, load_medians, run
from bench_report.summary import build_summary


def suite_main(a):
    build = os.environ.get("OCTRAY_BUILD_DIR", "build")
    stages_bin = os.path.join(build, "bench", "octray_bench")
    embree_bin = os.path.join(build, "bench", "octray_bench_embree")
    aobench_bin = os.path.join(build, "bench", "octray_bench_aobench")
    raw = os.path.join(a.out, "raw")
    os.makedirs(raw, exist_ok=True)
    t_start = time.time()
    # The revision measured, taken before this run writes its own outputs
    # (which would mark a clean checkout dirty when --out is inside it).
    rev = subprocess.run(["git", "describe", "--always", "--dirty"], capture_output=True, text=True, cwd=TOOLS_DIR)

    pin = []
    if a.cpu != "none" and shutil.which("taskset"):
        pin = ["taskset", "-c", a.cpu]
    common = [f"--benchmark_repetitions={a.repetitions}", "--benchmark_report_aggregates_only=true",
              f"--benchmark_min_time={a.min_time}", "--benchmark_enable_random_interleaving=true",
              "--benchmark_format=json"]
    if a.filter:
        common.append(f"--benchmark_filter={a.filter}")

    binaries = [("stages", stages_bin)]
    if os.path.exists(embree_bin):
        binaries.append(("embree", embree_bin))
    elif not (a.reuse or a.plot_only):
        print(f"bench-report: {embree_bin} not found (Embree 3 not installed?): no peer tables", file=sys.stderr)
    if os.path.exists(aobench_bin):
        binaries.append(("aobench", aobench_bin))
    elif not (a.reuse or a.plot_only):
        print(f"bench-report: {aobench_bin} not found: no aobench table", file=sys.stderr)
    if not (a.reuse or a.plot_only):
        if not os.path.exists(stages_bin):
            sys.exit(f"bench-report: {stages_bin} not found: build with "
                     f"cmake -S . -B {build} -DOCTRAY_BUILD_BENCH=ON && "
                     f"cmake --build {build} --target octray_bench octray_bench_embree")
        for tag, binary in binaries:
            rc = run(pin + [binary] + common, os.path.join(raw, f"{tag}.json"))
            if rc != 0:
                sys.exit(f"bench-report: {binary} exited with {rc}")
        if os.path.exists(embree_bin):
            with open(os.path.join(raw, "crosscheck.txt"), "w") as f:
                subprocess.run(pin + [embree_bin, "--crosscheck"], stdout=f)
        if os.path.exists(aobench_bin):
            with open(os.path.join(raw, "crosscheck_aobench.txt"), "w") as f:
                subprocess.run(pin + [aobench_bin, "--crosscheck"], stdout=f)

    context, rows, order = {}, {}, []
    # From existing data: every raw JSON there is, whether or not its binary is built.
    sources = ([("stages", stages_bin), ("embree", embree_bin), ("aobench", aobench_bin)] if a.reuse or a.plot_only
               else binaries)
    for tag, binary in sources:
        p = os.path.join(raw, f"{tag}.json")
        if os.path.exists(p):
            c, r = load_medians(p)
            for k, v in c.items():
                context.setdefault(k, v)
            rows.update(r)
        if os.path.exists(binary) and not a.plot_only:  # the chart's order does not depend on it
            listed = subprocess.run([binary, "--benchmark_list_tests=true"], capture_output=True, text=True)
            order += listed.stdout.split()
    crosscheck_text = ""
    if os.path.exists(os.path.join(raw, "crosscheck.txt")):
        with open(os.path.join(raw, "crosscheck.txt")) as f:
            crosscheck_text = f.read()

    peak_row = rows.get(PEAK)
    peak = peak_row.get("GFLOPS") if peak_row and "error" not in peak_row else None
    rep = Report(rows, peak, order)
    if a.plot_only:
        if not plot_chart(rep, a.out):
            sys.exit(f"bench-report: no rays/s to plot in {raw}/*.json")
        print(f"bench-report: wrote {a.out}/bench.svg, {a.out}/bench.png from {a.out}/bench_plot.json", file=sys.stderr)
        return

    summary = build_summary(a, rows, rep, peak)
    summary_path = os.path.join(a.out, "summary.json")
    if os.path.exists(summary_path):  # keep the other runs' keys (--scale, --counts, python-overhead)
        with open(summary_path) as f:
            earlier = json.load(f)
        for key, value in earlier.items():
            summary.setdefault(key, value)
    with open(summary_path, "w") as f:
        json.dump(summary, f, indent=2)
        f.write("\n")

    write_bench_md(a, build, pin, rev, context, rows, peak, summary, rep, raw, crosscheck_text, t_start)
    have_plot = plot_chart(rep, a.out)
    print(f"bench-report: wrote {a.out}/bench.md, {a.out}/summary.json"
          f"{', ' + a.out + '/bench.svg, .png' if have_plot else ''} in {time.time() - t_start:.0f} s", file=sys.stderr)
    print(json.dumps({k: summary.get(k) for k in SUITE_KEYS}, indent=2))
