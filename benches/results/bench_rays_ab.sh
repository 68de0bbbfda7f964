#!/usr/bin/env bash
# Issue 17's traversal workloads with several binaries, interleaved (device: H200): bench-rays
# (1920x1080 primary + one cosine hemisphere ray per pixel, 200 frames, software tracing) on
# the 8.4M-triangle heightfield (tray_racing's seed and camera) and interior (merged
# world-space BVH). RUNS lists BINARY:PRESETS[:INTERIOR_PRESETS] entries (presets comma
# separated; the heightfield's also serve interior unless given), run in that order REPS
# times. The binaries are in /root/bins (`.dev/bins.tar.xz`; carry .gl, it and
# .dev/SOLARI_COMMIT). Output: $OUT/rays.jsonl (each line tagged "binary" and "rep") and a
# table of medians (ms of each ray kind, build seconds).
# Usage: RUNS="solari_a:very-slow solari_b:very-slow:medium,very-slow" REPS=3 bash benches/results/bench_rays_ab.sh
set -u -o pipefail
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
tag() { python3 -c 'import json,sys
for l in sys.stdin:
    l=l.strip()
    if l.startswith("{"):
        d=json.loads(l); d["binary"]=sys.argv[1]; d["rep"]=int(sys.argv[2]); print(json.dumps(d))' "$@"; }
for rep in $(seq 1 ${REPS:-2}); do
  for run in $RUNS; do
    IFS=: read -r b hf_presets in_presets <<< "$run"
    /root/bins/$b bench-rays --heightfield 2048 --frames 200 --presets "$hf_presets" --json 2>> "$OUT/rays.log" \
      | tag "$b" "$rep" >> "$OUT/rays.jsonl"
    /root/bins/$b bench-rays "$(scene_file interior)" --tracer software --frames 200 \
      --presets "${in_presets:-$hf_presets}" --json 2>> "$OUT/rays.log" | tag "$b" "$rep" >> "$OUT/rays.jsonl"
  done
done
python3 - "$OUT/rays.jsonl" <<'PY'
import json, sys, statistics
rows = [json.loads(l) for l in open(sys.argv[1])]
for r in rows:
    r["scene"] = r["scene"].split("/")[-1]
keys = sorted({(r["scene"], r["binary"], r["preset"]) for r in rows})
print("scene binary preset: primary_ms ao_ms build_s (medians)")
for k in keys:
    sel = [r for r in rows if (r["scene"], r["binary"], r["preset"]) == k]
    med = lambda f: statistics.median(r[f] for r in sel)
    print(f"{k[0]:16} {k[1]:9} {k[2]:9} {med('primary_ms'):.4f} {med('ao_ms'):.4f} {med('bvh_build_s'):.2f}")
PY
