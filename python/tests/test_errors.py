"""Every error path: scenes (SceneError with the CLI's message), arguments (ValueError / TypeError naming them)."""
import copy
import json
import os
import subprocess

import numpy as np
import pytest

import octray
from conftest import SOURCE, sphere_scene

CLI = os.environ.get("OCTRAY_CLI", "")


def cli_message(path):
    """The CLI's one line on stderr, without its "octray: " prefix."""
    r = subprocess.run([CLI, "info", str(path)], capture_output=True, text=True)
    assert r.returncode == 2
    line = r.stderr.strip()
    assert line.startswith("octray: ") and "\n" not in line
    return line[len("octray: "):]


def test_scene_error_is_a_value_error():
    assert issubclass(octray.SceneError, ValueError)


def test_dict_errors_carry_the_json_path():
    d = sphere_scene([((0, 0, 0), -1)])
    with pytest.raises(octray.SceneError) as e:
        octray.Scene(d)
    assert str(e.value) == "objects[0].radius: must be > 0, got -1"
    d = sphere_scene([((0, 0, 0), 1)])
    d["objects"][0]["radius"] = "big"
    with pytest.raises(octray.SceneError, match=r'^objects\[0\]\.radius: must be a number, got a string \("big"\)$'):
        octray.Scene(d)
    d = sphere_scene([((0, 0, 0), 1)])
    d["objects"][0]["material"] = "nope"
    with pytest.raises(octray.SceneError, match=r'^objects\[0\]\.material: unknown material "nope"'):
        octray.Scene(d)
    d = sphere_scene([((0, 0, 0), 1)])
    d["camara"] = {}
    with pytest.raises(octray.SceneError, match=r"^camara: unknown field"):
        octray.Scene(d)
    d = sphere_scene([((0, 0, 0), 1)])
    d["objects"][0]["radius"] = float("nan")
    with pytest.raises(octray.SceneError, match="finite"):
        octray.Scene(d)
    with pytest.raises(TypeError, match="^d: expected a dict"):
        octray.Scene([1, 2])
    d = sphere_scene([((0, 0, 0), 1)])
    d["objects"][0]["radius"] = object()
    with pytest.raises(TypeError, match="scene dict"):
        octray.Scene(d)


def test_numpy_values_in_a_dict():
    d = sphere_scene([((0, 0, 0), 1)])
    d["objects"][0]["center"] = np.zeros(3, np.float32)
    d["objects"][0]["radius"] = np.float64(1.0)
    d["camera"]["width"] = np.int64(16)
    assert octray.Scene(d).primitive_count == 1


def test_file_errors_match_the_cli(tmp_path):
    bad = tmp_path / "bad.json"
    d = sphere_scene([((0, 0, 0), 1), ((1, 0, 0), -1)])
    bad.write_text(json.dumps(d))
    with pytest.raises(octray.SceneError) as e:
        octray.load(bad)
    assert str(e.value) == f"{bad}: objects[1].radius: must be > 0, got -1"
    syntax = tmp_path / "syntax.json"
    syntax.write_text('{\n  "camera": ,\n}')
    with pytest.raises(octray.SceneError) as e2:
        octray.load(str(syntax))
    missing = tmp_path / "missing.json"
    with pytest.raises(octray.SceneError, match="cannot open"):
        octray.load(missing)
    model = tmp_path / "model.json"
    d = sphere_scene([((0, 0, 0), 1)])
    d["objects"].append({"type": "mesh", "file": "nothere.ply", "material": "m"})
    model.write_text(json.dumps(d))
    with pytest.raises(octray.SceneError) as e3:
        octray.load(model)
    assert str(e3.value).startswith(f"{model}: objects[1].file: nothere.ply: ")
    if CLI:
        assert str(e.value) == cli_message(bad)
        assert str(e2.value) == cli_message(syntax)
        assert str(e3.value) == cli_message(model)


def test_relative_model_files_and_base_dir(tmp_path):
    d = sphere_scene([])
    d["objects"] = [{"type": "mesh", "file": "BoxTextured.glb", "material": "m"}]
    with pytest.raises(octray.SceneError, match=r"^objects\[0\]\.file: BoxTextured\.glb: cannot open"):
        octray.Scene(d)
    base = "/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary"
    if os.path.exists(base):
        assert octray.Scene(d, base_dir=base).primitive_count == 12


def mesh_dict(verts, tris, **extra):
    d = sphere_scene([])
    d["objects"] = [{"type": "sphere", "center": [0, 5, 0], "radius": 1, "material": "m"},
                    dict({"type": "mesh", "vertices": verts, "indices": tris, "material": "m"}, **extra)]
    return d


TRI_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
TRI_I = np.array([[0, 1, 2], [1, 3, 2]])


def test_mesh_array_errors():
    assert octray.Scene(mesh_dict(TRI_V, TRI_I)).primitive_count == 3
    assert octray.Scene(mesh_dict(TRI_V.tolist(), TRI_I.tolist())).primitive_count == 3
    with pytest.raises(octray.SceneError, match=r"^objects\[1\]\.vertices: must be an \(N, 3\) array, got shape \(12,\)$"):
        octray.Scene(mesh_dict(TRI_V.ravel(), TRI_I))
    with pytest.raises(octray.SceneError, match=r"^objects\[1\]\.indices: must be an \(M, 3\) array"):
        octray.Scene(mesh_dict(TRI_V, TRI_I.ravel()))
    with pytest.raises(TypeError, match=r"^objects\[1\]\.indices: must be an array of integers, got dtype float64$"):
        octray.Scene(mesh_dict(TRI_V, TRI_I.astype(float)))
    with pytest.raises(TypeError, match=r"^objects\[1\]\.vertices: must be an array of numbers"):
        octray.Scene(mesh_dict(np.array([["a", "b", "c"]]), TRI_I))
    with pytest.raises(octray.SceneError, match=r"^objects\[1\]\.indices\[1\]: index -1 out of range \(indices are 0 \.\. 2\^32 - 1\)$"):
        octray.Scene(mesh_dict(TRI_V, -TRI_I))
    with pytest.raises(octray.SceneError, match=r"^objects\[1\]\.indices\[5\]: index 4 out of range \(4 vertices\)$"):
        octray.Scene(mesh_dict(TRI_V, np.array([[0, 1, 2], [1, 3, 4]])))
    v = TRI_V.copy()
    v[3, 1] = np.inf
    with pytest.raises(octray.SceneError, match=r"^objects\[1\]\.vertices\[3\]: must be finite$"):
        octray.Scene(mesh_dict(v, TRI_I))
    # Zero-area triangles are dropped and counted, as a model file's are; all of them is an error.
    zero = octray.Scene(mesh_dict(TRI_V, np.array([[0, 1, 2], [1, 1, 2], [0, 1, 1]])))
    assert zero.primitive_count == 2 and zero.info()["meshes"][0]["dropped_degenerate"] == 2
    with pytest.raises(octray.SceneError, match=r"^objects\[1\]\.indices: no triangles \(all 2 have zero area\)$"):
        octray.Scene(mesh_dict(TRI_V, np.array([[1, 1, 2], [0, 1, 1]])))
    # A bad index is reported at its place in the caller's array, zero-area triangles before it or not.
    with pytest.raises(octray.SceneError, match=r"^objects\[1\]\.indices\[5\]: index 9 out of range \(4 vertices\)$"):
        octray.Scene(mesh_dict(TRI_V, np.array([[1, 1, 2], [0, 1, 9]])))
    with pytest.raises(octray.SceneError, match=r"^objects\[1\]: has no triangles$"):
        octray.Scene(mesh_dict(TRI_V, np.zeros((0, 3), int)))
    d = mesh_dict(TRI_V, TRI_I)
    del d["objects"][1]["indices"]
    with pytest.raises(octray.SceneError, match=r"^objects\[1\]\.indices: missing required field"):
        octray.Scene(d)
    d = mesh_dict(TRI_V, TRI_I, file="x.ply")
    with pytest.raises(octray.SceneError, match=r"^objects\[1\]\.file: unknown field"):
        octray.Scene(d)
    d = mesh_dict(TRI_V, TRI_I, transform={"scale": -1})
    with pytest.raises(octray.SceneError, match=r"^objects\[1\]\.transform\.scale: must be finite and > 0, got -1$"):
        octray.Scene(d)
    d = mesh_dict(TRI_V, TRI_I, transform={"translate": [0, 0, 2], "scale": 2})
    h = octray.Scene(d).intersect([[0.5, 0.5, 10]], [[0, 0, -1]])
    assert h["t"][0] == 8 and h["primitive"][0] == 1


def test_vertices_in_a_json_file_are_still_unknown(tmp_path):
    f = tmp_path / "v.json"
    d = sphere_scene([])
    d["objects"] = [{"type": "mesh", "vertices": [[0, 0, 0]], "indices": [[0, 0, 0]], "material": "m"}]
    f.write_text(json.dumps(d))
    with pytest.raises(octray.SceneError, match=r"objects\[0\]\.vertices: unknown field"):
        octray.load(f)


@pytest.fixture(scope="module")
def scene():
    return octray.Scene(sphere_scene([((0, 0, 0), 1)]))


def test_ray_argument_errors(scene):
    o = np.zeros((4, 3), np.float32)
    d = np.ones((4, 3), np.float32)
    for method in (scene.intersect, scene.occluded):
        with pytest.raises(ValueError, match=r"^origins: expected an \(N, 3\) array, got shape \(3,\)$"):
            method(o[0], d)
        with pytest.raises(ValueError, match=r"^directions: expected an \(N, 3\) array, got shape \(4, 4\)$"):
            method(o, np.ones((4, 4)))
        with pytest.raises(ValueError, match=r"^directions: expected 4 rays \(as origins\), got 3$"):
            method(o, d[:3])
        with pytest.raises(TypeError, match=r"^origins: expected a floating-point array, got dtype int64$"):
            method(o.astype(np.int64), d)
        with pytest.raises(TypeError, match=r"^directions: expected a floating-point array, got dtype complex128$"):
            method(o, d.astype(complex))
        with pytest.raises(TypeError, match=r"^origins: expected an \(N, 3\) array of floats"):
            method({"a": 1}, d)
        with pytest.raises(ValueError, match=r"^path: expected 'simd' or 'scalar', got 'gpu'$"):
            method(o, d, path="gpu")
        with pytest.raises(ValueError, match=r"^threads: must be in \[0, 1024\] \(0 = every core\), got -?[0-9]+$"):
            method(o, d, threads=-1)
        with pytest.raises(ValueError, match=r"^threads: must be in \[0, 1024\]"):
            method(o, d, threads=100000)
        with pytest.raises(ValueError, match=r"^tmin: must not be NaN$"):
            method(o, d, float("nan"))
        with pytest.raises(ValueError, match=r"^tmax: must not be NaN$"):
            method(o, d, 0.0, float("nan"))
        with pytest.raises(TypeError):
            method(o, d, 0.0, 1.0, "simd")  # path and threads are keyword-only


def test_render_and_tonemap_argument_errors(scene):
    with pytest.raises(ValueError, match=r"^path: expected 'simd' or 'scalar', got 'gpu'$"):
        scene.render("gpu")
    with pytest.raises(ValueError, match=r"^width: must be in \[1, 16384\], got 0$"):
        scene.render(width=0)
    with pytest.raises(ValueError, match=r"^threads: must be in \[0, 1024\] \(0 = every core\), got -?[0-9]+$"):
        scene.render(threads=-2)
    with pytest.raises(ValueError, match=r"^hdr: expected an \(H, W, 3\) array, got shape \(2, 2\)$"):
        scene.tonemap(np.zeros((2, 2)))
    with pytest.raises(TypeError, match=r"^hdr: expected a floating-point array, got dtype uint8$"):
        scene.tonemap(np.zeros((2, 2, 3), np.uint8))
    with pytest.raises(ValueError, match=r"^threads: must be in \[0, 1024\] \(0 = every core\), got -?[0-9]+$"):
        scene.verify(threads=-1)
    with pytest.raises(TypeError, match=r"^scene: expected an octray.Scene"):
        octray.errtime("scenes/sphere.json")
    with pytest.raises(ValueError, match=r"^min_repetitions: must be >= 5"):
        octray.errtime(scene, min_repetitions=1)


def test_a_huge_width_is_a_scene_error():
    tall = octray.Scene(sphere_scene([((0, 0, 0), 1)], width=1, height=16))
    with pytest.raises(octray.SceneError, match=r"^camera\.height: "):
        tall.render(width=16384)
