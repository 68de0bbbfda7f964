#!/usr/bin/env python3
"""The CSV of a gi_h200.sh run: one row per scene and mode, with the frame's GPU time at
1080p, the GI and specular passes' times, and the error of one frame and of a 16-frame mean
against the reference, and what the reference's own noise adds to those errors
(reference_noise, from `compare --reference-variance`; nan for runs before the forty-fourth
session). Usage: gi_table.py RESULTS_DIR > gi_table.csv (every mode found)."""
import json, os, sys

r = sys.argv[1]


def load(p):
    try:
        return json.load(open(os.path.join(r, p)))
    except Exception:
        return None


rows = []
for f in sorted(os.listdir(r)):
    if not f.endswith("_1080p.json"):
        continue
    stem = f[: -len("_1080p.json")]
    scene = next((s for s in ("cornell_box", "sun_boxes", "many_lights", "interior",
                              "metal_rough_spheres") if stem.startswith(s + "_")), None)
    if scene is None:
        continue
    mode = stem[len(scene) + 1:]
    t = load(f) or {}
    p = t.get("passes", {})
    ms = lambda n: (p.get(n) or {}).get("mean_ms") or 0.0
    gi = sum(ms(n) for n in ("gi_initial_temporal", "gi_spatial_shade", "world_cache_gi"))
    di = sum(ms(n) for n in ("di_initial_temporal", "di_spatial_shade"))
    c = [load(f"{scene}_{mode}_mean{m}.compare.json") or {} for m in (1, 16)]
    e = [x.get("all", {}) for x in c]
    nan = float("nan")
    noise = ((c[0].get("reference_noise") or {}).get("all") or {}).get("rel_mse", nan)
    rows.append([scene, mode, t.get("gpu_frame_ms") or nan, di, gi, ms("specular_gi"),
                 e[0].get("rel_mse", nan), e[1].get("rel_mse", nan), e[0].get("flip", nan),
                 e[0].get("mean_ratio") or nan, noise])
print("scene,mode,gpu_ms,di_ms,gi_ms,specular_ms,rel_mse_1,rel_mse_16,flip_1,mean_ratio_1,"
      "reference_noise")
for row in rows:
    print(",".join(row[:2] + [f"{v:.6g}" for v in row[2:]]))
