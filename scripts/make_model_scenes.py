#!/usr/bin/env python3
"""Writes scenes of the assimp test models lit by three shadow-casting lights.

    python3 scripts/make_model_scenes.py --out DIR [--models /usr/share/assimp/models] [--all]

The precision modes' shadow rays on meshes (docs/accuracy.md): each scene is
scenes/models.json's ground plane and camera with one of its models (or all
three), lit by a directional light, a point light and an inverse-square point
light, every one casting shadows. The meshes come from Debian's
assimp-testmodels (tools/install-deps); the scenes name them by absolute path,
so they are written at build time into the build tree, not tracked.
--all also writes models_shadows_all.json, the three models together (at
400 x 300). The build leaves it out: under three lights, 14% of its lanes lie
near a shadow boundary (the spider's legs), past the 10% of lanes the
end-to-end test may leave out, which keeps it from passing by leaving lanes out.
"""
import argparse
import json
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, help="directory the scenes go to")
    ap.add_argument("--models", default="/usr/share/assimp/models", help="assimp-testmodels' folder")
    ap.add_argument("--all", action="store_true", help="also the three models together (models_shadows_all.json)")
    args = ap.parse_args()
    with open(os.path.join(ROOT, "scenes", "models.json")) as f:
        base = json.load(f)
    prefix = "/usr/share/assimp/models"
    plane = [o for o in base["objects"] if o["type"] == "plane"]
    meshes = [dict(o, file=o["file"].replace(prefix, args.models)) for o in base["objects"] if o["type"] == "mesh"]
    lights = [dict(l, shadows=True) for l in base["lights"]]
    os.makedirs(args.out, exist_ok=True)
    scenes = {"models_shadows_all": meshes} if args.all else {}
    for m in meshes:
        scenes["models_shadows_" + os.path.splitext(os.path.basename(m["file"]))[0].lower()] = [m]
    for name, objects in scenes.items():
        scene = dict(base, lights=lights, objects=plane + objects)
        if len(objects) > 1:
            # 18% of the lanes near a shadow boundary at 160 x 120, 14% at 400 x 300.
            scene["camera"] = dict(base["camera"], width=400, height=300)
        path = os.path.join(args.out, name + ".json")
        with open(path, "w") as f:
            json.dump(scene, f, indent=1)
            f.write("\n")
        print(f"wrote {path}: {len(objects)} model(s), {len(lights)} shadow-casting lights")


if __name__ == "__main__":
    main()
