#!/usr/bin/env python3
"""Tables from a run of brdf_h200.sh: per-pass GPU ms old vs new (mean of the two rounds of
each binary's per-pass means over 200 frames), and the brightness ratios from `solari compare`.

Usage: brdf_table.py RESULTS_DIR
"""
import glob
import json
import os
import sys

root = sys.argv[1]
PASSES = ["di_initial_temporal", "di_spatial_shade", "gi_initial_temporal", "gi_spatial_shade",
          "specular_gi", "world_cache_update"]
scenes = sorted({os.path.basename(p).split("_old_")[0][len("time_"):]
                 for p in glob.glob(os.path.join(root, "time_*_old_1.json"))})


def load(scene, b):
    runs = [json.load(open(p)) for p in sorted(glob.glob(os.path.join(root, f"time_{scene}_{b}_*.json")))]
    out = {}
    for p in PASSES + ["frame"]:
        vals = []
        for r in runs:
            if p == "frame":
                vals.append(r["gpu_frame_ms"])
            else:
                ms = r["passes"][p]["mean_ms"]
                if ms is not None:
                    vals.append(ms)
        out[p] = sum(vals) / len(vals) if vals else None
    return out, runs[0]["gi"]


print("| scene | GI | pass | before ms | layered ms | change |")
print("|---|---|---|---|---|---|")
for s in scenes:
    old, gi = load(s, "old")
    new, _ = load(s, "new")
    for p in PASSES + ["frame"]:
        if old[p] is None or new[p] is None:
            continue
        print(f"| {s} | {gi} | {p} | {old[p]:.3f} | {new[p]:.3f} | {(new[p] / old[p] - 1) * 100:+.1f}% |")

print()
print("| scene | seeds' layering / layered (reference) | gltf-spec / layered (reference) | real-time / reference, before | real-time / reference, layered |")
print("|---|---|---|---|---|")
for s in scenes:
    def ratio(name):
        p = os.path.join(root, f"cmp_{s}_{name}.json")
        if not os.path.exists(p):
            return float("nan")
        try:
            return json.load(open(p))["all"]["mean_ratio"]
        except (ValueError, KeyError):
            return float("nan")
    print(f"| {s} | {ratio('ref_old_vs_ref_layered'):.4f} | {ratio('ref_gltf-spec_vs_ref_layered'):.4f} "
          f"| {ratio('rt_old_vs_ref_old'):.4f} | {ratio('rt_new_vs_ref_layered'):.4f} |")
