"""Shared fixtures of the octray module's tests (run by CTest as python.pytest)."""
import os
import pathlib

import pytest

import octray

SOURCE = pathlib.Path(os.environ.get("OCTRAY_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


def sphere_scene(spheres, width=16, height=12, extra=None):
    """A dict scene of spheres [(center, radius), ...], one material."""
    d = {
        "camera": {"type": "pinhole", "eye": [0, 0, 10], "look_at": [0, 0, 0], "up": [0, 1, 0],
                   "fov_y": 40, "width": width, "height": height},
        "ambient": {"ls": 0.2},
        "lights": [{"type": "directional", "direction": [1, 1, 1], "ls": 1.0}],
        "materials": {"m": {"type": "matte", "ka": 0.25, "kd": 0.65, "cd": [1, 0.5, 0.25]}},
        "objects": [{"type": "sphere", "center": list(c), "radius": r, "material": "m"} for c, r in spheres],
    }
    if extra:
        d.update(extra)
    return d


@pytest.fixture(scope="session")
def source_dir():
    return SOURCE


@pytest.fixture(scope="session")
def models():
    return octray.load(SOURCE / "scenes" / "models.json")
