#!/usr/bin/env python3
"""fuzz/make_kernel_seeds.py — writes the hand-made seeds of fuzz/corpus/kernels/.

The input layout is the one fuzz/kernels_fuzz.cpp documents: two feature bytes,
the scene's numbers, then ray packets (288 bytes each). Each seed is a scene
that passes validate() with packets of ordinary, grazing and garbage rays, so
the fuzzer starts from inputs that reach every stage. Run from anywhere:

    python3 fuzz/make_kernel_seeds.py
"""
import math
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "corpus", "kernels")

NAN, INF = float("nan"), float("inf")


def num(v):
    """A number: one tag byte for multiples of 1/8 in [-8, 8), else a float's bits."""
    if math.isfinite(v) and v * 8 == int(v * 8) and -8 <= v < 8:
        return bytes([int(v * 8) + 0x40])
    return b"\x80" + struct.pack("<f", v)


def dbl(v):
    """A number as a double's bits (values past the float range)."""
    return b"\xe0" + struct.pack("<d", v)


def vec(*v):
    return b"".join(x if isinstance(x, bytes) else num(x) for x in v)


def scene(tonemap=0, ortho=False, spheres=1, boxes=1, triangles=1, plane=True, disk=True, rect=True,
          ambient=True, directional=True, point=True, attenuated=True, shadows=True, extreme=False,
          occlusion=False):
    has = spheres | boxes << 2 | triangles << 4 | plane << 6 | disk << 7
    more = rect | ambient << 1 | directional << 2 | point << 3 | attenuated << 4 | shadows << 5
    more |= (3 if ortho else tonemap) << 6  # 3: orthographic camera, saturate tone map
    b = bytes([has, more])
    b += vec(0, 2, 7.5) + vec(0, 0, 0) + vec(0, 1, 0) + num(45.0) + num(6.0)
    b += bytes([40 | 0x80, 24 | 2 << 6]) if occlusion else bytes([40, 24])  # occlusion: 4 samples
    b += vec(0.125, 0.25, 0.375) + num(2.2 if tonemap == 0 else 1.0) + vec(1, 0, 0)
    b += num(0.25) + num(0.625) + vec(1, 0.5, 0.25)
    b += num(0.25) + num(0.625) + vec(0.25, 0.5, 1)
    if ambient:
        b += vec(1, 1, 1) + num(0.375)
    if directional:
        b += vec(0.5, 0.75, 0.25) + vec(1, 0.875, 0.75) + num(1.5)
    if point:
        b += vec(-3, 4, 3) + vec(1, 1, 1) + (dbl(1e30) if extreme else num(1.25))
    if attenuated:
        b += vec(2, 3, 3) + vec(1, 0.75, 0.5) + num(7.875)
    for i in range(spheres):
        b += bytes([i % 2]) + vec(i - 1, 0.5, 0) + (dbl(1e-20) if extreme and i == 0 else num(0.75))
    for i in range(boxes):
        b += bytes([1]) + vec(1.25, -1, -0.5 - i) + vec(2.25, 0.25, 0.5 - i)
    for i in range(triangles):
        b += bytes([0]) + vec(0.5, -1, 1.5 + i) + vec(2, -1, 2 + i) + vec(1.25, 0.5, 1.75 + i)
    if plane:
        b += bytes([1]) + vec(0, -1, 0) + vec(0, 1, 0)
    if disk:
        b += bytes([0]) + vec(-2, 0.5, -1) + (vec(dbl(1e-300), 0, 1) if extreme else vec(0.25, 0.125, 1)) + num(0.75)
    if rect:
        b += bytes([1]) + vec(-1.5, -1, -2.5) + vec(3, 0, 0) + vec(0, 2.5, 0.25)
    if occlusion:
        b += num(6.0) + num(0.125)  # distance, min_amount
    return b


def packet(lanes):
    """lanes: 8 tuples (ox, oy, oz, dx, dy, dz, tmin, tmax, active)."""
    fields = [struct.pack("<8f", *[lane[k] for lane in lanes]) for k in range(8)]
    return b"".join(fields) + struct.pack("<8i", *[lane[8] for lane in lanes])


def camera_packet(rng):
    lanes = []
    for _ in range(8):
        target = (rng.uniform(-3, 3), rng.uniform(-1, 1.5), rng.uniform(-2, 2))
        d = (target[0], target[1] - 2, target[2] - 7.5)
        lanes.append((0, 2, 7.5, *d, 0, INF, 1))
    return packet(lanes)


def garbage_packet():
    return packet([
        (NAN, 0, 0, 1, 0, 0, 0, INF, 1),           # NaN origin
        (0, 0, 0, 0, 0, 0, 0, INF, 1),             # zero direction
        (0, 0, 0, 2.0 ** -63, 0, 0, 0, INF, 1),       # d.d = 2^-126: usable
        (0, 0, 0, 2.0 ** 63, 0, 0, 0, INF, 1),        # d.d = 2^126: masked
        (0, 0, 0, 1, 0, 0, 5, 1, 1),               # tmin > tmax
        (0, 0, 0, 1, 0, 0, 0, NAN, -1),            # NaN tmax
        (INF, 0, 0, 1, 0, 0, 0, INF, 7),           # infinite origin
        (1e-40, 2, 7.5, 1e-40, -1, -4, -INF, INF, 0),  # inactive
    ])


def inside_packet(rng):
    # From inside the sphere, box and behind the plane; grazing the plane.
    lanes = []
    for i in range(8):
        o = [(0, 0.5, 0), (1.75, -0.5, 0), (0, -2, 0), (3, -1, 0)][i % 4]
        d = (rng.uniform(-1, 1), rng.uniform(-1, 1) if i % 4 != 3 else 0.0, rng.uniform(-1, 1))
        lanes.append((*o, *d, rng.choice([0.0, 0.001]), rng.choice([INF, 10.0]), 1))
    return packet(lanes)


def main():
    os.makedirs(OUT, exist_ok=True)
    rng = random.Random(19)
    seeds = {
        "max_to_one": scene(tonemap=0),
        "clamp_to_color": scene(tonemap=1),
        "saturate": scene(tonemap=2, spheres=3, boxes=2, triangles=2),
        "orthographic": scene(ortho=True),
        "no_shadows_no_lights": scene(ambient=False, directional=False, point=False, attenuated=False, shadows=False),
        "no_objects": scene(spheres=0, boxes=0, triangles=0, plane=False, disk=False, rect=False),
        "extreme_values": scene(extreme=True),
        "occlusion": scene(occlusion=True),
        "occlusion_ambient_only": scene(directional=False, point=False, attenuated=False, shadows=False,
                                        boxes=0, triangles=0, disk=False, rect=False, occlusion=True),
    }
    for name, head in seeds.items():
        data = head + camera_packet(rng) + garbage_packet() + inside_packet(rng)
        with open(os.path.join(OUT, "seed-" + name), "wb") as f:
            f.write(data)
    print(f"wrote {len(seeds)} seeds to {OUT}")


if __name__ == "__main__":
    main()
