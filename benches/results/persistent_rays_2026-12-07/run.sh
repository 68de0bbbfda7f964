#!/usr/bin/env bash
# Persistent threads with dynamic ray fetch against the inline ray bench (device: H200 asked;
# the recorded run got an H100).
# Needs binaries built from 5684a92 (`bench-rays --schedules`, reverted after this measurement;
# persistent_schedule.patch).
# bench-rays, 1920x1080 primary + one cosine hemisphere ray per pixel, 200 frames, software
# tracing, on the 8.4M-triangle heightfield (very-slow build; tray_racing's seed and camera)
# and interior (merged, medium and very-slow), every schedule in $SCHEDULES measured on the same
# BVH, for each binary of $BINS (in /root/bins, from .dev/bins.tar.xz), REPS interleaved rounds.
# Output: $OUT/rays.jsonl (lines tagged "binary" and "rep") and a table of medians.
# SCHEDULES is required. Usage: BINS="solari_a solari_b" SCHEDULES=inline,persistent:131072:8 REPS=2 bash benches/results/persistent_rays_2026-12-07/run.sh
set -u -o pipefail
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
for rep in $(seq 1 ${REPS:-2}); do
  for b in ${BINS:-solari}; do
    S=/root/bins/$b
    tag="s/^{/{\"rep\":$rep,\"binary\":\"$b\",/"
    $S bench-rays --heightfield 2048 --frames 200 --presets very-slow --schedules "$SCHEDULES" --json \
      2>> "$OUT/rays.log" | sed "$tag" >> "$OUT/rays.jsonl"
    $S bench-rays "$(scene_file interior)" --tracer software --frames 200 --presets medium,very-slow \
      --schedules "$SCHEDULES" --json 2>> "$OUT/rays.log" | sed "$tag" >> "$OUT/rays.jsonl"
  done
done
python3 - "$OUT/rays.jsonl" <<'PY' | tee "$OUT/table.txt"
import json, sys, statistics
rows = [json.loads(l) for l in open(sys.argv[1]) if l.startswith("{")]
keys = []
for r in rows:
    r["scene"] = r["scene"].split("/")[-1]
    k = (r["scene"], r["preset"], r.get("binary", "solari"), r["schedule"])
    if k not in keys:
        keys.append(k)
print("scene preset binary schedule: primary_ms ao_ms ao_grays (medians over reps)")
for k in keys:
    sel = [r for r in rows if (r["scene"], r["preset"], r.get("binary", "solari"), r["schedule"]) == k]
    med = lambda f: statistics.median(r[f] for r in sel)
    print(f"{k[0]:16} {k[1]:9} {k[2]:9} {k[3]:24} {med('primary_ms'):.4f} {med('ao_ms'):.4f} {med('ao_grays_per_s'):.3f}")
PY
