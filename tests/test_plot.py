#!/usr/bin/env python3
"""CTest tools.plot, tools.bench_report_plot and cli.errtime_plot: the plots tools/plot.py draws.

    test_plot.py script PLOT_PY         plot.py on hand-made errtime CSV and bench JSON, good and bad
    test_plot.py bench-report TOOL      `bench-report --plot-only` on hand-made benchmark JSON
    test_plot.py cli OCTRAY SCENE       `octray errtime SCENE --csv X --plot Y.svg` and its failures

Run by a python3 with matplotlib (the build's OCTRAY_PLOT_PYTHON), which
also runs plot.py here.
"""

import html
import json
import os
import re
import struct
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

ERRTIME_CSV = """\
path,isa,mode,kernel,ns_per_ray,ns_min,ns_max,repetitions,max_rel,mean_rel,p99_rel,max_ulp,max_scaled,mismatched,mismatched_silhouette,nonfinite,compared,lanes,kappa,pareto
scalar,avx2,exact,"scalar/avx2/exact [sphere | ambient]",160.5,150.2,171,50,1.2e-05,1e-07,1.5e-06,189,2e-06,0,0,0,1200,1200,3.5,0
simd,avx2,exact,"simd/avx2/exact [sphere | ambient]",28.4,26.2,30.6,50,1.2e-05,1e-07,1.5e-06,189,2e-06,0,0,0,1200,1200,3.5,1
simd,avx2,approx,"simd/avx2/approx [sphere | ambient]",27.1,25.9,28.8,50,0.0086,0.00011,0.0017,119765,0.0014,4,4,0,1196,1200,3.5,1
"""

BENCH_JSON = """\
{"series": ["octray scalar", "octray simd", "Embree rtcIntersect8 (best)"],
 "groups": [
  {"label": "e2e/default/render_rows", "values": [4.4e6, 2.7e7, null], "notes": ["", "", ""]},
  {"label": "peer/spheres:4", "values": [1.9e7, 1.1e8, 6.6e7], "notes": ["", "", "user"]}
 ]}
"""


def run(cmd, env=None):
    return subprocess.run(cmd, capture_output=True, text=True, env=env)


def one_line(proc):
    """The one line of an error on stderr, past errtime's progress lines ("  simd/exact  14.29 ns/ray ...")."""
    lines = [l for l in proc.stderr.splitlines() if not re.match(r"  \w+/\w+ +[0-9.]+ ns/ray  max rel ", l)]
    assert len(lines) == 1, f"the error is not one line:\n{proc.stderr}"
    return lines[0]


def svg_texts(path):
    """The SVG parsed as XML (it must be) and its texts: matplotlib draws text as paths and
    keeps each string, XML-escaped, in a comment before them."""
    parser = ET.XMLParser(target=ET.TreeBuilder(insert_comments=True))
    root = ET.parse(path, parser).getroot()
    assert root.tag == "{http://www.w3.org/2000/svg}svg", root.tag
    return [html.unescape(e.text.strip()) for e in root.iter() if e.tag is ET.Comment and e.text]


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == PNG_SIGNATURE, f"{path}: not a PNG: {head[:8]!r}"
    assert head[12:16] == b"IHDR", f"{path}: no IHDR chunk first"
    return struct.unpack(">II", head[16:24])


def check_plot(svg, expect_texts, width=None, height=None):
    texts = svg_texts(svg)
    for expected in expect_texts:
        assert any(expected in t for t in texts), f"{svg}: no text containing {expected!r} in {texts}"
    png = svg[:-4] + ".png"
    w, h = png_size(png)
    assert width is None or w == width, f"{png}: {w} px wide, expected {width}"
    assert height is None or h == height, f"{png}: {h} px high, expected {height}"


def read(path, mode="r"):
    with open(path, mode) as f:
        return f.read()


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def fake_missing_matplotlib(tmp):
    """A PYTHONPATH under which `import matplotlib` fails as when it is not installed."""
    pkg = os.path.join(tmp, "no-matplotlib", "matplotlib")
    os.makedirs(pkg)
    write(os.path.join(pkg, "__init__.py"), "raise ImportError(\"No module named 'matplotlib'\")\n")
    return dict(os.environ, PYTHONPATH=os.path.dirname(pkg))


def test_script(plot_py):
    plot = [sys.executable, plot_py]
    with tempfile.TemporaryDirectory() as tmp:
        csv_path, json_path = os.path.join(tmp, "e.csv"), os.path.join(tmp, "b.json")
        write(csv_path, ERRTIME_CSV)
        write(json_path, BENCH_JSON)

        # errtime: both files, the axis labels and title, 7 x 4.5 in at 150 dpi; the same bytes again.
        svg = os.path.join(tmp, "e.svg")
        p = run(plot + ["errtime", csv_path, svg, "--title", "errtime <test>"])
        assert p.returncode == 0, p.stderr
        assert f"wrote {svg} and {svg[:-4]}.png" in p.stdout, p.stdout
        check_plot(svg, ["errtime <test>", "ns per ray", "1200 rays a render", "relative radiance error",
                         "simd path", "scalar path", "approx", "Pareto front"], width=1050, height=675)
        first = (read(svg, "rb"), read(svg[:-4] + ".png", "rb"))
        p = run(plot + ["errtime", csv_path, svg, "--title", "errtime <test>"])
        assert p.returncode == 0, p.stderr
        assert (read(svg, "rb"), read(svg[:-4] + ".png", "rb")) == first, "a second run wrote other bytes"

        # bench: labels, groups and series.
        svg = os.path.join(tmp, "b.svg")
        p = run(plot + ["bench", json_path, svg])
        assert p.returncode == 0, p.stderr
        check_plot(svg, ["rays per second", "e2e/default/render_rows", "peer/spheres:4", "octray simd",
                         "Embree rtcIntersect8 (best)", "66M (user)"], width=1050)

        # Malformed input: exit 2, one line naming the file, the line and the field; nothing written.
        bad_cases = [
            ("bad_number.csv", ERRTIME_CSV.replace(",28.4,", ",fast,"), r"bad_number\.csv: line 3: ns_per_ray: .*'fast'"),
            ("short_row.csv", ERRTIME_CSV + "simd,avx2,fast\n", r"short_row\.csv: line 5: 3 fields, the header has 20"),
            ("no_header.csv", "a,b,c\n1,2,3\n", r"no_header\.csv: line 1: the header lacks path, mode, ns_per_ray"),
            ("only_header.csv", ERRTIME_CSV.splitlines()[0] + "\n", r"only_header\.csv: no data rows"),
        ]
        for name, text, pattern in bad_cases:
            path, out = os.path.join(tmp, name), os.path.join(tmp, name + ".svg")
            write(path, text)
            p = run(plot + ["errtime", path, out])
            assert p.returncode == 2, f"{name}: exit {p.returncode}\n{p.stderr}"
            line = one_line(p)
            assert re.match(r"plot\.py: .*" + pattern, line), f"{name}: {line}"
            assert not os.path.exists(out) and not os.path.exists(out[:-4] + ".png"), f"{name}: wrote a plot"
        write(os.path.join(tmp, "bad.json"), '{"series": ["a"], "groups": [{"label": "x", "values": [-1]}]}')
        p = run(plot + ["bench", os.path.join(tmp, "bad.json"), os.path.join(tmp, "bad.svg")])
        assert p.returncode == 2 and re.search(r"groups\[0\]: values: expected rays/s > 0", one_line(p)), p.stderr
        p = run(plot + ["errtime", os.path.join(tmp, "missing.csv"), os.path.join(tmp, "m.svg")])
        assert p.returncode == 2 and "missing.csv: cannot read" in one_line(p), p.stderr

        # No matplotlib: exit 3, one line that says so and how to get it.
        p = run(plot + ["errtime", csv_path, os.path.join(tmp, "n.svg")], env=fake_missing_matplotlib(tmp))
        assert p.returncode == 3, f"exit {p.returncode}\n{p.stderr}"
        line = one_line(p)
        assert "needs matplotlib" in line and "python3-matplotlib" in line, line
    print("plot.py: errtime and bench plots as SVG and PNG; bad input and no matplotlib refused in one line")


def benchmark_json(rates):
    """Google Benchmark JSON with one median aggregate of items_per_second per run name, in the given order."""
    return json.dumps({"context": {"host_name": "test"}, "benchmarks": [
        {"name": f"{name}_median", "run_name": name, "run_type": "aggregate", "aggregate_name": "median",
         "items_per_second": rate} for name, rate in rates]})


def test_bench_report(tool):
    with tempfile.TemporaryDirectory() as tmp:
        os.makedirs(os.path.join(tmp, "raw"))
        write(os.path.join(tmp, "raw", "stages.json"), benchmark_json([
            ("e2e/default/render_rows/simd", 2.7e7), ("e2e/default/render_rows/scalar", 4.4e6),
            ("shade/default/scalar", 2.3e7)]))
        # Scenes in a random (interleaved) order, as a run writes them.
        write(os.path.join(tmp, "raw", "embree.json"), benchmark_json([
            ("peer/spheres:16/octray_simd", 6.2e7), ("peer/spheres+plane:1/octray_simd", 1.2e8),
            ("peer/spheres:4/embree8_user", 6.6e7), ("peer/spheres:4/embree8_native_isa_avx2", 3.0e7),
            ("peer/spheres:4/octray_simd", 1.1e8), ("peer/spheres:4/embree1_native", 2.1e7)]))
        env = dict(os.environ, OCTRAY_PYTHON=sys.executable, OCTRAY_BUILD_DIR=os.path.join(tmp, "no-build"))
        p = run([sys.executable, tool, "--out", tmp, "--plot-only"], env=env)
        assert p.returncode == 0, p.stderr
        with open(os.path.join(tmp, "bench_plot.json")) as f:
            data = json.load(f)
        got = [(g["label"], g["values"], g["notes"]) for g in data["groups"]]
        assert got == [
            ("e2e/default/render_rows", [4.4e6, 2.7e7, None, None], ["", "", "", ""]),
            ("shade/default", [2.3e7, None, None, None], ["", "", "", ""]),
            ("peer/spheres:4", [None, 1.1e8, 6.6e7, 2.1e7], ["", "", "user", "native"]),
            ("peer/spheres:16", [None, 6.2e7, None, None], ["", "", "", ""]),
            ("peer/spheres+plane:1", [None, 1.2e8, None, None], ["", "", "", ""]),
        ], got
        check_plot(os.path.join(tmp, "bench.svg"), ["rays per second", "peer/spheres+plane:1", "66M (user)"],
                   width=1050)
        # --plot-only leaves the report alone.
        assert not os.path.exists(os.path.join(tmp, "bench.md")) and not os.path.exists(os.path.join(tmp, "summary.json"))
    print("bench-report --plot-only: the chart's data from raw/*.json in a fixed order, drawn by plot.py")


def test_cli(octray, scene):
    with tempfile.TemporaryDirectory() as tmp:
        # The contract: --csv and --plot both written, the plot drawn from that CSV.
        csv_path, svg = os.path.join(tmp, "e.csv"), os.path.join(tmp, "e.svg")
        p = run([octray, "errtime", scene, "--csv", csv_path, "--plot", svg])
        assert p.returncode == 0, f"exit {p.returncode}\n{p.stdout}\n{p.stderr}"
        assert f"wrote {csv_path}\nwrote {svg} and {svg[:-4]}.png" in p.stdout, p.stdout
        lines = read(csv_path).splitlines()
        assert lines[0].startswith("path,isa,mode,") and len(lines) >= 3, lines
        check_plot(svg, [f"octray errtime: {scene}", "ns per ray", "relative radiance error", "simd path"],
                   width=1050, height=675)

        # A smaller scene for the rest: the run's numbers do not matter here.
        small = os.path.join(tmp, "small.json")
        write(small, re.sub(r'"width": *\d+, *"height": *\d+', '"width": 16, "height": 12', read(scene)))
        # --plot alone: its CSV is a temporary file, removed afterwards.
        scratch = os.path.join(tmp, "scratch")
        os.makedirs(scratch)
        svg = os.path.join(tmp, "alone.svg")
        p = run([octray, "errtime", small, "--plot", svg], env=dict(os.environ, TMPDIR=scratch))
        assert p.returncode == 0, f"exit {p.returncode}\n{p.stderr}"
        check_plot(svg, [f"octray errtime: {small}"], width=1050, height=675)
        assert os.listdir(scratch) == [], f"left behind: {os.listdir(scratch)}"

        # No python3 / no matplotlib: exit 2, one line saying what is missing, the CSV still written.
        for what, env, expect in [
            ("no python3", dict(os.environ, OCTRAY_PYTHON=os.path.join(tmp, "nowhere", "python3")),
             r"^octray: --plot .*nope\.svg: cannot run .*nowhere/python3 \(No such file or directory\): .*matplotlib"),
            ("no matplotlib", dict(fake_missing_matplotlib(tmp), OCTRAY_PYTHON=sys.executable),
             r"^octray: --plot .*nope\.svg: plot\.py: needs matplotlib, .*python3-matplotlib"),
        ]:
            csv_path, svg = os.path.join(tmp, "nope.csv"), os.path.join(tmp, "nope.svg")
            if os.path.exists(csv_path):
                os.remove(csv_path)
            p = run([octray, "errtime", small, "--csv", csv_path, "--plot", svg], env=env)
            assert p.returncode == 2, f"{what}: exit {p.returncode}\n{p.stderr}"
            assert re.match(expect, one_line(p)), f"{what}: {p.stderr}"
            assert read(csv_path).startswith("path,isa,mode,"), f"{what}: no CSV"
            assert not os.path.exists(svg), f"{what}: {svg} written"
    print("octray errtime --csv --plot: CSV, SVG and PNG; no python3 / matplotlib: exit 2 in one line, CSV kept")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "script":
        test_script(sys.argv[2])
    elif len(sys.argv) == 3 and sys.argv[1] == "bench-report":
        test_bench_report(sys.argv[2])
    elif len(sys.argv) == 4 and sys.argv[1] == "cli":
        test_cli(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)
