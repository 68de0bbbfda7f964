#!/usr/bin/env bash
# Issue 17's traversal workloads (bench-rays: 1920x1080 primary + one cosine hemisphere ray per
# pixel, 200 frames, software tracing) with two binaries, interleaved, REPS rounds:
# `solari_a` (the commit before the change) and `solari_b` (the node test's bytes turned into
# floats by a mantissa trick instead of int-to-float conversions). The 8.4M-triangle
# heightfield (very-slow build, tray_racing's seed and camera) and interior (merged world-space
# BVH, medium and very-slow). Carry .gl, .dev/bins.tar.xz (the two stripped binaries) and
# .dev/SOLARI_COMMIT. Output: $OUT/rays.jsonl (each line tagged with "binary" and "rep").
# Usage: REPS=3 bash benches/results/traversal_bytes_2026-11-29/run.sh
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
for rep in $(seq 1 ${REPS:-3}); do
  for b in solari_a solari_b; do
    /root/bins/$b bench-rays --heightfield 2048 --frames 200 --presets very-slow --json 2>> "$OUT/rays.log" \
      | tag $b $rep >> "$OUT/rays.jsonl"
    /root/bins/$b bench-rays "$(scene_file interior)" --tracer software --frames 200 --presets medium,very-slow \
      --json 2>> "$OUT/rays.log" | tag $b $rep >> "$OUT/rays.jsonl"
  done
done
python3 - "$OUT/rays.jsonl" <<'PY'
import json, sys, statistics
rows = [json.loads(l) for l in open(sys.argv[1])]
keys = sorted({(r["scene"].split("/")[-1], r["preset"]) for r in rows})
for s, p in keys:
    for what in ("primary_ms", "ao_ms"):
        med = {b: statistics.median(r[what] for r in rows if r["binary"] == b and r["scene"].split("/")[-1] == s and r["preset"] == p) for b in ("solari_a", "solari_b")}
        print(f"{s:16} {p:9} {what:10} a {med['solari_a']:.4f}  b {med['solari_b']:.4f}  ({(med['solari_b']/med['solari_a']-1)*100:+.1f}%)")
PY
