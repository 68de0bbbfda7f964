#!/usr/bin/env python3
"""The CSV of a quality_h200.sh run: one row per scene and setting with the frame's GPU and
wall time at 1080p, the one-frame error at 960x540 of a still camera, and the mean relMSE of
the orbit frames measured (rel_mse_moving: a moving camera, the orbit phase), then one row per scene and budget with
auto quality's pick (setting "auto<B>": the setting it chose in the `chosen` column, its own
frame time in gpu_ms). reference_noise and reference_noise_moving are what the references'
own noise adds to rel_mse and rel_mse_moving (from `compare --reference-variance`, which
sweep_phases.sh passes since the forty-fourth session; nan for older runs), the columns
auto quality takes out before it compares settings. Usage: quality_table.py RESULTS_DIR >
quality_table.csv."""
import json, os, re, sys

r = sys.argv[1]
SCENES = ("cornell_box", "sun_boxes", "many_lights", "interior")


def load(p):
    try:
        return json.load(open(os.path.join(r, p)))
    except Exception:
        return None


nan = float("nan")
print("scene,setting,gpu_ms,wall_ms,rel_mse,flip,mean_ratio,chosen,rel_mse_moving,"
      "reference_noise,reference_noise_moving")


def noise(compare):
    """The reference's noise term of a compare JSON, or None."""
    n = ((compare or {}).get("reference_noise") or {}).get("all") or {}
    return n.get("rel_mse")
ORBIT = re.compile(r"^(.*)_orbit(\d+)\.compare\.json$")
stems = set()
orbit = {}  # stem -> the orbit frames' compare files
for f in os.listdir(r):
    if ORBIT.match(f):
        orbit.setdefault(ORBIT.match(f).group(1), []).append(f)
for f in os.listdir(r):
    if f.endswith("_time.json"):
        stems.add((f[: -len("_time.json")], False))
    elif f.endswith(".json") and "_auto" in f:
        stems.add((f[: -len(".json")], True))
    elif ORBIT.match(f):
        stems.add((ORBIT.match(f).group(1), False))
for stem, auto in sorted(stems):
    scene = next((s for s in SCENES if stem.startswith(s + "_")), None)
    if scene is None:
        continue
    setting = stem[len(scene) + 1:]
    t = (load(f"{stem}.json") if auto else load(f"{stem}_time.json")) or {}
    ec = load(f"{scene}_{setting}_error.compare.json") or {}
    e = ec.get("all", {})
    chosen = (t.get("quality") or {}).get("chosen", "") if auto else ""
    oc = [load(f) or {} for f in orbit.get(stem, [])]
    moving = [c.get("all", {}).get("rel_mse") for c in oc]
    moving = [m for m in moving if m is not None]
    moving_noise = [noise(c) for c in oc]
    moving_noise = [m for m in moving_noise if m is not None]
    row = [t.get("gpu_frame_ms") or nan, t.get("wall_frame_ms") or nan,
           e.get("rel_mse", nan), e.get("flip", nan), e.get("mean_ratio") or nan]
    mv = sum(moving) / len(moving) if moving else nan
    # The moving noise is the mean over the same frames as rel_mse_moving's.
    mn = sum(moving_noise) / len(moving_noise) if moving_noise and len(moving_noise) == len(moving) else nan
    sn = noise(ec)
    print(",".join([scene, setting] + [f"{v:.6g}" for v in row]
                   + [chosen, f"{mv:.6g}", f"{sn if sn is not None else nan:.6g}", f"{mn:.6g}"]))
