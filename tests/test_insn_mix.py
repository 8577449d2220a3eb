#!/usr/bin/env python3
"""CTest tools.insn_mix: scripts/insn-mix classes a hand-made callgrind profile right.

    test_insn_mix.py TOOL BINARY

The profile charges 7 to BINARY's first vfmadd, 13 to its first
vbroadcastss and 11 to its first ret, plus a call's inclusive cost (1000)
that must not be counted; insn-mix must print exactly those counts by kind.
"""

import os
import re
import subprocess
import sys
import tempfile

tool, binary = sys.argv[1], sys.argv[2]
disassembly = subprocess.run(["objdump", "-d", "--no-show-raw-insn", binary], capture_output=True, text=True,
                             check=True).stdout
first = {}
for line in disassembly.splitlines():
    m = re.match(r"\s+([0-9a-f]+):\s+(\S+)", line)
    if m:
        for prefix in ("vfmadd", "vbroadcastss", "ret"):
            if prefix not in first and m.group(2).startswith(prefix):
                first[prefix] = int(m.group(1), 16)
assert len(first) == 3, f"{binary} lacks one of vfmadd, vbroadcastss, ret: {first}"

profile = f"""# callgrind format
version: 1
creator: test_insn_mix.py
events: Ir
ob=(1) {binary}
fn=(1) f
0x{first['vfmadd']:x} 1 7
0x{first['vbroadcastss']:x} 1 13
calls=1 0x{first['ret']:x} 1
0x{first['ret']:x} 1 1000
0x{first['ret']:x} 1 11
"""
with tempfile.TemporaryDirectory() as tmp:
    path = os.path.join(tmp, "callgrind.out")
    with open(path, "w") as f:
        f.write(profile)
    out = subprocess.run([sys.executable, tool, path, binary], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    counts = {m.group(1).strip(): float(m.group(2))
              for m in re.finditer(r"^(.+?)\s+([0-9.]+)(?:\s+[0-9.]+%)?$", out.stdout, re.M)}
    expected = {"FP multiply, FMA": 7, "broadcasts of scene data": 13, "integer, branches": 11,
                "vector ALU work (sum of the rest)": 7, "total": 31}
    for kind, n in expected.items():
        assert counts.get(kind) == n, f"{kind}: expected {n}, got {counts.get(kind)}\n{out.stdout}"

    # Not a profile: a clear error, not a traceback.
    bad = subprocess.run([sys.executable, tool, binary, binary], capture_output=True, text=True)
    assert bad.returncode != 0 and "not a callgrind profile" in bad.stderr, bad.stderr
print("insn-mix: counts by kind as charged")
