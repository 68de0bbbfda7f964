#!/usr/bin/env python3
"""Writes a copy of a glTF scene with a grid of point and spot lights under its ceiling
(KHR_lights_punctual), beside the original so it shares its buffers. For timing and checking
point lights on the shared `interior` hall, which has only a sun.

Usage: point_scene.py SRC.gltf DST.gltf [--grid 8x4] [--height 6.2] [--extent 10.5x5.5]
       [--intensity 3]
Every fourth light is a spot pointing down (inner 0.4, outer 0.8 rad)."""
import argparse
import json

ap = argparse.ArgumentParser()
ap.add_argument("src")
ap.add_argument("dst")
ap.add_argument("--grid", default="8x4")
ap.add_argument("--height", type=float, default=6.2)
ap.add_argument("--extent", default="10.5x5.5")
ap.add_argument("--intensity", type=float, default=3.0)
a = ap.parse_args()
nx, nz = (int(v) for v in a.grid.split("x"))
ex, ez = (float(v) for v in a.extent.split("x"))
doc = json.load(open(a.src))
doc.setdefault("extensionsUsed", [])
if "KHR_lights_punctual" not in doc["extensionsUsed"]:
    doc["extensionsUsed"].append("KHR_lights_punctual")
lights = doc.setdefault("extensions", {}).setdefault("KHR_lights_punctual", {}).setdefault("lights", [])
scene = doc["scenes"][doc.get("scene", 0)]
k = 0
for i in range(nx):
    for j in range(nz):
        x = -ex + 2 * ex * i / max(nx - 1, 1)
        z = -ez + 2 * ez * j / max(nz - 1, 1)
        warm = [1.0, 0.85, 0.7] if (i + j) % 2 else [0.8, 0.9, 1.0]
        light = {"type": "point", "name": f"lamp{k}", "color": warm, "intensity": a.intensity}
        node = {"name": f"lamp{k}", "translation": [x, a.height, z]}
        if k % 4 == 3:
            light["type"] = "spot"
            light["spot"] = {"innerConeAngle": 0.4, "outerConeAngle": 0.8}
            # -90 degrees about x: the light's -z points down.
            node["rotation"] = [-0.70710677, 0.0, 0.0, 0.70710677]
        node["extensions"] = {"KHR_lights_punctual": {"light": len(lights)}}
        lights.append(light)
        doc["nodes"].append(node)
        scene["nodes"].append(len(doc["nodes"]) - 1)
        k += 1
json.dump(doc, open(a.dst, "w"))
print(f"{a.dst}: {k} lights added")
