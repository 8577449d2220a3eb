"""Type stubs of the octray package (docs/python.md); the docstrings are the module's own."""

import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class SceneError(ValueError):
    """A scene that octray rejects: str() is the CLI's one-line message ("FILE: JSON_PATH: problem")."""

_Path = Union[str, "os.PathLike[str]"]
_Interval = Union[float, npt.ArrayLike]  # one number for all rays, or one per ray

class Scene:
    """A scene, loaded and compiled once. Scene(d) takes a dict of the scene JSON's schema; a mesh
    may give "vertices" ((N, 3) numbers) and "indices" ((M, 3) integers) instead of "file"; without
    "camera" or "materials" it is geometry-only (intersect and occluded only)."""

    def __init__(self, d: Mapping[str, Any], *, base_dir: Optional[_Path] = None) -> None: ...
    @classmethod
    def from_meshes(
        cls,
        meshes: Sequence[Tuple[npt.ArrayLike, npt.ArrayLike]] = (),
        *,
        objects: Sequence[Mapping[str, Any]] = (),
        base_dir: Optional[_Path] = None,
    ) -> "Scene":
        """A geometry-only scene: (vertices, indices) meshes, then objects (dicts without "material");
        geometry ids in that order."""
    def intersect(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        tmin: _Interval = 0.0,
        tmax: _Interval = ...,
        *,
        path: str = "simd",
        mode: str = "exact",
        threads: int = 0,
    ) -> Dict[str, Any]:
        """Closest hits: {"t": (N,) float32 (inf: miss), "geometry_id": (N,) int32 (-1: miss),
        "primitive_id": (N,) int32 (-1: miss), "uv": (N, 2) float32, "geometric_normal": (N, 3) float32,
        "primitive": (N,) int32 (-1: miss), "normal": (N, 3) float32, "masked": int (invalid rays)}."""
    def occluded(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        tmin: _Interval = 0.0,
        tmax: _Interval = ...,
        *,
        path: str = "simd",
        mode: str = "exact",
        threads: int = 0,
    ) -> npt.NDArray[np.bool_]:
        """Whether anything lies on each ray in (tmin, tmax): (N,) bool."""
    def shade(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        tmin: _Interval = 0.0,
        tmax: _Interval = ...,
        *,
        path: str = "simd",
        mode: str = "exact",
        threads: int = 0,
    ) -> npt.NDArray[np.float32]:
        """HDR radiance along each ray, (N, 3) float32: intersect, then Kernel::shade."""
    def render(
        self, path: str = "simd", width: Optional[int] = None, threads: int = 0, *, mode: str = "exact"
    ) -> npt.NDArray[np.float32]:
        """HDR radiance (H, W, 3) float32, top row first; bit-identical to `octray render --hdr`."""
    def tonemap(self, hdr: npt.ArrayLike, path: str = "simd") -> npt.NDArray[np.uint8]:
        """Display colours, 8 bits: tonemap(render()) is the PNG of `octray render`."""
    def camera_rays(self) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
        """The camera kernel's rays: (origins, directions), each (H, W, 3) float32."""
    def verify(self, threads: int = 0) -> Dict[str, Any]:
        """`octray verify`: per path ("scalar", "simd") the error table's numbers and "verdict"."""
    def info(self) -> Dict[str, Any]:
        """`octray info` as a dict."""
    @property
    def width(self) -> Optional[int]: ...
    @property
    def height(self) -> Optional[int]: ...
    @property
    def geometry_only(self) -> bool: ...
    @property
    def primitive_count(self) -> int: ...

def load(path: _Path) -> Scene:
    """Loads a scene JSON file and its model files; SceneError on a bad scene."""

def errtime(
    scene: Scene, threads: int = 1, min_repetitions: int = 5, max_repetitions: int = 50, min_seconds: float = 0.5
) -> List[Dict[str, Any]]:
    """`octray errtime`: one dict per path x precision mode."""

def stability() -> List[Dict[str, Any]]:
    """`octray stability`: one dict per case of the catalogue."""
