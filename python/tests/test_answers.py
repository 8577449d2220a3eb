"""Answers against closed forms: analytic spheres, and a brute-force numpy triangle test."""
import numpy as np
import pytest

import octray
from conftest import height_field, sphere_scene, triangle_t

RNG = np.random.default_rng(7)


def analytic_spheres(centers, radii, o, d):
    """Closest t (units of |d|), id and outward unit normal of rays against spheres, in float64."""
    n = len(o)
    best = np.full(n, np.inf)
    ids = np.full(n, -1)
    for k, (c, r) in enumerate(zip(centers, radii)):
        f = o - c
        a = np.einsum("ij,ij->i", d, d)
        b = np.einsum("ij,ij->i", f, d)
        cc = np.einsum("ij,ij->i", f, f) - r * r
        disc = b * b - a * cc
        ok = disc >= 0
        sq = np.sqrt(np.where(ok, disc, 0))
        t0 = (-b - sq) / a
        t1 = (-b + sq) / a
        t = np.where(t0 > 0, t0, np.where(t1 > 0, t1, np.inf))
        t = np.where(ok, t, np.inf)
        closer = t < best
        best = np.where(closer, t, best)
        ids = np.where(closer, k, ids)
    return best, ids


@pytest.mark.parametrize("path", ["simd", "scalar"])
def test_spheres_match_the_closed_form(path):
    centers = RNG.uniform(-3, 3, size=(12, 3))
    radii = RNG.uniform(0.3, 0.9, size=12)
    scene = octray.Scene(sphere_scene([(c.tolist(), float(r)) for c, r in zip(centers, radii)]))
    n = 5000
    o = np.tile([0.0, 0.0, 12.0], (n, 1)) + RNG.uniform(-0.5, 0.5, size=(n, 3))
    target = centers[RNG.integers(0, len(centers), n)] + RNG.normal(0, 0.6, size=(n, 3))
    d = (target - o) * RNG.uniform(0.2, 3.0, size=(n, 1))  # not unit
    o32, d32 = o.astype(np.float32), d.astype(np.float32)
    hits = scene.intersect(o32, d32, path=path)
    t_ref, id_ref = analytic_spheres(centers, radii, o32.astype(np.float64), d32.astype(np.float64))
    assert hits["masked"] == 0
    assert hits["t"].dtype == np.float32 and hits["t"].shape == (n,)
    assert hits["primitive"].shape == (n,) and hits["normal"].shape == (n, 3)
    hit = id_ref >= 0
    assert hit.sum() > n // 5 and (~hit).sum() > n // 20
    # Rays grazing a sphere may legally go either way; they are a sliver.
    agree = hits["primitive"] == id_ref
    assert agree.mean() > 0.995
    both = agree & hit
    np.testing.assert_allclose(hits["t"][both], t_ref[both], rtol=2e-5)
    assert np.all(np.isinf(hits["t"][agree & ~hit]))
    p = o32[both].astype(np.float64) + t_ref[both, None] * d32[both].astype(np.float64)
    n_ref = (p - centers[id_ref[both]]) / radii[id_ref[both], None]
    facing = np.where(np.einsum("ij,ij->i", n_ref, d32[both].astype(np.float64))[:, None] > 0, -n_ref, n_ref)
    np.testing.assert_allclose(hits["normal"][both], facing, atol=2e-4)


def test_unit_sphere_head_on():
    scene = octray.Scene(sphere_scene([((0, 0, 0), 1.0)]))
    o = np.array([[0, 0, 5], [0, 0, 5], [3, 0, 5], [0, 0, 0]], np.float64)
    d = np.array([[0, 0, -1], [0, 0, -2], [0, 0, -1], [1, 0, 0]], np.float64)
    h = scene.intersect(o, d)
    np.testing.assert_array_equal(h["t"], np.array([4, 2, np.inf, 1], np.float32))
    np.testing.assert_array_equal(h["primitive"], [0, 0, -1, 0])
    np.testing.assert_array_equal(h["normal"][0], [0, 0, 1])
    np.testing.assert_array_equal(h["normal"][3], [-1, 0, 0])  # from inside: faces the ray
    np.testing.assert_array_equal(scene.occluded(o, d), [True, True, False, True])
    np.testing.assert_array_equal(scene.occluded(o, d, tmax=3.5), [False, True, False, True])
    np.testing.assert_array_equal(scene.occluded(o, d, tmin=4.5), [True, False, False, False])


def brute_force_triangles(v, tris, o, d):
    """Every triangle in float64: closest t and triangle index."""
    a, b, c = v[tris[:, 0]], v[tris[:, 1]], v[tris[:, 2]]
    e1, e2 = b - a, c - a
    best = np.full(len(o), np.inf)
    ids = np.full(len(o), -1)
    for k in range(len(tris)):
        t = triangle_t(a[k], e1[k], e2[k], o, d)
        closer = t < best
        best = np.where(closer, t, best)
        ids = np.where(closer, k, ids)
    return best, ids


def test_mesh_arrays_match_brute_force():
    # A bumpy 12 x 12 grid mesh plus one sphere first: triangle ids follow the objects'.
    k = 12
    xs = np.linspace(-2, 2, k + 1)
    verts, tris = height_field(xs, xs, lambda x, z: 0.3 * np.sin(2 * x) * np.cos(3 * z))
    d = sphere_scene([((0, 3, 0), 0.5)])
    d["objects"].append({"type": "mesh", "vertices": verts, "indices": tris, "material": "m"})
    scene = octray.Scene(d)
    assert scene.primitive_count == 1 + len(tris)
    n = 3000
    o = np.column_stack([RNG.uniform(-2.5, 2.5, n), np.full(n, 5.0), RNG.uniform(-2.5, 2.5, n)])
    dirs = np.column_stack([RNG.uniform(-0.3, 0.3, n), np.full(n, -1.0), RNG.uniform(-0.3, 0.3, n)])
    o32, d32 = o.astype(np.float32), dirs.astype(np.float32)
    h = scene.intersect(o32, d32)
    t_ref, id_ref = brute_force_triangles(verts, tris, o32.astype(np.float64), d32.astype(np.float64))
    # the sphere above the mesh
    ts, _ = analytic_spheres(np.array([[0, 3, 0.0]]), np.array([0.5]), o32.astype(np.float64), d32.astype(np.float64))
    sphere = ts < t_ref
    ids = np.where(sphere, 0, np.where(id_ref >= 0, id_ref + 1, -1))
    t_all = np.minimum(ts, t_ref)
    agree = h["primitive"] == ids
    assert agree.mean() > 0.99  # rays through shared edges may take either triangle
    ok = agree & (ids >= 0)
    np.testing.assert_allclose(h["t"][ok], t_all[ok], rtol=1e-5)
    assert (ids > 0).sum() > n // 2


def test_invalid_rays_are_masked_misses():
    scene = octray.Scene(sphere_scene([((0, 0, 0), 1.0)]))
    nan = np.nan
    o = np.array([[0, 0, 5]] * 5, np.float32)
    d = np.array([[0, 0, -1], [nan, 0, -1], [0, 0, 0], [0, 0, -1], [0, nan, nan]], np.float32)
    h = scene.intersect(o, d)
    assert h["masked"] == 3
    np.testing.assert_array_equal(h["primitive"], [0, -1, -1, 0, -1])
    assert np.isinf(h["t"][[1, 2, 4]]).all()
    assert not scene.occluded(o, d)[[1, 2, 4]].any()


def test_dtypes_and_layouts_give_the_same_answers():
    scene = octray.Scene(sphere_scene([((0, 0, 0), 1.0), ((1.5, 0.5, -1), 0.7)]))
    n = 333  # not a multiple of 8
    o = np.tile([0.1, 0.2, 6.0], (n, 1)) + RNG.uniform(-0.1, 0.1, (n, 3))
    d = np.column_stack([RNG.uniform(-0.4, 0.4, n), RNG.uniform(-0.4, 0.4, n), -np.ones(n)])
    o32, d32 = o.astype(np.float32), d.astype(np.float32)
    base = scene.intersect(o32, d32)
    fortran = scene.intersect(np.asfortranarray(o32), np.asfortranarray(d32))
    wide = np.zeros((n, 6), np.float32)
    wide[:, 0:3], wide[:, 3:6] = o32, d32
    strided = scene.intersect(wide[:, 0:3], wide[:, 3:6])  # Open3D's (N, 6) layout, as views
    f64 = scene.intersect(o32.astype(np.float64), d32.astype(np.float64))
    f16 = scene.intersect(o32.astype(np.float16), d32.astype(np.float16))
    rev = scene.intersect(o32[::-1], d32[::-1])
    lists = scene.intersect(o32.tolist(), d32.tolist())
    for other in (fortran, strided, f64, lists):
        for key in ("t", "primitive", "normal"):
            np.testing.assert_array_equal(other[key], base[key])
    for key in ("t", "primitive", "normal"):
        np.testing.assert_array_equal(rev[key][::-1], base[key])
    assert f16["t"].shape == (n,)
    empty = scene.intersect(np.zeros((0, 3)), np.zeros((0, 3)))
    assert empty["t"].shape == (0,) and empty["normal"].shape == (0, 3) and empty["masked"] == 0


def test_primitive_ids_as_info_numbers_them(models):
    info = models.info()
    assert info["primitive_count"] == 1 + sum(m["triangles"] for m in info["meshes"])
    assert info["primitives"]["plane"] == 1
    o = np.array([[0, 5, 0.3], [0, 5, 30]], np.float32)
    d = np.array([[0, -1, 0], [0, -1, 0]], np.float32)
    h = models.intersect(o, d)
    assert h["primitive"][1] == 0  # the ground plane, object 0
    assert 1 <= h["primitive"][0] <= info["meshes"][0]["triangles"]  # Wuson, the first mesh


def test_camera_rays_are_the_camera_kernels(models):
    o, d = models.camera_rays()
    assert o.shape == (models.height, models.width, 3) and o.dtype == np.float32
    h = models.intersect(o.reshape(-1, 3), d.reshape(-1, 3))
    assert h["masked"] == 0 and (h["primitive"] >= 0).mean() > 0.5
