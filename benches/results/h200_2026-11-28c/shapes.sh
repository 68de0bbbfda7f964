#!/usr/bin/env bash
# Thirty-ninth session: the ray benchmark's workgroup shape (shipped 8x8) on issue 17's
# traversal workloads: 1920x1080 primary + one cosine hemisphere ray per pixel, 200 frames,
# software tracing, two reps. Shapes from SOLARI_EXP_BENCH_WG (the experiment's bench.rs).
# Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
S=/root/bins/solari
export SOLARI_EXP_BENCH_WG=${SHAPES:-8x4,4x8,16x4,16x8,8x16,16x16,32x1,32x2,32x4,64x1}
for rep in 1 2; do
  $S bench-rays --heightfield 2048 --frames 200 --presets very-slow --json >> "$OUT/rays.jsonl" 2>> "$OUT/rays.log"
  for s in interior many_lights; do
    $S bench-rays "$(scene_file "$s")" --tracer software --frames 200 --presets medium \
      --json >> "$OUT/rays.jsonl" 2>> "$OUT/rays.log"
  done
done
