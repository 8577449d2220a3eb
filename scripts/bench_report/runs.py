"""Running a benchmark binary into a JSON file, and reading the medians back."""

import json
import os
import subprocess
import sys
import time

# The repository's tools/ folder (plot.py is there; git runs there): beside
# scripts/, the folder of the bench-report script.
TOOLS_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "tools")


def run(cmd, out_path):
    print("bench-report: " + " ".join(cmd), file=sys.stderr, flush=True)
    t0 = time.time()
    with open(out_path, "w") as out:
        proc = subprocess.run(cmd, stdout=out)
    print(f"bench-report:   {time.time() - t0:.0f} s, exit {proc.returncode}", file=sys.stderr, flush=True)
    return proc.returncode


def load_medians(path):
    """run_name -> fields of its median aggregate (or of its error entry)."""
    with open(path) as f:
        text = f.read()
    # A --filter that matches nothing in one binary leaves its output empty.
    data = json.loads(text) if text.strip() else {}
    rows = {}
    for b in data.get("benchmarks", []):
        name = b.get("run_name", b["name"])
        if b.get("error_occurred"):
            rows[name] = {"error": b.get("error_message", "error")}
        elif b.get("run_type") == "aggregate" and b.get("aggregate_name") == "median":
            rows[name] = b
        elif b.get("run_type") == "iteration" and name not in rows:
            rows[name] = b  # repetitions=1: no aggregates
    return data.get("context", {}), rows
