#!/usr/bin/env python3
"""The CSV of a quality_h200.sh run: one row per scene and setting with the frame's GPU and
wall time at 1080p and the one-frame error at 960x540, then one row per scene and budget with
auto quality's pick (setting "auto<B>": the setting it chose in the `chosen` column, its own
frame time in gpu_ms). Usage: quality_table.py RESULTS_DIR > quality_table.csv."""
import json, os, sys

r = sys.argv[1]
SCENES = ("cornell_box", "sun_boxes", "many_lights", "interior")


def load(p):
    try:
        return json.load(open(os.path.join(r, p)))
    except Exception:
        return None


nan = float("nan")
print("scene,setting,gpu_ms,wall_ms,rel_mse,flip,mean_ratio,chosen")
for f in sorted(os.listdir(r)):
    if f.endswith("_time.json"):
        stem, auto = f[: -len("_time.json")], False
    elif f.endswith(".json") and "_auto" in f:
        stem, auto = f[: -len(".json")], True
    else:
        continue
    scene = next((s for s in SCENES if stem.startswith(s + "_")), None)
    if scene is None:
        continue
    setting = stem[len(scene) + 1:]
    t = load(f) or {}
    e = (load(f"{scene}_{setting}_error.compare.json") or {}).get("all", {})
    chosen = (t.get("quality") or {}).get("chosen", "") if auto else ""
    row = [t.get("gpu_frame_ms") or nan, t.get("wall_frame_ms") or nan,
           e.get("rel_mse", nan), e.get("flip", nan), e.get("mean_ratio") or nan]
    print(",".join([scene, setting] + [f"{v:.6g}" for v in row] + [chosen]))
