#!/usr/bin/env python3
"""Writes the sphere-field scenes (many small, distant spheres: the sphere-frame hit's test).

    python3 scripts/make_sphere_fields.py --out DIR [NAME...]   # all of SCENES below, or the NAMEs
    python3 scripts/make_sphere_fields.py --out DIR --report DIR2  # also the first report's scenes, into DIR2

The build runs it (tests/CMakeLists.txt: build/generated/ and
build/generated/pinhole/); the scenes are not tracked (2.4 MB each).
sphere_field and sphere_field_far put 20,000 spheres in front of an
orthographic camera: radius 0.04 over a 10 x 2 grid 10-15 units away, and
radius 1e-3 at 100-105 units (t/r = 1e5). Their inputs
are exact in float, so `octray verify` measures the kernels, not the rounding
of the scene file: the camera frame is axis-aligned, the image width and
height and the view's half extents are powers of two (every camera ray
origin and direction is a float, the same in the reference's double), and
every centre is written as the float it rounds to. A pinhole camera's rays,
rounded to float, are off by about 1u of angle (u = 2^-24), which would move
the hit on a sphere of radius R at distance t by ~u t and its normal by
~u t / (R cos); the camera kernel keeps that rounding as a residual and the
sphere normal takes it in (precision.hpp), as it takes a centre's. The
pinhole_field* scenes are such fields through pinhole cameras (docs/accuracy.md's
20,000 spheres r = 0.04 at 10-14 units, fov 42; 4,000 r = 1e-3 at 100 units,
fov 3; a 100-degree wide angle; shadows on; point lights among the spheres;
the first two with centres written to 4 and 7 decimals): `octray verify`
checks them at its unchanged tolerance.

--report DIR writes the scenes of the first report of sphere-normal errors at
distance, as a new user would make
them: scenes/default.json with its objects replaced by N spheres over a
10 x 2 grid 10-15 units in front of its pinhole camera, centres rounded to
four decimals (report_2000.json, report_20000.json, report_20000_r0.4.json),
and report_20000_f32.json: the same 20,000 with those centres written as the
floats they round to, which leaves the camera rays as the only rounded input.
"""
import argparse
import json
import math
import os
import random
import struct

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def f32(x):
    """x rounded to float, as a double (exact in JSON's shortest repr)."""
    return struct.unpack("f", struct.pack("f", x))[0]


def default_scene():
    with open(os.path.join(ROOT, "scenes", "default.json")) as f:
        return json.load(f)


def sphere(center, radius, material):
    return {"type": "sphere", "center": center, "radius": radius, "material": material}


def field(count, radius, lo, hi, near, far, seed):
    """count spheres, centres uniform in x in lo[0]..hi[0], y in lo[1]..hi[1],
    z in -far..-near (in front of a camera at the origin looking down -z),
    rounded to float."""
    rng = random.Random(seed)
    base = default_scene()
    materials = sorted(base["materials"])
    objects = []
    for k in range(count):
        c = [f32(rng.uniform(lo[0], hi[0])), f32(rng.uniform(lo[1], hi[1])), f32(-rng.uniform(near, far))]
        objects.append(sphere(c, radius, materials[k % len(materials)]))
    return base, objects


def orthographic(base, objects, width, height, height_world):
    scene = dict(base)
    scene["camera"] = {"type": "orthographic", "eye": [0, 0, 0], "look_at": [0, 0, -1], "up": [0, 1, 0],
                       "height_world": height_world, "width": width, "height": height}
    scene["objects"] = objects
    return scene


def write(path, scene):
    with open(path, "w") as f:
        json.dump(scene, f, separators=(",", ":"))
        f.write("\n")
    print(f"wrote {path}: {len(scene['objects'])} objects")


def report_scenes(outdir):
    """The first report's reproduction: default.json's pinhole camera and lights."""
    base = default_scene()
    eye, look = base["camera"]["eye"], base["camera"]["look_at"]
    fwd = [l - e for l, e in zip(look, eye)]
    n = math.sqrt(sum(x * x for x in fwd))
    fwd = [x / n for x in fwd]
    right = [fwd[1] * 0 - fwd[2] * 1, fwd[2] * 0 - fwd[0] * 0, fwd[0] * 1 - fwd[1] * 0]  # fwd x (0, 1, 0)
    n = math.sqrt(sum(x * x for x in right))
    right = [x / n for x in right]
    up = [right[1] * fwd[2] - right[2] * fwd[1], right[2] * fwd[0] - right[0] * fwd[2], right[0] * fwd[1] - right[1] * fwd[0]]
    materials = sorted(base["materials"])
    for count, radius, as_float in ((2000, 0.04, False), (20000, 0.04, False), (20000, 0.4, False), (20000, 0.04, True)):
        rng = random.Random(16)
        objects = []
        for k in range(count):
            a, b, dist = rng.uniform(-5, 5), rng.uniform(-1, 1), rng.uniform(10, 15)
            c = [round(eye[i] + fwd[i] * dist + right[i] * a + up[i] * b, 4) for i in range(3)]
            objects.append(sphere([f32(x) for x in c] if as_float else c, radius, materials[k % len(materials)]))
        scene = dict(base)
        scene["objects"] = objects
        name = f"report_{count}" + ("" if radius == 0.04 else f"_r{radius}") + ("_f32" if as_float else "") + ".json"
        write(os.path.join(outdir, name), scene)


def pinhole_field(count, radius, near, far, fov, seed, eye=(0, 2.4, 8), look_at=(0, 0.8, 0), width=320, height=240,
                  shadows=False, close_lights=False, decimals=None):
    """count spheres of the given radius in the view of a pinhole camera with
    vertical field of view `fov` (degrees) at eye, looking at look_at: the
    centres uniform over the frustum between `near` and `far` units along
    the view axis (within 90% of its half extents), written as the floats
    they round to (the camera's rays are then the only rounded input), or
    with `decimals`, rounded to that many decimals as a user writes them
    (then the centres are rounded inputs too).
    default.json's materials and lights; `shadows`: every light casts them;
    `close_lights`: two more point lights among the spheres, one
    inverse-square."""
    rng = random.Random(seed)
    base = default_scene()
    fwd = [l - e for l, e in zip(look_at, eye)]
    n = math.sqrt(sum(x * x for x in fwd))
    fwd = [x / n for x in fwd]
    right = [-fwd[2], 0.0, fwd[0]]  # fwd x (0, 1, 0)
    n = math.sqrt(sum(x * x for x in right))
    right = [x / n for x in right]
    up = [right[1] * fwd[2] - right[2] * fwd[1], right[2] * fwd[0] - right[0] * fwd[2], right[0] * fwd[1] - right[1] * fwd[0]]
    half = math.tan(math.radians(fov) / 2)
    aspect = width / height
    materials = sorted(base["materials"])
    objects = []
    for k in range(count):
        dist = rng.uniform(near, far)
        a = rng.uniform(-0.9, 0.9) * half * aspect * dist
        b = rng.uniform(-0.9, 0.9) * half * dist
        c = [eye[i] + fwd[i] * dist + right[i] * a + up[i] * b for i in range(3)]
        c = [f32(x) if decimals is None else round(x, decimals) for x in c]
        objects.append(sphere(c, radius, materials[k % len(materials)]))
    scene = dict(base)
    scene["camera"] = {"type": "pinhole", "eye": list(eye), "look_at": list(look_at), "up": [0, 1, 0], "fov_y": fov,
                       "width": width, "height": height}
    lights = [dict(l) for l in base["lights"]]
    if close_lights:
        mid = (near + far) / 2
        at = lambda s, t, d: [eye[i] + fwd[i] * d + right[i] * s + up[i] * t for i in range(3)]
        lights.append({"type": "point", "position": at(0.3 * half * mid, 0.2 * half * mid, mid), "color": [1.0, 0.9, 0.7],
                       "ls": 1.0})
        lights.append({"type": "point", "position": at(-0.4 * half * mid, -0.1 * half * mid, near + 0.25 * (far - near)),
                       "color": [0.6, 0.8, 1.0], "ls": 0.2 * radius * 50, "attenuation": "inverse_square"})
    if shadows:
        for l in lights:
            l["shadows"] = True
    scene["lights"] = lights
    scene["objects"] = objects
    return scene


def planar_far_field(count, seed):
    """count disks and rectangles (alternately, radius 0.02 and 0.03 x 0.03,
    tilted at random, centres to 6 decimals) 100-100.05 units in front of a
    3-degree pinhole at default.json's eye, lit by its lights and a point
    light 8 units in front of them: the planar primitives at distance."""
    rng = random.Random(seed)
    base = default_scene()
    materials = sorted(base["materials"])
    eye = [0, 2.4, 8]
    objects = []
    for k in range(count):
        dist = rng.uniform(100, 100.05)
        c = [round(rng.uniform(-2, 2), 6), round(eye[1] + rng.uniform(-1.5, 1.5), 6), round(eye[2] - dist, 6)]
        m = materials[k % len(materials)]
        if k % 2:
            objects.append({"type": "disk", "center": c, "normal": [rng.uniform(-1, 1), rng.uniform(-1, 1), 1.0],
                            "radius": 0.02, "material": m})
        else:
            objects.append({"type": "rectangle", "corner": c, "a": [0.03, 0.001, 0.0], "b": [0.0, 0.03, 0.002],
                            "material": m})
    scene = dict(base)
    scene["camera"] = {"type": "pinhole", "eye": eye, "look_at": [0, eye[1], 0], "up": [0, 1, 0], "fov_y": 3,
                       "width": 320, "height": 240}
    scene["lights"] = [dict(l) for l in base["lights"]] + [
        {"type": "point", "position": [0.5, 2.9, eye[2] - 92], "color": [1, 1, 1], "ls": 2.0}]
    scene["objects"] = objects
    return scene


# name: (what it is, how to make it). The orthographic fields keep every input
# exact in float; the pinhole ones round every camera ray.
SCENES = {
    # radius 0.04, 10-15 units: 256 x 64 pixels over 10 x 2.5 units (a pixel ~ a sphere's diameter).
    "sphere_field": lambda: orthographic(*field(20000, 0.04, (-5, -1), (5, 1), 10, 15, seed=16), 256, 64, 2.5),
    # radius 1e-3, 100-105 units: 128 x 64 pixels over 0.125 x 0.0625 (a pixel ~ half a diameter).
    "sphere_field_far": lambda: orthographic(*field(20000, 1e-3, (-0.0625, -0.03125), (0.0625, 0.03125), 100, 105, seed=17),
                                             128, 64, 0.0625),
    # The pinhole fields of docs/accuracy.md: default.json's camera (fov 42) and a 3-degree telephoto at 100 units.
    "pinhole_field": lambda: pinhole_field(20000, 0.04, 10, 14, 42, seed=18),
    "pinhole_field_far": lambda: pinhole_field(4000, 1e-3, 100, 100.05, 3, seed=19),
    # Variants: a wide angle (100 degrees: rays up to 60 degrees off axis), shadows from every light,
    # and point lights among the spheres (inverse square, shadows on); the shadowed ones at 160 x 120
    # (a shadow ray per light and lane: four times the work of a camera ray's).
    "pinhole_field_wide": lambda: pinhole_field(20000, 0.04, 6, 10, 100, seed=20),
    "pinhole_field_shadows": lambda: pinhole_field(20000, 0.04, 10, 14, 42, seed=21, width=160, height=120, shadows=True),
    "pinhole_field_close_lights": lambda: pinhole_field(20000, 0.04, 10, 14, 42, seed=22, width=160, height=120,
                                                        shadows=True, close_lights=True),
    # The two fields with centres as a user writes them (4 and 7 decimals): rounded to float, each
    # is off by up to u/2 |c|, ~u |c| / r of a normal, as much as the camera rays' rounding.
    "pinhole_field_decimal": lambda: pinhole_field(20000, 0.04, 10, 14, 42, seed=23, decimals=4),
    "pinhole_field_far_decimal": lambda: pinhole_field(4000, 1e-3, 100, 100.05, 3, seed=24, decimals=7),
    # Disks and rectangles at 100 units through the same telephoto: their normal is the plane's.
    "pinhole_planar_far": lambda: planar_far_field(400, seed=25),
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, help="directory the scenes go to (the build tree: they are not tracked)")
    ap.add_argument("--report", metavar="DIR", help="also write the first report's pinhole reproduction scenes into DIR")
    ap.add_argument("names", nargs="*", help=f"scenes to write (default: all of {', '.join(SCENES)})")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    for name in args.names or SCENES:
        write(os.path.join(args.out, name + ".json"), SCENES[name]())
    if args.report:
        os.makedirs(args.report, exist_ok=True)
        report_scenes(args.report)


if __name__ == "__main__":
    main()
