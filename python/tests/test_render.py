"""render() against the CLI's PFM, tonemap() against its PNG; threads against one thread; the harnesses."""
import os
import subprocess

import numpy as np
import pytest

import octray
from conftest import SOURCE, sphere_scene

CLI = os.environ.get("OCTRAY_CLI", "")
needs_cli = pytest.mark.skipif(not CLI, reason="the octray CLI was not built (OCTRAY_BUILD_TOOLS=OFF)")


def read_pfm(path):
    data = open(path, "rb").read()
    parts = data.split(b"\n", 3)
    assert parts[0] == b"PF" and parts[2] == b"-1.0"
    w, h = map(int, parts[1].split())
    img = np.frombuffer(parts[3], dtype="<f4").reshape(h, w, 3)
    return img[::-1]  # PFM stores the bottom row first


def bits(a):
    return np.ascontiguousarray(a, np.float32).view(np.uint32)


CASES = [
    ("scenes/sphere.json", "simd", 2, None),
    ("scenes/shadows.json", "scalar", 1, 96),
    ("scenes/models.json", "simd", 0, None),
    ("scenes/aobench.json", "simd", 2, 64),
    ("scenes/point_attenuated.json", "reference", 1, 48),
]


@needs_cli
@pytest.mark.parametrize("scene_file,path,threads,width", CASES)
def test_render_equals_the_cli(tmp_path, scene_file, path, threads, width):
    png, pfm = tmp_path / "out.png", tmp_path / "out.pfm"
    cmd = [CLI, "render", str(SOURCE / scene_file), "-o", str(png), "--hdr", str(pfm), "--path", path,
           "--threads", str(threads)]
    if width:
        cmd += ["--width", str(width)]
    subprocess.run(cmd, check=True, capture_output=True)
    scene = octray.load(SOURCE / scene_file)
    hdr = scene.render(path=path, width=width, threads=threads)
    assert hdr.dtype == np.float32 and hdr.ndim == 3 and hdr.shape[2] == 3
    expected = read_pfm(pfm)
    assert hdr.shape == expected.shape
    np.testing.assert_array_equal(bits(hdr), bits(expected))
    if path != "reference":
        import matplotlib.image
        shown = np.round(matplotlib.image.imread(png)[..., :3] * 255).astype(np.uint8)
        np.testing.assert_array_equal(scene.tonemap(hdr, path=path), shown)


def test_tonemap_shapes():
    scene = octray.Scene(sphere_scene([((0, 0, 0), 1)]))
    hdr = scene.render()
    img = scene.tonemap(hdr)
    assert img.dtype == np.uint8 and img.shape == hdr.shape
    flat = scene.tonemap(hdr.reshape(-1, 3).astype(np.float64))
    np.testing.assert_array_equal(flat, img.reshape(-1, 3))
    np.testing.assert_array_equal(scene.tonemap(np.full((2, 3), np.nan, np.float32)).shape, (2, 3))


@pytest.fixture(scope="module")
def models():
    return octray.load(SOURCE / "scenes" / "models.json")


def test_threads_give_the_same_answers(models):
    o, d = models.camera_rays()
    rng = np.random.default_rng(3)
    o = np.concatenate([o.reshape(-1, 3), rng.uniform(-3, 3, (5001, 3)).astype(np.float32)])
    d = np.concatenate([d.reshape(-1, 3), rng.normal(size=(5001, 3)).astype(np.float32)])
    d[::97] = np.nan
    one = models.intersect(o, d, threads=1)
    assert one["masked"] == len(d[::97])
    occ1 = models.occluded(o, d, threads=1)
    for t in (0, 2, 3, 7):
        many = models.intersect(o, d, threads=t)
        for key in ("t", "primitive", "normal"):
            np.testing.assert_array_equal(many[key], one[key])
        assert many["masked"] == one["masked"]
        np.testing.assert_array_equal(models.occluded(o, d, threads=t), occ1)
    for path in ("simd", "scalar"):
        np.testing.assert_array_equal(bits(models.render(path=path, threads=1)), bits(models.render(path=path, threads=3)))


def test_scalar_and_simd_agree(models):
    o, d = models.camera_rays()
    a = models.intersect(o.reshape(-1, 3), d.reshape(-1, 3), path="simd")
    b = models.intersect(o.reshape(-1, 3), d.reshape(-1, 3), path="scalar")
    assert (a["primitive"] == b["primitive"]).mean() > 0.999


def test_verify_and_info():
    scene = octray.load(SOURCE / "scenes" / "sphere.json")
    v = scene.verify(threads=2)
    assert v["pass"] is True
    for path in ("scalar", "simd"):
        assert v[path]["verdict"] == "ok" and v[path]["max_scaled"] <= v["tolerance"]["scaled_error"]
        assert v[path]["compared"] > 0
    info = scene.info()
    assert info["width"] == scene.width and info["primitives"]["sphere"] >= 1
    assert set(info["kernels"]) == {"simd", "scalar"}
    assert repr(scene).startswith("<octray.Scene ")


def test_errtime_rows():
    scene = octray.Scene(sphere_scene([((0, 0, 0), 1)], width=16, height=8))
    rows = octray.errtime(scene, threads=1, min_repetitions=5, max_repetitions=5, min_seconds=0)
    assert len(rows) >= 4
    assert {r["path"] for r in rows} == {"scalar", "simd"}
    assert all(r["ns_per_ray"] > 0 and r["repetitions"] == 5 for r in rows)
    assert any(r["pareto"] for r in rows)
    # The verdict, as `octray errtime` prints it: every mode within its bound here.
    assert all(r["verdict"] == "ok" and r["pass"] and r["max_scaled"] <= r["bound"] for r in rows)
    assert all(r["bound"] < 2e-3 for r in rows)


def test_stability_rows():
    rows = octray.stability()
    assert len(rows) > 10
    assert all(r["verdict"] in ("pass", "FAIL") and "simd/exact" in r["results"] for r in rows)
    assert all(r["pass"] for r in rows)
