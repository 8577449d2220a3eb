"""octray for Python: numpy in, numpy out, the same packet kernels as the C++ library.

    import octray
    scene = octray.load("scenes/models.json")
    hits = scene.intersect(origins, directions)      # (N, 3) arrays, any float dtype
    hits["t"], hits["primitive"], hits["normal"], hits["masked"]

Scenes come from a JSON file (:func:`load`) or a dict of the same schema
(:class:`Scene`), where a mesh may give ``"vertices"`` and ``"indices"`` arrays
instead of a ``"file"``. A bad scene raises :class:`SceneError` (a ValueError)
with the one-line message of the ``octray`` command line, JSON path included.
docs/python.md is the guide.
"""

import json as _json
import os as _os
from collections.abc import Mapping as _Mapping

import numpy as _np

from . import _octray
from ._octray import SceneError

__all__ = ["Scene", "SceneError", "load", "errtime", "stability"]
__version__ = "0.1.0"

SceneError.__module__ = "octray"
SceneError.__doc__ = """A scene that octray rejects (a ValueError).

str(error) is exactly the message of the octray command line, one line:
"FILE: JSON_PATH: problem" for a file, "JSON_PATH: problem" for a dict, e.g.
"objects[0].radius: must be > 0, got -1"."""


class Scene:
    """A scene, loaded and compiled once for the packet kernels.

    ``Scene(d)`` takes a dict of the scene JSON's schema (docs/scene-format.md).
    A ``"mesh"`` object may give ``"vertices"``, an (N, 3) array of numbers, and
    ``"indices"``, an (M, 3) array of integers (three vertex indices a triangle),
    instead of ``"file"``; a ``"transform"`` applies to them as to a file. Model
    files named by ``"file"`` are read relative to ``base_dir`` (default: the
    working directory). Every check is the JSON loader's, with its messages:
    a bad value raises :class:`SceneError`.

    A Scene is immutable; its methods release the GIL while the kernels run, so
    threads may share one.
    """

    __slots__ = ("_h",)

    def __init__(self, d, *, base_dir=None):
        if not isinstance(d, _Mapping):
            raise TypeError("d: expected a dict of the scene JSON's schema, got " + type(d).__name__)
        text, arrays = _scene_json(d)
        self._h = _octray._from_json(text, "" if base_dir is None else _os.fspath(base_dir), arrays)

    @classmethod
    def _wrap(cls, handle):
        scene = cls.__new__(cls)
        scene._h = handle
        return scene

    def intersect(self, origins, directions, tmin=0.0, tmax=float("inf"), *, path="simd", threads=0):
        """Closest hits of rays, in the caller's order.

        origins, directions: (N, 3) arrays of any float dtype, C-contiguous or
        not (float32 and float64 are read in place); directions need not be
        unit: t is in units of |d|. A hit has tmin < t < tmax.
        path: "simd" or "scalar". threads: 0 = every core.

        Returns a dict: "t" (N,) float32, inf on a miss; "primitive" (N,) int32,
        -1 on a miss, numbered as `octray info` numbers them (objects, then mesh
        triangles); "normal" (N, 3) float32, the unit shading normal facing the
        ray (0 on a miss); "masked": how many rays were masked off as invalid
        input (NaN or infinite components, a zero direction): they are misses.
        """
        return self._h.intersect(origins, directions, tmin, tmax, path=path, threads=threads)

    def occluded(self, origins, directions, tmin=0.0, tmax=float("inf"), *, path="simd", threads=0):
        """Whether anything lies on each ray in (tmin, tmax): an (N,) bool array.

        Arguments as for :meth:`intersect`; invalid rays (NaN, zero direction) are not occluded.
        """
        return self._h.occluded(origins, directions, tmin, tmax, path=path, threads=threads)

    def render(self, path="simd", width=None, threads=0):
        """The HDR radiance of the scene's camera image: (H, W, 3) float32, top row first.

        Bit-identical to `octray render --hdr` with the same path ("simd",
        "scalar" or "reference") and thread count (0 = every core); width, as
        the CLI's --width, renders at that width with the same aspect ratio.
        """
        return self._h.render(path, width, threads)

    def tonemap(self, hdr, path="simd"):
        """Display colours of HDR radiance: (..., 3) float -> (..., 3) uint8.

        The scene's tone map and gamma by the packet kernels, then 8 bits as
        floor(255 c + 0.5): tonemap(render()) is the PNG of `octray render`.
        """
        return self._h.tonemap(hdr, path)

    def camera_rays(self):
        """The camera's rays, as the camera kernel makes them: (origins, directions), each (H, W, 3) float32."""
        return self._h.camera_rays()

    def verify(self, threads=0):
        """`octray verify`: the scalar and SIMD paths against the double reference.

        Returns {"scalar": {...}, "simd": {...}, "tolerance": {...}, "threads": n,
        "pass": bool}; a path's dict holds the error table's numbers (max_rel,
        mean_rel, p99_rel, max_scaled, max_ulp, compared, mismatched,
        mismatched_silhouette, shadow_edges, occlusion_grazing, nonfinite, ...)
        and "verdict" ("ok" or "OVER TOLERANCE").
        """
        return self._h.verify(threads)

    def info(self):
        """`octray info` as a dict: image size, primitives per type, meshes, lights, features, kernels."""
        return self._h.info()

    @property
    def width(self):
        """The camera image's width in pixels."""
        return self._h.width

    @property
    def height(self):
        """The camera image's height in pixels."""
        return self._h.height

    @property
    def primitive_count(self):
        """Objects plus mesh triangles: primitive ids are 0 .. primitive_count - 1."""
        return self._h.primitive_count

    def __repr__(self):
        src = self._h.source
        return "<octray.Scene %s%dx%d, %d primitives>" % (
            (src + ", ") if src else "", self.width, self.height, self.primitive_count)


def load(path):
    """Loads a scene JSON file (and the model files it names): a :class:`Scene`.

    Raises :class:`SceneError` with the CLI's message ("FILE: JSON_PATH: problem").
    """
    return Scene._wrap(_octray._load(_os.fspath(path)))


def errtime(scene, threads=1, min_repetitions=5, max_repetitions=50, min_seconds=0.5):
    """`octray errtime`: error against run time for every path x precision mode this CPU runs.

    A list of dicts, one per row: path, precision, isa, kernel, ns_per_ray
    (median), ns_min, ns_max, repetitions, pareto, the agreement numbers of
    :meth:`Scene.verify`, the mode's bound on max_scaled with the verdict
    (bound, pass, verdict "ok" or "OVER BOUND", as the CLI's columns), and
    the scene's kappa, width and height.
    """
    if not isinstance(scene, Scene):
        raise TypeError("scene: expected an octray.Scene, got " + type(scene).__name__)
    return _octray._errtime(scene._h, threads, min_repetitions, max_repetitions, min_seconds)


def stability():
    """`octray stability`: the catalogue of stiff and extreme cases.

    A list of dicts, one per case: case, expectation, bound_text, bound,
    results ({"scalar/exact": {"error", "pass", "note"}, ..., "naive": ...}),
    pass and verdict ("pass" or "FAIL"; the naive column is not in it).
    """
    return _octray._stability()


# ---- Scene(dict) ---------------------------------------------------------------

def _json_default(value):
    if isinstance(value, _np.ndarray):
        return value.tolist()
    if isinstance(value, _np.generic):
        return value.item()
    raise TypeError("scene dict: a %s is not a JSON value" % type(value).__name__)


def _mesh_array(value, where, kinds, what, dtype):
    """A mesh's "vertices" or "indices" as a C-contiguous (rows, 3) array of dtype."""
    a = _np.asarray(value)
    if a.dtype.kind not in kinds:
        raise TypeError("%s: must be an array of %s, got dtype %s" % (where, what, a.dtype))
    if a.ndim != 2 or a.shape[1] != 3:
        raise SceneError("%s: must be an (%s, 3) array, got shape %s" % (where, "N" if kinds == "fiu" else "M", a.shape))
    if kinds == "iu" and a.size and (a.min() < 0 or a.max() > 0xFFFFFFFF):
        k = int(_np.flatnonzero((a < 0) | (a > 0xFFFFFFFF))[0])
        raise SceneError("%s[%d]: index %d out of range (indices are 0 .. 2^32 - 1)" % (where, k, a.flat[k]))
    return _np.ascontiguousarray(a, dtype=dtype)


def _scene_json(d):
    """The dict as JSON text, mesh arrays taken out: (text, {object index: (vertices, indices)})."""
    doc = dict(d)
    arrays = {}
    objects = doc.get("objects")
    if isinstance(objects, (list, tuple)):
        out = []
        for i, o in enumerate(objects):
            if isinstance(o, _Mapping) and o.get("type") == "mesh" and ("vertices" in o or "indices" in o):
                o = dict(o)
                v = ix = None
                if "vertices" in o:
                    v = _mesh_array(o["vertices"], "objects[%d].vertices" % i, "fiu", "numbers", _np.float64)
                if "indices" in o:
                    ix = _mesh_array(o["indices"], "objects[%d].indices" % i, "iu", "integers", _np.uint32)
                arrays[i] = (v, ix)
                for key in ("vertices", "indices"):
                    if key in o:
                        o[key] = None
            out.append(o)
        doc["objects"] = out
    try:
        text = _json.dumps(doc, default=_json_default, allow_nan=False)
    except ValueError as e:
        raise SceneError("scene dict: every number must be finite (%s)" % e) from None
    return text, arrays
