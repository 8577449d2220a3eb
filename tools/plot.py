#!/usr/bin/env python3
"""plot.py: octray's plots, drawn with matplotlib, as SVG and PNG.

    tools/plot.py errtime CSV OUT.svg [--title T]   error against ns/ray, from `octray errtime --csv`
    tools/plot.py bench JSON OUT.svg [--title T]    rays/s per case, from bench-report's DIR/bench_plot.json

Each writes OUT.svg and, beside it, the same plot as PNG (OUT.svg's name with
.png for .svg), then prints what it wrote. The output is deterministic: the
same input gives byte-identical files with the same matplotlib.

`octray errtime --plot` runs this very text: the build embeds it in the
binary and pipes it to python3 (cmake/octrayPlot.cmake); scripts/bench-report
runs this file. Bad input: one line on stderr and exit 2; matplotlib missing:
one line and exit 3.
"""

import argparse
import csv
import json
import math
import os
import sys

PROG = "plot.py"
EXIT_BAD_INPUT = 2
EXIT_NO_MATPLOTLIB = 3

FIGSIZE = (7.0, 4.5)  # inches; README width
DPI = 150             # PNG only; the SVG is vector


class BadInput(Exception):
    pass


def fail(message, status):
    print(f"{PROG}: {message}", file=sys.stderr)
    sys.exit(status)


def load_matplotlib():
    try:
        import matplotlib
    except ImportError as e:
        fail(f"needs matplotlib, which {sys.executable or 'python3'} cannot import ({e}); "
             "Debian: apt-get install python3-matplotlib; another python3 for octray and bench-report: "
             "OCTRAY_PYTHON=/its/python3", EXIT_NO_MATPLOTLIB)
    matplotlib.use("Agg")
    # Deterministic SVG: fixed ids (hash salt) and no date in the metadata (savefig below).
    matplotlib.rcParams.update({"svg.hashsalt": "octray", "font.size": 9, "axes.titlesize": 10,
                                "legend.fontsize": 8})
    import matplotlib.pyplot as plt
    return plt


def png_path(svg_path):
    stem = svg_path[:-4] if svg_path.lower().endswith(".svg") else svg_path
    return stem + ".png"


def save(fig, plt, out_svg):
    out_png = png_path(out_svg)
    try:
        fig.savefig(out_svg, format="svg", metadata={"Date": None})
        fig.savefig(out_png, format="png", dpi=DPI)
    except OSError as e:
        raise BadInput(f"{e.filename or out_svg}: cannot write: {e.strerror or e}")
    finally:
        plt.close(fig)
    print(f"wrote {out_svg} and {out_png}")


# ---- errtime: `octray errtime --csv` -------------------------------------------------
ERRTIME_NUMBERS = ["ns_per_ray", "ns_min", "ns_max", "max_rel", "p99_rel", "pareto"]
PATH_COLOURS = {"scalar": "#2ca02c", "simd": "#1f77b4"}
MODE_MARKERS = {"exact": "o", "fast": "s", "approx": "^", "fast14": "D", "approx14": "v", "double": "P"}
SPARE_COLOURS = ["#9467bd", "#8c564b", "#e377c2", "#7f7f7f"]
SPARE_MARKERS = ["X", "*", "h", "<", ">", "p"]
FRONT_COLOUR = "#d62728"


def read_errtime_csv(path):
    """Rows of the CSV as dicts, with ERRTIME_NUMBERS as floats (and `lanes` when present)."""
    try:
        with open(path, newline="") as f:
            lines = list(csv.reader(f))
    except OSError as e:
        raise BadInput(f"{path}: cannot read: {e.strerror or e}")
    except (csv.Error, UnicodeDecodeError) as e:
        raise BadInput(f"{path}: not a CSV file: {e}")
    if not lines:
        raise BadInput(f"{path}: empty, expected the header of `octray errtime --csv`")
    header = lines[0]
    missing = [c for c in ["path", "mode"] + ERRTIME_NUMBERS if c not in header]
    if missing:
        raise BadInput(f"{path}: line 1: the header lacks {', '.join(missing)} (not `octray errtime --csv` output?)")
    rows = []
    for n, fields in enumerate(lines[1:], start=2):
        if not fields:
            continue
        if len(fields) != len(header):
            raise BadInput(f"{path}: line {n}: {len(fields)} fields, the header has {len(header)}")
        row = dict(zip(header, fields))
        for name in ERRTIME_NUMBERS + (["lanes"] if "lanes" in header else []):
            try:
                value = float(row[name])
            except ValueError:
                value = math.nan
            if not math.isfinite(value) or value < 0:
                raise BadInput(f"{path}: line {n}: {name}: expected a finite number >= 0, got '{row[name]}'")
            row[name] = value
        if not row["ns_min"] <= row["ns_per_ray"] <= row["ns_max"] or row["ns_min"] <= 0:
            raise BadInput(f"{path}: line {n}: expected 0 < ns_min <= ns_per_ray <= ns_max")
        rows.append(row)
    if not rows:
        raise BadInput(f"{path}: no data rows after the header")
    return rows


def style_for(keys, table, spare):
    """keys -> style: the table's where it has one, else the spare styles in order."""
    out, extra = {}, iter(spare * (len(keys) // len(spare) + 1))
    for k in keys:
        out[k] = table[k] if k in table else next(extra)
    return out


def unique(values):
    return list(dict.fromkeys(values))


def plot_errtime(csv_path, out_svg, title):
    rows = read_errtime_csv(csv_path)
    plt = load_matplotlib()
    from matplotlib.lines import Line2D
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    colours = style_for(unique(r["path"] for r in rows), PATH_COLOURS, SPARE_COLOURS)
    markers = style_for(unique(r["mode"] for r in rows), MODE_MARKERS, SPARE_MARKERS)
    positive = [e for r in rows for e in (r["max_rel"], r["p99_rel"]) if e > 0]
    floor = 10 ** math.floor(math.log10(min(positive))) / 10 if positive else 1e-12  # where an error of 0 is drawn

    def err(e):
        return max(e, floor)

    fig, ax = plt.subplots(figsize=FIGSIZE, layout="constrained")
    front = sorted((r for r in rows if r["pareto"]), key=lambda r: r["ns_per_ray"])
    if front:  # the front as a staircase, fastest first
        xs, ys = [], []
        for i, r in enumerate(front):
            if i:
                xs.append(r["ns_per_ray"]), ys.append(err(front[i - 1]["max_rel"]))
            xs.append(r["ns_per_ray"]), ys.append(err(r["max_rel"]))
        ax.plot(xs, ys, color=FRONT_COLOUR, alpha=0.5, lw=2, zorder=1)
        ax.plot([r["ns_per_ray"] for r in front], [err(r["max_rel"]) for r in front], "o", ms=13, mfc="none",
                mec=FRONT_COLOUR, mew=1.5, zorder=2)
    for r in rows:
        c, x = colours[r["path"]], r["ns_per_ray"]
        ax.plot([x, x], [err(r["max_rel"]), err(r["p99_rel"])], color=c, lw=0.8, ls=":", zorder=3)
        ax.plot([x], [err(r["p99_rel"])], marker="_", ms=9, mew=2, color=c, zorder=3)
        ax.errorbar([x], [err(r["max_rel"])], xerr=[[x - r["ns_min"]], [r["ns_max"] - x]], fmt=markers[r["mode"]],
                    ms=7, color=c, mec="black", mew=0.5, elinewidth=1, alpha=0.85, zorder=4)

    ax.set_yscale("log")
    ns = [v for r in rows for v in (r["ns_min"], r["ns_max"])]
    if max(ns) / min(ns) >= 3:  # scalar and SIMD an order apart: log, with plain tick labels
        ax.set_xscale("log")
        ax.xaxis.set_major_locator(LogLocator(subs=(1, 2, 3, 5)))
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.xaxis.set_minor_formatter(NullFormatter())
        scale = "log scale"
    else:
        scale = "linear"
    lanes = {r.get("lanes") for r in rows}
    per = f"; {int(lanes.pop())} rays a render" if len(lanes) == 1 and None not in lanes else ""
    ax.set_xlabel(f"ns per ray: median of the timed renders{per} ({scale})")
    ax.set_ylabel("relative radiance error vs reference (log scale)\nmarker: max, dash: p99")
    ax.set_title(title)
    ax.grid(True, which="major", color="#e4e4e4", lw=0.8)
    ax.set_axisbelow(True)
    if not positive or min(r["max_rel"] for r in rows) == 0 or min(r["p99_rel"] for r in rows) == 0:
        ax.text(0.01, 0.01, f"an error of 0 is drawn at {floor:.0e}", transform=ax.transAxes, fontsize=7,
                va="bottom")

    handles = [Line2D([], [], color=colours[p], lw=6, label=f"{p} path") for p in colours]
    handles += [Line2D([], [], ls="none", marker=markers[m], ms=7, color="#bbbbbb", mec="black", mew=0.5,
                       label=m) for m in markers]
    handles += [Line2D([], [], ls="none", marker="_", ms=9, mew=2, color="#777777", label="p99 rel. error"),
                Line2D([], [], color="#777777", lw=1, label="ns/ray min..max"),
                Line2D([], [], color=FRONT_COLOUR, alpha=0.5, lw=2, marker="o", ms=11, mfc="none", mec=FRONT_COLOUR,
                       label="Pareto front\n(max rel. error)")]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, borderaxespad=0)
    save(fig, plt, out_svg)


# ---- bench: bench-report's chart data ------------------------------------------------
BENCH_COLOURS = ["#9e9e9e", "#1f77b4", "#ff7f0e", "#ffbb78", "#2ca02c", "#9467bd"]


def read_bench_json(path):
    """{"series": [names], "groups": [{"label", "values": [rays/s or null per series], "notes": [...]}]}."""
    try:
        with open(path) as f:
            data = json.load(f)
    except OSError as e:
        raise BadInput(f"{path}: cannot read: {e.strerror or e}")
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise BadInput(f"{path}: not JSON: {e}")
    if not isinstance(data, dict) or not isinstance(data.get("series"), list) or not data["series"] \
            or not isinstance(data.get("groups"), list):
        raise BadInput(f"{path}: expected an object with a non-empty list \"series\" and a list \"groups\"")
    n = len(data["series"])
    if n > len(BENCH_COLOURS):
        raise BadInput(f"{path}: series: at most {len(BENCH_COLOURS)}, got {n}")
    for i, g in enumerate(data["groups"]):
        where = f"{path}: groups[{i}]"
        if not isinstance(g, dict) or not isinstance(g.get("label"), str) or not isinstance(g.get("values"), list):
            raise BadInput(f"{where}: expected {{\"label\": text, \"values\": [...]}}")
        if len(g["values"]) != n or len(g.get("notes", [""] * n)) != n:
            raise BadInput(f"{where}: values (and notes): one per series ({n})")
        for v in g["values"]:
            if v is not None and not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise BadInput(f"{where}: values: expected rays/s > 0 or null, got {v!r}")
    groups = [g for g in data["groups"] if any(v is not None for v in g["values"])]
    if not groups:
        raise BadInput(f"{path}: no group has a value")
    return data["series"], groups


def plot_bench(json_path, out_svg, title):
    series, groups = read_bench_json(json_path)
    plt = load_matplotlib()
    from matplotlib.patches import Patch

    bar, gap = 1.0, 0.6  # in bar heights
    bars = sum(sum(v is not None for v in g["values"]) for g in groups)
    height = max(FIGSIZE[1], 0.105 * (bars + gap * (len(groups) - 1)) + 1.0)  # a bar 7.5 pt high
    fig, ax = plt.subplots(figsize=(FIGSIZE[0], height), layout="constrained")
    y, ticks = 0.0, []
    values = [v for g in groups for v in g["values"] if v is not None]
    for g in groups:
        top = y
        notes = g.get("notes", [""] * len(series))
        for i, v in enumerate(g["values"]):
            if v is None:
                continue
            ax.barh(y, v, height=0.9 * bar, color=BENCH_COLOURS[i], align="edge")
            note = f" ({notes[i]})" if notes[i] else ""
            ax.text(v * 1.04, y + 0.45 * bar, f"{v / 1e6:.3g}M{note}", va="center", fontsize=6.5)
            y += bar
        ticks.append(((top + y) / 2, g["label"]))
        y += gap
    ax.set_xscale("log")
    lo = 10 ** math.floor(math.log10(min(values)))
    ax.set_xlim(lo, max(values) * 3)  # room for the value labels
    ax.set_ylim(y - gap + 0.3, -0.3)  # first group at the top
    ax.set_yticks([t for t, _ in ticks], [label for _, label in ticks], fontsize=8)
    ax.tick_params(axis="y", length=0)
    ax.set_xlabel("rays per second (median; log scale)")
    ax.set_title(title)
    ax.grid(True, axis="x", which="major", color="#dddddd", lw=0.8)
    ax.set_axisbelow(True)
    ax.legend(handles=[Patch(color=BENCH_COLOURS[i], label=s) for i, s in enumerate(series)], loc="best",
              framealpha=0.95)
    save(fig, plt, out_svg)


def main():
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="kind", required=True)
    e = sub.add_parser("errtime", help="error against ns/ray from `octray errtime --csv`")
    e.add_argument("csv")
    b = sub.add_parser("bench", help="rays/s per case from bench-report's bench_plot.json")
    b.add_argument("json")
    for p in (e, b):
        p.add_argument("out", metavar="OUT.svg", help="the SVG to write; the PNG goes beside it")
        p.add_argument("--title", default=None)
    a = ap.parse_args()
    try:
        if a.kind == "errtime":
            plot_errtime(a.csv, a.out, a.title or f"octray errtime: {os.path.basename(a.csv)}")
        else:
            plot_bench(a.json, a.out, a.title or "octray rays/s: scalar vs simd vs Embree (one thread)")
    except BadInput as e:
        fail(str(e), EXIT_BAD_INPUT)


if __name__ == "__main__":
    main()
