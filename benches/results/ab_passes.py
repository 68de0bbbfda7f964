#!/usr/bin/env python3
"""Tables of an ab_passes_h200.sh run: per scene, each pass group's mean GPU ms for the base
and the new binary (the mean over repetitions of each run's per-pass mean), and the traced
G-buffer's ms under each BVH preset. Usage: ab_passes.py RESULTS_DIR"""
import glob, json, os, re, statistics, sys

r = sys.argv[1]
GROUPS = {
    "denoiser": ("denoise_temporal", "denoise_variance", "denoise_atrous"),
    "atrous": ("denoise_atrous",),
    "DI": ("di_initial_temporal", "di_spatial_shade"),
    "GI": ("gi_initial_temporal", "gi_spatial_shade"),
    "G-buffer": ("gbuffer",),
    "frame": None,
}


def group_ms(t, names):
    if names is None:
        return t.get("gpu_frame_ms") or float("nan")
    p = t.get("passes", {})
    return sum((p.get(n) or {}).get("mean_ms") or 0.0 for n in names)


runs = {}
for f in glob.glob(os.path.join(r, "ab_*.json")):
    m = re.match(r"ab_(.+)_(solari_base|solari)_(\d+)\.json", os.path.basename(f))
    if not m:
        continue
    try:
        t = json.load(open(f))
    except Exception:
        continue
    runs.setdefault((m.group(1), m.group(2)), []).append(t)

print("| scene | group | base ms | new ms | change |")
print("|---|---|---|---|---|")
for scene in sorted({s for s, _ in runs}):
    for g, names in GROUPS.items():
        base = [group_ms(t, names) for t in runs.get((scene, "solari_base"), [])]
        new = [group_ms(t, names) for t in runs.get((scene, "solari"), [])]
        if not base or not new:
            continue
        b, n = statistics.mean(base), statistics.mean(new)
        if not b > 0:
            # The group did not run in this configuration (e.g. GI's passes under --gi cache).
            continue
        print(f"| {scene} | {g} | {b:.4f} | {n:.4f} | {100 * (n / b - 1):+.1f}% |")

print()
print("| scene | BVH preset | G-buffer ms | GPU frame ms | upload s |")
print("|---|---|---|---|---|")
for f in sorted(glob.glob(os.path.join(r, "bvh_*.json"))):
    m = re.match(r"bvh_(.+)_([a-z-]+)\.json", os.path.basename(f))
    try:
        t = json.load(open(f))
    except Exception:
        continue
    print(f"| {m.group(1)} | {m.group(2)} | {group_ms(t, ('gbuffer',)):.4f} | "
          f"{t.get('gpu_frame_ms', float('nan')):.4f} | {t.get('upload_s', float('nan')):.2f} |")
