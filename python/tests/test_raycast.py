"""Ray casting (docs/python.md): geometry-only scenes, geometry and primitive ids, barycentrics,
geometric normals and per-ray intervals, each against brute force in numpy (float64)."""
import numpy as np
import pytest

import octray
from conftest import height_field, sphere_scene, triangle_t

RNG = np.random.default_rng(11)
U = 2.0 ** -24  # float's unit roundoff


def grid(k, x0, x1, z0, z1, height, phase):
    """A bumpy height field over [x0, x1] x [z0, z1]: (vertices, faces)."""
    return height_field(np.linspace(x0, x1, k + 1), np.linspace(z0, z1, k + 1),
                        lambda x, z: height + 0.25 * np.sin(2 * x + phase) * np.cos(3 * z))


def with_slivers(verts, faces, count):
    """The mesh with `count` zero-area triangles spliced in at random places (repeated
    vertices, and exactly collinear new ones): faces' numbering changes, hits must not."""
    n = len(verts)
    extra = verts[0] + np.array([[0, 0, 0], [0.5, 0, 0], [1, 0, 0]])  # exactly collinear
    verts = np.vstack([verts, extra])
    faces = faces.tolist()
    for _ in range(count):
        at = int(RNG.integers(0, len(faces) + 1))
        a, b = (int(x) for x in RNG.integers(0, n, 2))
        faces.insert(at, [a, a, b] if RNG.random() < 0.5 else [n, n + 1, n + 2])
    return verts, np.array(faces)


def brute_force(meshes, o, d):
    """Closest hit over every non-degenerate face of every mesh, Moller-Trumbore in float64:
    t, mesh index and face index (in the caller's array), -1 / inf on a miss."""
    best = np.full(len(o), np.inf)
    mesh_of = np.full(len(o), -1)
    face_of = np.full(len(o), -1)
    for m, (v, f) in enumerate(meshes):
        a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
        e1, e2 = b - a, c - a
        for k in range(len(f)):
            if not np.cross(e1[k], e2[k]).any():
                continue  # zero area: never hit
            t = triangle_t(a[k], e1[k], e2[k], o, d)
            closer = t < best
            best = np.where(closer, t, best)
            mesh_of = np.where(closer, m, mesh_of)
            face_of = np.where(closer, k, face_of)
    return best, mesh_of, face_of


@pytest.fixture(scope="module")
def several():
    """Three meshes (with zero-area triangles) and a sphere between them in "objects"; rays from above."""
    a = with_slivers(*grid(6, -3.0, -0.5, -1.5, 1.5, 0.6, 0.0), 7)
    b = with_slivers(*grid(7, -1.2, 1.4, -1.5, 1.5, 0.0, 1.0), 9)
    c = with_slivers(*grid(5, 1.0, 3.0, -1.5, 1.5, 0.4, 2.0), 5)
    meshes = [a, b, c]
    objects = [{"type": "mesh", "vertices": a[0], "indices": a[1]},
               {"type": "sphere", "center": [0.3, 1.5, 0.2], "radius": 0.35},
               {"type": "mesh", "vertices": b[0], "indices": b[1]},
               {"type": "mesh", "vertices": c[0], "indices": c[1]}]
    scene = octray.Scene({"objects": objects})
    n = 4000
    o = np.column_stack([RNG.uniform(-3.2, 3.2, n), np.full(n, 4.0), RNG.uniform(-1.7, 1.7, n)])
    d = np.column_stack([RNG.uniform(-0.2, 0.2, n), -np.ones(n), RNG.uniform(-0.2, 0.2, n)])
    o32, d32 = o.astype(np.float32), d.astype(np.float32)
    o64, d64 = o32.astype(np.float64), d32.astype(np.float64)
    t_ref, mesh_ref, face_ref = brute_force(meshes, o64, d64)
    # the sphere, geometry 1
    f = o64 - [0.3, 1.5, 0.2]
    bb = np.einsum("ij,ij->i", f, d64)
    aa = np.einsum("ij,ij->i", d64, d64)
    disc = bb * bb - aa * (np.einsum("ij,ij->i", f, f) - 0.35 ** 2)
    ts = np.where(disc >= 0, (-bb - np.sqrt(np.maximum(disc, 0))) / aa, np.inf)
    sphere = ts < t_ref
    geometry_of_mesh = np.array([0, 2, 3])
    geo = np.where(sphere, 1, np.where(mesh_ref >= 0, geometry_of_mesh[mesh_ref], -1))
    prim = np.where(sphere, 0, face_ref)
    return dict(scene=scene, meshes=meshes, o=o32, d=d32, t=np.minimum(ts, t_ref), geo=geo, prim=prim,
                sliver_count=[7, 9, 5])


def test_a_dict_without_camera_lights_or_materials_casts_rays(several):
    scene = several["scene"]
    assert scene.geometry_only and scene.width is None and scene.height is None
    info = scene.info()
    assert info["camera"] is None and info["materials"] == []
    assert [m["dropped_degenerate"] for m in info["meshes"]] == several["sliver_count"]
    assert [m["geometry_id"] for m in info["meshes"]] == [0, 2, 3]
    kept = sum(len(f) for _, f in several["meshes"]) - sum(several["sliver_count"])
    assert scene.primitive_count == 1 + kept
    assert "no camera" in repr(scene)


def test_geometry_and_primitive_ids_match_brute_force(several):
    h = several["scene"].intersect(several["o"], several["d"])
    geo, prim = several["geo"], several["prim"]
    assert h["geometry_id"].dtype == np.int32 and h["primitive_id"].dtype == np.int32
    assert h["geometry_id"].shape == (len(geo),) and h["primitive_id"].shape == (len(geo),)
    # every geometry is hit, and some rays miss
    assert set(np.unique(geo)) == {-1, 0, 1, 2, 3}
    assert (geo == 1).sum() > 20 and (geo == -1).sum() > 50
    agree = (h["geometry_id"] == geo) & (h["primitive_id"] == prim)
    assert agree.mean() > 0.99  # rays through a shared edge may take either triangle
    hit = agree & (geo >= 0)
    np.testing.assert_allclose(h["t"][hit], several["t"][hit], rtol=2e-5)
    # misses agree exactly; ids are -1 together
    miss = h["t"] == np.inf
    np.testing.assert_array_equal(miss, h["geometry_id"] == -1)
    np.testing.assert_array_equal(miss, h["primitive_id"] == -1)
    np.testing.assert_array_equal(miss, h["primitive"] == -1)
    assert (miss == (geo == -1)).mean() > 0.995
    # the sphere's primitive id is 0; the old global number is still there
    assert (h["primitive_id"][h["geometry_id"] == 1] == 0).all()
    assert (h["primitive"][h["geometry_id"] == 1] == 0).all()  # the scene's one object: number 0


def hit_faces(several, h):
    """The caller's vertices of the face each hit names: (v0, v1, v2), rows for mesh hits."""
    rows = np.flatnonzero((h["geometry_id"] >= 0) & (h["geometry_id"] != 1))
    mesh_index = {0: 0, 2: 1, 3: 2}
    v0, v1, v2 = (np.empty((len(rows), 3)) for _ in range(3))
    for k, r in enumerate(rows):
        v, f = several["meshes"][mesh_index[int(h["geometry_id"][r])]]
        face = f[h["primitive_id"][r]]
        v0[k], v1[k], v2[k] = v[face[0]], v[face[1]], v[face[2]]
    return rows, v0, v1, v2


def test_barycentrics_reproduce_the_hit_point_on_the_callers_face(several):
    h = several["scene"].intersect(several["o"], several["d"])
    assert h["uv"].dtype == np.float32 and h["uv"].shape == (len(several["o"]), 2)
    rows, v0, v1, v2 = hit_faces(several, h)
    assert len(rows) > 2000
    u = h["uv"][rows, 0].astype(np.float64)
    v = h["uv"][rows, 1].astype(np.float64)
    p = several["o"][rows].astype(np.float64) + h["t"][rows, None].astype(np.float64) * several["d"][rows]
    back = (1 - u - v)[:, None] * v0 + u[:, None] * v1 + v[:, None] * v2
    scale = (np.abs(p).max(axis=1) + h["t"][rows] * np.abs(several["d"][rows]).max(axis=1)
             + np.abs(v1 - v0).max(axis=1) + np.abs(v2 - v0).max(axis=1))
    err = np.abs(back - p).max(axis=1)
    assert (err <= 16 * U * scale).all(), (err / (U * scale)).max()
    # inside the face to rounding: the face is the one the ray hit
    assert u.min() > -1e-6 and v.min() > -1e-6 and (u + v).max() < 1 + 1e-6
    assert np.all(h["uv"][h["geometry_id"] == -1] == 0)
    assert np.all(h["uv"][h["geometry_id"] == 1] == 0)  # a sphere's uv: 0


def test_geometric_normals_follow_the_winding_not_the_ray(several):
    scene, o, d = several["scene"], several["o"], several["d"]
    h = scene.intersect(o, d)
    rows, v0, v1, v2 = hit_faces(several, h)
    n = np.cross(v1 - v0, v2 - v0)
    n /= np.linalg.norm(n, axis=1)[:, None]
    gn = h["geometric_normal"]
    assert gn.dtype == np.float32 and gn.shape == (len(o), 3)
    np.testing.assert_allclose(gn[rows], n, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(gn[h["geometry_id"] >= 0], axis=1), 1, atol=1e-6)
    assert np.all(gn[h["geometry_id"] == -1] == 0)
    # The same points seen from below: the geometric normal stays, the shading normal turns.
    p = o[rows].astype(np.float64) + h["t"][rows, None] * d[rows]
    below = (p + 0.05 * d[rows]).astype(np.float32)  # 0.05 |d| under the surface, looking up
    back = scene.intersect(below, -d[rows])
    same = (back["geometry_id"] == h["geometry_id"][rows]) & (back["primitive_id"] == h["primitive_id"][rows])
    assert same.mean() > 0.9
    np.testing.assert_allclose(back["geometric_normal"][same], gn[rows][same], atol=1e-6)
    np.testing.assert_allclose(back["normal"][same], -h["normal"][rows][same], atol=1e-5)
    # sphere hits: outward, from the center
    s = h["geometry_id"] == 1
    ps = o[s].astype(np.float64) + h["t"][s, None] * d[s]
    np.testing.assert_allclose(gn[s], (ps - [0.3, 1.5, 0.2]) / 0.35, atol=1e-5)


def test_per_ray_tmax_and_tmin_cut_hits(several):
    scene, o, d, t_ref = several["scene"], several["o"], several["d"], several["t"]
    n = len(o)
    factor = RNG.uniform(0.5, 1.5, n)
    factor[np.abs(factor - 1) < 1e-3] = 1.5  # no ray's tmax within rounding of its hit
    tmax = np.where(np.isfinite(t_ref), t_ref * factor, 10.0).astype(np.float32)
    h = scene.intersect(o, d, tmax=tmax)
    base = scene.intersect(o, d)
    expect_hit = t_ref < tmax
    assert expect_hit.sum() > n // 4 and (~expect_hit & np.isfinite(t_ref)).sum() > n // 4
    assert ((h["t"] < np.inf) == expect_hit).mean() > 0.995
    assert np.all(h["t"][h["t"] < np.inf] < tmax[h["t"] < np.inf])
    kept = expect_hit & (h["t"] < np.inf)
    np.testing.assert_array_equal(h["primitive"][kept], base["primitive"][kept])
    occ = scene.occluded(o, d, tmax=tmax.astype(np.float64))
    assert (occ == expect_hit).mean() > 0.995
    # tmin beyond the first hit: a farther one or none
    tmin = np.where(np.isfinite(t_ref), t_ref * factor, 0.0)
    far = scene.intersect(o, d, tmin=tmin)
    got = far["t"] < np.inf
    assert np.all(far["t"][got] > tmin[got].astype(np.float32))
    near = tmin < t_ref * (1 - 1e-3)
    np.testing.assert_array_equal(far["primitive"][near & got], base["primitive"][near & got])
    beyond = ~near & np.isfinite(t_ref)
    assert beyond.sum() > n // 4 and np.all(far["t"][beyond] > base["t"][beyond])
    # a strided view and a list are read as arrays; a NaN masks its ray alone
    wide = np.column_stack([tmax, tmax]).astype(np.float64)
    np.testing.assert_array_equal(scene.intersect(o, d, tmax=wide[:, 1])["t"], h["t"])
    nan = tmax.copy()
    nan[:5] = np.nan
    masked = scene.intersect(o, d, tmax=nan)
    assert masked["masked"] == 5 and np.all(masked["geometry_id"][:5] == -1)
    small = scene.intersect(o[:3], d[:3], tmax=[1.0, 2.0, 100.0])
    assert small["t"].shape == (3,) and small["t"][0] == np.inf


def test_bad_intervals_name_the_argument(several):
    scene = several["scene"]
    o, d = several["o"][:4], several["d"][:4]
    for method in (scene.intersect, scene.occluded):
        with pytest.raises(ValueError, match=r"^tmin: expected a number or an \(N,\) array with N = 4 \(one per ray\), got shape \(5,\)$"):
            method(o, d, tmin=np.zeros(5))
        with pytest.raises(ValueError, match=r"^tmax: expected a number or an \(N,\) array with N = 4 \(one per ray\), got shape \(4, 1\)$"):
            method(o, d, tmax=np.ones((4, 1)))
        with pytest.raises(ValueError, match=r"^tmax: .* got shape \(3,\)$"):
            method(o, d, 0.0, [1.0, 2.0, 3.0])
        with pytest.raises(ValueError, match=r"^tmin: .* got shape \(2, 4\)$"):
            method(o, d, np.zeros((2, 4)))
        with pytest.raises(TypeError, match=r"^tmax: expected a number or an \(N,\) array of numbers, got dtype complex128$"):
            method(o, d, tmax=np.ones(4, complex))
        with pytest.raises(TypeError, match=r"^tmin: expected a number or an \(N,\) array of numbers, got dtype <U1$"):
            method(o, d, tmin="a")
        with pytest.raises(ValueError, match=r"^tmin: must not be NaN$"):
            method(o, d, tmin=np.float32("nan"))


def test_a_geometry_only_scene_refuses_what_needs_a_camera_or_materials(several):
    scene = several["scene"]
    o, d = several["o"][:8], several["d"][:8]
    both = r'this scene has no camera and no materials \(a geometry-only scene: intersect and occluded only\); ' \
           r'give its dict a "camera" and "materials", and each object a "material"$'
    with pytest.raises(ValueError, match="^render: " + both):
        scene.render()
    with pytest.raises(ValueError, match="^verify: " + both):
        scene.verify()
    with pytest.raises(ValueError, match="^errtime: " + both):
        octray.errtime(scene)
    with pytest.raises(ValueError, match=r'^camera_rays: this scene has no camera .*give its dict a "camera"$'):
        scene.camera_rays()
    with pytest.raises(ValueError, match=r'^shade: this scene has no materials .*give its dict "materials", and each object a "material"$'):
        scene.shade(o, d)
    assert scene.occluded(o, d).shape == (8,)
    # a camera alone: camera rays, no render; materials and lights alone: shade, no render
    cam = sphere_scene([((0, 0, 0), 1.0)])
    lit = sphere_scene([((0, 0, 0), 1.0)])
    del lit["camera"]
    del cam["materials"]
    for obj in cam["objects"]:
        del obj["material"]
    with_camera = octray.Scene(cam)
    assert with_camera.camera_rays()[0].shape == (12, 16, 3) and with_camera.width == 16
    with pytest.raises(ValueError, match=r'^render: this scene has no materials '):
        with_camera.render()
    shaded = octray.Scene(lit)
    with pytest.raises(ValueError, match=r'^render: this scene has no camera '):
        shaded.render()
    rgb = shaded.shade([[0, 0, 5], [0, 3, 5]], [[0, 0, -1], [0, 0, -1]])
    assert rgb.shape == (2, 3) and rgb.dtype == np.float32
    # the sphere's top, n = (0, 0, 1): ambient ls ka cd + directional kd cd / pi (n.l); a miss: the background
    lambert = 0.2 * 0.25 + 0.65 / np.pi / np.sqrt(3)
    np.testing.assert_allclose(rgb[0], np.array([1, 0.5, 0.25]) * lambert, rtol=1e-5)
    assert np.all(rgb[1] == 0)


def test_from_meshes_numbers_meshes_then_objects(several):
    (va, fa), (vb, fb) = several["meshes"][:2]
    scene = octray.Scene.from_meshes([(va, fa), (vb.tolist(), fb.tolist())],
                                     objects=[{"type": "sphere", "center": [0.3, 1.5, 0.2], "radius": 0.35}])
    o, d = several["o"], several["d"]
    h = scene.intersect(o, d)
    ref = octray.Scene({"objects": [{"type": "mesh", "vertices": va, "indices": fa},
                                    {"type": "mesh", "vertices": vb, "indices": fb},
                                    {"type": "sphere", "center": [0.3, 1.5, 0.2], "radius": 0.35}]}).intersect(o, d)
    for key in ("t", "geometry_id", "primitive_id", "uv", "geometric_normal"):
        np.testing.assert_array_equal(h[key], ref[key])
    assert set(np.unique(h["geometry_id"])) == {-1, 0, 1, 2}
    with pytest.raises(octray.SceneError, match=r"^meshes\[1\]\.indices\[2\]: index 99 out of range \(3 vertices\)$"):
        octray.Scene.from_meshes([(va, fa), (np.eye(3), [[0, 1, 99]])])
    with pytest.raises(octray.SceneError, match=r"^objects\[0\]\.radius: must be > 0, got -1$"):
        octray.Scene.from_meshes([(va, fa)], objects=[{"type": "sphere", "center": [0, 0, 0], "radius": -1}])
    with pytest.raises(TypeError, match=r"^meshes\[0\]: expected a \(vertices, indices\) pair, got int$"):
        octray.Scene.from_meshes([3])
    assert octray.Scene.from_meshes(objects=[{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}]).primitive_count == 1


def test_a_model_files_primitive_ids_count_its_dropped_triangles(tmp_path):
    # An ASCII PLY of a fan of 6 triangles, 3 of them zero-area, interleaved.
    v = np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0], [-2, 2, 0], [1, 0, 0]], float)
    faces = np.array([[0, 1, 2], [0, 5, 1], [0, 2, 3], [3, 3, 4], [0, 3, 4], [1, 1, 1]])
    lines = ["ply", "format ascii 1.0", "element vertex %d" % len(v), "property float x", "property float y",
             "property float z", "element face %d" % len(faces), "property list uchar int vertex_indices",
             "end_header"]
    lines += ["%g %g %g" % tuple(p) for p in v] + ["3 %d %d %d" % tuple(f) for f in faces]
    (tmp_path / "fan.ply").write_text("\n".join(lines) + "\n")
    scene = octray.Scene({"objects": [{"type": "sphere", "center": [0, 0, -9], "radius": 1},
                                      {"type": "mesh", "file": "fan.ply"}]}, base_dir=tmp_path)
    assert scene.info()["meshes"][0]["dropped_degenerate"] == 3
    # a ray into each real triangle's centroid
    real = [0, 2, 4]
    c = v[faces[real]].mean(axis=1)
    h = scene.intersect(c + [0, 0, 3], np.tile([0.0, 0, -1], (3, 1)))
    np.testing.assert_array_equal(h["geometry_id"], [1, 1, 1])
    np.testing.assert_array_equal(h["primitive_id"], real)
    np.testing.assert_allclose(h["uv"], 1 / 3, atol=1e-6)
    np.testing.assert_allclose(h["geometric_normal"], np.tile([0, 0, 1.0], (3, 1)), atol=1e-7)


def test_analytic_shapes_uv_and_geometric_normals():
    objects = [{"type": "sphere", "center": [0, 0, 0], "radius": 1},
               {"type": "box", "min": [3, -1, -1], "max": [5, 1, 1]},
               {"type": "rectangle", "corner": [-6, -1, -1], "a": [0, 2, 0], "b": [0, 0, 4]},
               {"type": "triangle", "vertices": [[0, 5, 0], [2, 5, 0], [0, 7, 0]]},
               {"type": "disk", "center": [0, -5, 0], "normal": [0, 0, -3], "radius": 1}]
    scene = octray.Scene.from_meshes(objects=objects)
    o = np.array([[0, 0, 0], [0.2, 0, 5], [4, 0.3, 0], [9, 0, 0], [-9, 0, 0.5], [0.5, 6, -3], [0, -5, 4]], float)
    d = np.array([[1, 0, 0], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [1, 0, 0], [0, 0, 1], [0, 0, -1]], float)
    h = scene.intersect(o, d)
    np.testing.assert_array_equal(h["geometry_id"], [0, 0, 1, 1, 2, 3, 4])
    gn = h["geometric_normal"]
    np.testing.assert_allclose(gn[0], [1, 0, 0], atol=1e-7)   # from inside the sphere: outward
    np.testing.assert_allclose(h["normal"][0], [-1, 0, 0], atol=1e-7)  # the shading normal faces the ray
    np.testing.assert_allclose(gn[1], [0.2, 0, np.sqrt(0.96)], atol=1e-6)
    np.testing.assert_allclose(gn[2], [1, 0, 0], atol=1e-7)   # from inside the box: the +x face, outward
    np.testing.assert_allclose(gn[3], [1, 0, 0], atol=1e-7)   # from outside: the same face
    np.testing.assert_allclose(gn[4], [1, 0, 0], atol=1e-7)   # rectangle: a x b
    np.testing.assert_allclose(h["uv"][4], [0.5, 0.375], atol=1e-7)  # (-6, 0, 0.5) = corner + 0.5 a + 0.375 b
    np.testing.assert_allclose(gn[5], [0, 0, 1], atol=1e-7)   # triangle winding, the ray from behind
    np.testing.assert_allclose(h["uv"][5], [0.25, 0.5], atol=1e-7)
    np.testing.assert_allclose(gn[6], [0, 0, -1], atol=1e-7)  # the disk's normal, not the ray's side
    assert np.all(h["uv"][[0, 1, 2, 3, 6]] == 0) and np.all(h["primitive_id"] == 0)


def test_precision_modes(several):
    scene, o, d = several["scene"], several["o"], several["d"]
    exact = scene.intersect(o, d)
    info = scene.info()
    for mode, rel in (("exact", 0), ("double", 1e-6), ("fast", 1e-5), ("approx", 2e-3),
                      ("fast14", 1e-5), ("approx14", 2e-3)):
        if mode.endswith("14") and not info["avx512_supported"]:
            with pytest.raises(ValueError, match="^mode: '%s' needs AVX-512 F\\+VL, which this CPU lacks$" % mode):
                scene.intersect(o, d, mode=mode)
            continue
        h = scene.intersect(o, d, mode=mode)
        same = (h["primitive"] == exact["primitive"]) & (h["primitive"] >= 0)
        assert same.mean() > 0.7, mode
        np.testing.assert_allclose(h["t"][same], exact["t"][same], rtol=max(rel, 1e-7), err_msg=mode)
        assert (scene.occluded(o, d, mode=mode) == (exact["primitive"] >= 0)).mean() > 0.99, mode
    with pytest.raises(ValueError, match=r"^mode: expected one of exact, fast, approx, fast14, approx14, double, got 'f64'$"):
        scene.intersect(o, d, mode="f64")


def test_shade_of_the_camera_rays_is_the_render(models):
    o, d = models.camera_rays()
    rgb = models.shade(o.reshape(-1, 3), d.reshape(-1, 3))  # ray i keys its samples as pixel i
    np.testing.assert_array_equal(rgb.reshape(models.height, models.width, 3), models.render())


def test_every_output_is_the_same_on_any_thread_count_and_path(several):
    scene, o, d = several["scene"], several["o"], several["d"]
    one = scene.intersect(o, d, threads=1)
    for other in (scene.intersect(o, d, threads=2), scene.intersect(o, d, threads=3),
                  scene.intersect(o.astype(np.float64), d.astype(np.float64), threads=2)):
        for key in ("t", "geometry_id", "primitive_id", "uv", "geometric_normal", "primitive", "normal"):
            np.testing.assert_array_equal(other[key], one[key], err_msg=key)
    scalar = scene.intersect(o, d, path="scalar")
    for key in ("geometry_id", "primitive_id", "primitive"):
        assert (scalar[key] == one[key]).mean() > 0.999, key
    # a count of rays that is no multiple of a packet or of the binding's chunks of 128
    part = scene.intersect(o[:1001], d[:1001], threads=1)
    for key in ("t", "geometry_id", "primitive_id", "uv", "geometric_normal"):
        np.testing.assert_array_equal(part[key], one[key][:1001], err_msg=key)
