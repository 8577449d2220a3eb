"""python/examples/depth_normals.py (docs/python.md's example) runs and writes its picture."""
import os
import subprocess
import sys

import pytest

from conftest import SOURCE


def test_depth_normals_example(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "depth_normals.png"
    r = subprocess.run([sys.executable, str(SOURCE / "python" / "examples" / "depth_normals.py"), str(out)],
                       capture_output=True, text=True, env=dict(os.environ))
    assert r.returncode == 0, r.stderr
    assert "masked 0" in r.stdout and out.stat().st_size > 10000
