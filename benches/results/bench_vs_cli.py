#!/usr/bin/env python3
"""The criterion-vs-CLI table from a run of bench_vs_cli_h200.sh.

Usage: bench_vs_cli.py RESULTS_DIR   (the folder holding criterion/ and cli/)

Criterion side: the median estimate of each case (criterion/<group>/<case>/new/estimates.json).
CLI side: per frame of `solari render --mode realtime`, the sum of the component's passes'
GPU times, median over frames 100 to the end (the world cache fills in the first ~100);
for traversal, `solari bench-rays`'s medians. Prints a markdown table.
"""
import glob
import json
import os
import statistics
import sys

# Component: (criterion group, case suffix or None for "<scene>/<n>_lights", realtime passes).
COMPONENTS = [
    ("light tiles", "light_tiles", None, ["light_tiles"]),
    ("light tiles, after the G-buffer", "light_tiles", "after_gbuffer", ["light_tiles"]),
    ("light tiles, frames in flight", "light_tiles", "in_flight", ["light_tiles"]),
    ("ReSTIR DI", "restir_di", "software", ["di_initial_temporal", "di_spatial_shade"]),
    (
        "world cache + cache GI",
        "world_cache",
        "software",
        ["world_cache_decay", "world_cache_compact", "world_cache_update",
         "world_cache_blend", "world_cache_gi"],
    ),
    ("fallback denoiser", "fallback_denoiser", "software",
     ["denoise_temporal", "denoise_variance", "denoise_atrous"]),
    ("whole frame", "frame", "software", None),
    ("light tiles, in the frame", "frame", "software_light_tiles", ["light_tiles"]),
    ("ReSTIR DI, in the frame", "frame", "software_restir_di",
     ["di_initial_temporal", "di_spatial_shade"]),
    (
        "world cache + cache GI, in the frame",
        "frame",
        "software_world_cache",
        ["world_cache_decay", "world_cache_compact", "world_cache_update",
         "world_cache_blend", "world_cache_gi"],
    ),
    ("fallback denoiser, in the frame", "frame", "software_fallback_denoiser",
     ["denoise_temporal", "denoise_variance", "denoise_atrous"]),
]


def criterion_ms(root, group, case):
    """Criterion's median in ms, or None where that bench was not run."""
    path = os.path.join(root, "criterion", group, case, "new", "estimates.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)["median"]["point_estimate"] * 1e-6


def realtime_ms(root, scene, passes, first=100):
    sums = []
    with open(os.path.join(root, "cli", f"realtime_{scene}.jsonl")) as f:
        for line in f:
            r = json.loads(line)
            if r["frame"] < first:
                continue
            timed = {p["pass"]: p["gpu_ms"] for p in r["passes"] if p["gpu_ms"] is not None}
            if passes is None:
                sums.append(sum(timed.values()))
            elif all(p in timed for p in passes):
                sums.append(sum(timed[p] for p in passes))
    return statistics.median(sums) if sums else None


def main():
    root = sys.argv[1]
    scenes = sorted(
        os.path.basename(p)[len("realtime_"):-len(".jsonl")]
        for p in glob.glob(os.path.join(root, "cli", "realtime_*.jsonl"))
    )
    rows = []
    for scene in scenes:
        rays_path = os.path.join(root, "cli", f"rays_{scene}.jsonl")
        rays = {}
        if os.path.exists(rays_path):  # a run limited to some benches skips bench-rays
            with open(rays_path) as f:
                rays = json.loads(f.readline())
        for kind, key in [("primary", "primary_ms"), ("primary+hemi", "ao_ms")]:
            bench = criterion_ms(root, "traversal", f"{scene}_software_{kind}")
            if bench is not None and key in rays:
                rows.append((scene, f"traversal, {kind}", bench, rays[key]))
        for name, group, suffix, passes in COMPONENTS:
            if group == "light_tiles":
                pattern = f"{scene}_*_lights" + (f"_{suffix}" if suffix else "")
                cases = glob.glob(os.path.join(root, "criterion", group, pattern))
                if not cases:
                    continue
                case = os.path.basename(cases[0])
            else:
                case = f"{scene}_{suffix}"
            cli = realtime_ms(root, scene, passes)
            bench = criterion_ms(root, group, case)
            if cli is None or bench is None:
                continue
            rows.append((scene, name, bench, cli))
    print("| scene | component | cargo bench ms | CLI ms | difference |")
    print("|---|---|---|---|---|")
    worst = 0.0
    for scene, name, bench, cli in rows:
        diff = (bench - cli) / cli * 100.0
        worst = max(worst, abs(diff))
        print(f"| {scene} | {name} | {bench:.4f} | {cli:.4f} | {diff:+.1f}% |")
    print(f"\nlargest difference: {worst:.1f}%")


if __name__ == "__main__":
    main()
