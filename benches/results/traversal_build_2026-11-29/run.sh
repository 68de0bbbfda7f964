#!/usr/bin/env bash
# obvhs build parameters beyond its presets, on issue 17's traversal workloads (bench-rays:
# 1920x1080 primary + one cosine hemisphere ray per pixel, 200 frames, software tracing):
# the 8.4M-triangle heightfield (tray_racing's seed and camera) and interior (merged
# world-space BVH). RUNS lists binary:presets pairs, run in that order REPS times
# (interleaved). The binaries (README): `solari_a` the commit under test; the others the
# same with one field of the very-slow preset changed. Carry .gl, .dev/bins.tar.xz and
# .dev/SOLARI_COMMIT. Output: $OUT/rays.jsonl (each line tagged "binary", "rep") and a
# table of medians.
# Usage: RUNS="solari_a:slow,very-slow solari_c:very-slow" REPS=2 bash benches/results/traversal_build_2026-11-29/run.sh
set -u
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
    b=${run%%:*} presets=${run#*:}
    /root/bins/$b bench-rays --heightfield 2048 --frames 200 --presets $presets --json 2>> "$OUT/rays.log" \
      | tag $b $rep >> "$OUT/rays.jsonl"
    /root/bins/$b bench-rays "$(scene_file interior)" --tracer software --frames 200 --presets $presets \
      --json 2>> "$OUT/rays.log" | tag $b $rep >> "$OUT/rays.jsonl"
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
