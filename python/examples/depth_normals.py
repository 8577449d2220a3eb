#!/usr/bin/env python3
"""Loads scenes/models.json, casts a grid of rays at it and plots depth and normals.

    PYTHONPATH=build/python python3 python/examples/depth_normals.py [OUT.png]

writes docs/python_depth_normals.png by default (docs/python.md shows it).
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import octray

root = pathlib.Path(__file__).resolve().parents[2]
out = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else root / "docs" / "python_depth_normals.png"

scene = octray.load(root / "scenes" / "models.json")

# A pinhole grid of our own: 480 x 300 rays from a point above and in front of the models.
width, height = 480, 300
eye = np.array([0.0, 3.6, 7.5])
forward = np.array([0.0, 0.35, 0.0]) - eye
forward /= np.linalg.norm(forward)
right = np.cross(forward, [0.0, 1.0, 0.0])
right /= np.linalg.norm(right)
up = np.cross(right, forward)
half_h = np.tan(np.radians(38) / 2)
half_w = half_h * width / height
u = (np.arange(width) + 0.5) / width * 2 - 1    # left to right
v = 1 - (np.arange(height) + 0.5) / height * 2  # top to bottom
uu, vv = np.meshgrid(u * half_w, v * half_h)
directions = forward + uu[..., None] * right + vv[..., None] * up  # (H, W, 3), not unit
origins = np.broadcast_to(eye, directions.shape)                   # a view, not a copy

hits = scene.intersect(origins.reshape(-1, 3), directions.reshape(-1, 3))
# t is in units of |d|: times |d| it is the distance along the ray.
depth = (hits["t"] * np.linalg.norm(directions.reshape(-1, 3), axis=1)).reshape(height, width)
normal = hits["normal"].reshape(height, width, 3)
primitive = hits["primitive"].reshape(height, width)

info = scene.info()
first_mesh = 1  # object 0 is the ground plane; then each mesh's triangles
bounds = np.cumsum([first_mesh] + [m["triangles"] for m in info["meshes"]])
print("rays %d, hits %d, masked %d; triangles hit per mesh: %s" % (
    depth.size, (primitive >= 0).sum(), hits["masked"],
    [int(((primitive >= lo) & (primitive < hi)).sum()) for lo, hi in zip(bounds[:-1], bounds[1:])]))

fig, axes = plt.subplots(1, 2, figsize=(11, 3.6), constrained_layout=True)
shown = np.where(np.isfinite(depth), depth, np.nan)  # misses: blank
# The ground plane runs to the horizon: the colour scale spans the models (primitives past object 0).
models = depth[primitive >= first_mesh]
im = axes[0].imshow(shown, cmap="viridis_r", vmin=0.9 * models.min(), vmax=1.1 * models.max())
axes[0].set_title("depth (distance along the ray)")
fig.colorbar(im, ax=axes[0], shrink=0.85)
axes[1].imshow(np.where((primitive >= 0)[..., None], (normal + 1) / 2, 1.0))
axes[1].set_title("shading normal, (n + 1) / 2 as RGB")
for ax in axes:
    ax.set_xticks([])
    ax.set_yticks([])
fig.suptitle("octray.load('scenes/models.json').intersect(origins, directions): %d x %d rays" % (width, height))
fig.savefig(out, dpi=100)
print("wrote", out)
