"""Shared fixtures and brute-force references of the octray module's tests (run by CTest as python.pytest)."""
import os
import pathlib

import numpy as np
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


def triangle_t(a, e1, e2, o, d):
    """Moller-Trumbore in float64 of rays (o, d) against the triangle (a, a + e1, a + e2):
    t in units of |d|, inf where the ray misses it (or runs parallel to it)."""
    p = np.cross(d, e2)
    det = p @ e1
    inv = 1.0 / np.where(det == 0, np.nan, det)
    s = o - a
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    w = np.einsum("ij,ij->i", d, q) * inv
    t = (q @ e2) * inv
    return np.where((u >= 0) & (w >= 0) & (u + w <= 1) & (t > 0), t, np.inf)


def height_field(xs, zs, height):
    """A grid mesh over xs x zs with y = height(x, z): (vertices (N, 3), faces (M, 3)), two
    triangles a cell, wound (v1 - v0) x (v2 - v0) upward."""
    gx, gz = np.meshgrid(xs, zs)
    verts = np.stack([gx.ravel(), height(gx, gz).ravel(), gz.ravel()], axis=1)
    kx, kz = len(xs) - 1, len(zs) - 1
    a = (np.arange(kz)[:, None] * (kx + 1) + np.arange(kx)[None, :]).ravel()
    faces = np.empty((2 * len(a), 3), np.int64)
    faces[0::2] = np.stack([a, a + kx + 1, a + 1], axis=1)
    faces[1::2] = np.stack([a + 1, a + kx + 1, a + kx + 2], axis=1)
    return verts, faces
