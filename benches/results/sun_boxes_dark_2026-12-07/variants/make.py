#!/usr/bin/env python3
"""The sun_boxes variants of this folder's README, section 2, written to the folder given (with
a copy of the scene, `sun_boxes.gltf`, and its .bin beside them): `lambert.gltf`, the gold
sphere made rough (metallic 0, roughness 1, the same base colour; it keeps glTF's default
dielectric coat, F0 0.04, so it is Lambertian up to that coat), and `lifted.gltf`, the gold
sphere moved up by its radius (0.8) so it no longer touches the ground. `run.sh` renders
them."""
import json, shutil, sys
from pathlib import Path

src = Path(__file__).resolve().parents[4] / "crates/solari-testdata/scenes/sun_boxes"
out = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/sbl")
out.mkdir(parents=True, exist_ok=True)
shutil.copy(src / "sun_boxes.bin", out / "sun_boxes.bin")
shutil.copy(src / "sun_boxes.gltf", out / "sun_boxes.gltf")
g = json.loads((src / "sun_boxes.gltf").read_text())
a = json.loads(json.dumps(g))
gold = next(m for m in a["materials"] if m["name"] == "gold_metal")
gold["pbrMetallicRoughness"].update(metallicFactor=0.0, roughnessFactor=1.0)
(out / "lambert.gltf").write_text(json.dumps(a))
b = json.loads(json.dumps(g))
next(n for n in b["nodes"] if n.get("name") == "gold_sphere")["translation"] = [-0.4, 1.6, 0.6]
(out / "lifted.gltf").write_text(json.dumps(b))
