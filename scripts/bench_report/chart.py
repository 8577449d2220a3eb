"""bench.svg and bench.png: the chart's data here, the drawing in tools/plot.py."""

import importlib.util
import json
import os
import subprocess
import sys

from bench_report.keys import E2E, EMBREE1, EMBREE8, SHADE
from bench_report.runs import TOOLS_DIR
from bench_report.tables import rate

CHART_SERIES = ["octray scalar", "octray simd", "Embree rtcIntersect8 (best)", "Embree rtcIntersect1 (best)"]


def scene_key(scene):
    """'spheres+plane:16' -> ('spheres+plane', 16): families apart, sizes in numeric order."""
    family, _, n = scene.partition(":")
    return (family, int(n) if n.isdigit() else 0, n)


def embree_note(variant):
    """'embree8_native_isa_avx2' -> 'native isa=avx2'."""
    return variant.split("_", 1)[1].replace("_isa_", " isa=") if variant else ""


def chart_data(rep):
    """The rays/s that bench.svg shows, as tools/plot.py bench reads them; None when there are none."""
    groups = []
    for case in [E2E, "e2e/default/pipeline", SHADE, "shade/point:16", "camera/pinhole", "tonemap/max_to_one",
                 "intersect/mixed:16", "intersect/sphere:256"]:
        values = [rate(rep.get(f"{case}/{p}")) for p in ("scalar", "simd")] + [None, None]
        groups.append({"label": case, "values": values, "notes": [""] * 4})
    # Sorted by name, not by the (randomly interleaved) run order: the same chart from the same data.
    for sc in sorted(rep.peer_scenes(), key=scene_key):
        b8, w8 = rep.best(sc, EMBREE8)
        b1, w1 = rep.best(sc, EMBREE1)
        groups.append({"label": "peer/" + sc,
                       "values": [rate(rep.peer(sc, "octray_scalar")), rate(rep.peer(sc, "octray_simd")), b8, b1],
                       "notes": ["", "", embree_note(w8), embree_note(w1)]})
    groups = [g for g in groups if any(g["values"])]
    return {"series": CHART_SERIES, "groups": groups} if groups else None


def plot_python():
    """The python3 for tools/plot.py: $OCTRAY_PYTHON; else this one when it has matplotlib; else Debian's
    /usr/bin/python3 (install-deps installs python3-matplotlib for it) when there is one; else this one,
    and plot.py says what is missing."""
    if os.environ.get("OCTRAY_PYTHON"):
        return os.environ["OCTRAY_PYTHON"]
    if importlib.util.find_spec("matplotlib") or not os.access("/usr/bin/python3", os.X_OK):
        return sys.executable
    return "/usr/bin/python3"


def plot_chart(rep, out):
    """DIR/bench_plot.json (the data) and tools/plot.py's DIR/bench.svg and DIR/bench.png; False when no data."""
    data = chart_data(rep)
    if data is None:
        return False
    data_path = os.path.join(out, "bench_plot.json")
    with open(data_path, "w") as f:  # one line a group
        f.write('{"series": %s,\n "groups": [\n  %s\n]}\n' % (
            json.dumps(data["series"]), ",\n  ".join(json.dumps(g) for g in data["groups"])))
    script = os.path.join(TOOLS_DIR, "plot.py")
    proc = subprocess.run([plot_python(), script, "bench", data_path, os.path.join(out, "bench.svg")],
                          stdout=subprocess.DEVNULL)
    if proc.returncode != 0:
        sys.exit(f"bench-report: tools/plot.py failed (exit {proc.returncode}): no bench.svg")
    return True
