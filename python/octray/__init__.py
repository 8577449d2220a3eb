"""octray for Python: numpy in, numpy out, the same packet kernels as the C++ library.

    import octray
    scene = octray.Scene.from_meshes([(vertices, faces)])   # geometry only: no camera, no materials
    hits = scene.intersect(origins, directions)             # (N, 3) arrays, any float dtype
    hits["t"], hits["geometry_id"], hits["primitive_id"], hits["uv"], hits["geometric_normal"]

Scenes come from a JSON file (:func:`load`), a dict of the same schema
(:class:`Scene`, where a mesh may give ``"vertices"`` and ``"indices"``
arrays instead of a ``"file"``, and the camera, lights and materials may be
left out to cast rays alone) or meshes and shapes (:meth:`Scene.from_meshes`).
A bad scene raises :class:`SceneError` (a ValueError) with the one-line
message of the ``octray`` command line, JSON path included.
docs/python.md is the guide.
"""

import json as _json
import re as _re
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
    instead of ``"file"``; a ``"transform"`` applies to them as to a file, and a
    zero-area triangle is dropped and counted, as in a model file. Model files
    named by ``"file"`` are read relative to ``base_dir`` (default: the working
    directory). Every check is the JSON loader's, with its messages: a bad
    value raises :class:`SceneError`.

    A dict may leave out ``"camera"``, ``"lights"`` and ``"materials"`` (its
    objects then name no ``"material"``): such a geometry-only scene can
    :meth:`intersect` and :meth:`occluded`; :meth:`render`, :meth:`shade`,
    :meth:`camera_rays` and :meth:`verify` raise a ValueError naming what it
    lacks. Geometry ids number the dict's ``"objects"``: entry k is geometry k.

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
    def from_meshes(cls, meshes=(), *, objects=(), base_dir=None):
        """A geometry-only scene of triangle meshes and other shapes, for ray casting.

        meshes: a sequence of (vertices, indices) pairs, an (N, 3) array of
        numbers and an (M, 3) array of integers each. objects: a sequence of
        dicts of the scene JSON's "objects" schema without "material"
        ({"type": "sphere", "center": [0, 0, 0], "radius": 1}, a "mesh" with a
        "file" or arrays and a "transform", ...). Geometry ids: the meshes
        0 .. len(meshes) - 1 in order, then the objects. The same as
        Scene({"objects": [{"type": "mesh", "vertices": v, "indices": i}, ...] + objects}).
        """
        entries = []
        for k, mesh in enumerate(meshes):
            try:
                vertices, indices = mesh
            except (TypeError, ValueError):
                raise TypeError("meshes[%d]: expected a (vertices, indices) pair, got %s"
                                % (k, type(mesh).__name__)) from None
            entries.append({"type": "mesh", "vertices": vertices, "indices": indices})
        count = len(entries)
        entries.extend(objects)
        try:
            return cls({"objects": entries}, base_dir=base_dir)
        except (SceneError, TypeError) as e:
            # The messages name the dict's objects[k]: name the caller's own lists.
            def rename(m):
                k = int(m.group(1))
                return "meshes[%d]" % k if k < count else "objects[%d]" % (k - count)
            message = _re.sub(r"^objects\[(\d+)\]", rename, str(e))
            if message == str(e):
                raise
            raise type(e)(message) from None

    @classmethod
    def _wrap(cls, handle):
        scene = cls.__new__(cls)
        scene._h = handle
        return scene

    def intersect(self, origins, directions, tmin=0.0, tmax=float("inf"), *, path="simd", mode="exact", threads=0):
        """Closest hits of rays, in the caller's order.

        origins, directions: (N, 3) arrays of any float dtype, C-contiguous or
        not (float32 and float64 are read in place); directions need not be
        unit: t is in units of |d|. tmin, tmax: numbers, or (N,) arrays (one
        interval a ray); a hit has tmin < t < tmax. path: "simd" or "scalar".
        mode: the precision mode ("exact", "fast", "approx", "fast14",
        "approx14", "double"). threads: 0 = every core.

        Returns a dict; on a miss: inf, -1, 0 as below.
        "t" (N,) float32, inf on a miss.
        "geometry_id" (N,) int32: the hit object's index in the scene's
        "objects" (a mesh, however many meshes its file holds, is one), -1.
        "primitive_id" (N,) int32: the triangle's index in its mesh as the
        caller's face array or the model file numbers it (zero-area triangles
        counted); 0 for other shapes; -1.
        "uv" (N, 2) float32: triangles' barycentrics, hit = (1 - u - v) v0 +
        u v1 + v v2 (Embree's and Open3D's); a rectangle's (s, t), hit =
        corner + s a + t b; 0 for other shapes.
        "geometric_normal" (N, 3) float32: unit, the triangle's winding
        (v1 - v0) x (v2 - v0), the outward side of a sphere or box, a plane's
        or disk's normal, a rectangle's a x b: not turned to face the ray.
        "primitive" (N,) int32: the global number (objects, then mesh
        triangles), as `octray info` numbers them.
        "normal" (N, 3) float32: the kernels' unit shading normal, facing the ray.
        "masked": how many rays were masked off as invalid input (NaN or
        infinite components, a zero direction, an empty interval): they are misses.
        """
        return self._h.intersect(origins, directions, tmin, tmax, path=path, mode=mode, threads=threads)

    def occluded(self, origins, directions, tmin=0.0, tmax=float("inf"), *, path="simd", mode="exact", threads=0):
        """Whether anything lies on each ray in (tmin, tmax): an (N,) bool array.

        Arguments as for :meth:`intersect`; invalid rays (NaN, zero direction) are not occluded.
        """
        return self._h.occluded(origins, directions, tmin, tmax, path=path, mode=mode, threads=threads)

    def shade(self, origins, directions, tmin=0.0, tmax=float("inf"), *, path="simd", mode="exact", threads=0):
        """HDR radiance seen along each ray: (N, 3) float32, as Kernel::shade gives it.

        Arguments as for :meth:`intersect`. Each ray is intersected and its hit
        shaded with the scene's lights and materials (a miss or an invalid ray:
        the background). Where the scene has ambient occlusion, ray i draws the
        occlusion samples of pixel i (the same rays in the same order give the
        same radiance). Needs materials (not a geometry-only scene).
        """
        return self._h.shade(origins, directions, tmin, tmax, path=path, mode=mode, threads=threads)

    def render(self, path="simd", width=None, threads=0, *, mode="exact"):
        """The HDR radiance of the scene's camera image: (H, W, 3) float32, top row first.

        Bit-identical to `octray render --hdr` with the same path ("simd",
        "scalar" or "reference") and thread count (0 = every core); width, as
        the CLI's --width, renders at that width with the same aspect ratio.
        mode: a precision mode as for :meth:`intersect` (the CLI renders
        "exact"; "reference" takes "exact" only). Needs a camera and materials.
        """
        return self._h.render(path, width, threads, mode=mode)

    def tonemap(self, hdr, path="simd"):
        """Display colours of HDR radiance: (..., 3) float -> (..., 3) uint8.

        The scene's tone map and gamma by the packet kernels, then 8 bits as
        floor(255 c + 0.5): tonemap(render()) is the PNG of `octray render`.
        """
        return self._h.tonemap(hdr, path)

    def camera_rays(self):
        """The camera's rays, as the camera kernel makes them: (origins, directions), each (H, W, 3) float32.

        Needs a camera (not a geometry-only scene).
        """
        return self._h.camera_rays()

    def verify(self, threads=0):
        """`octray verify`: the scalar and SIMD paths against the double reference (needs a camera and materials).

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
        """The camera image's width in pixels; None without a camera."""
        return self._h.width

    @property
    def height(self):
        """The camera image's height in pixels; None without a camera."""
        return self._h.height

    @property
    def geometry_only(self):
        """True when the scene has no camera or no materials: it can intersect and occluded only."""
        return not (self._h.has_camera and self._h.has_materials)

    @property
    def primitive_count(self):
        """Objects plus mesh triangles (zero-area ones dropped): "primitive" numbers 0 .. primitive_count - 1."""
        return self._h.primitive_count

    def __repr__(self):
        src = self._h.source
        size = "%dx%d" % (self.width, self.height) if self.width is not None else "no camera"
        return "<octray.Scene %s%s, %d primitives>" % ((src + ", ") if src else "", size, self.primitive_count)


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
