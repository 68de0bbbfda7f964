#!/usr/bin/env bash
# Thirty-ninth session: the ray benchmark's persistent kernel (lanes fetch their next ray from
# the workgroup's tile inside the traversal loop, `ray_bench_persistent.wesl`) against the
# shipped kernel, on issue 17's traversal workloads: 1920x1080 primary + one cosine hemisphere
# ray per pixel, 200 frames, software tracing, two reps. Tiles from SOLARI_EXP_BENCH_TILE.
# Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
S=/root/bins/solari
export SOLARI_EXP_BENCH_TILE=${TILES:-8,16,32}
for rep in 1 2; do
  $S bench-rays --heightfield 2048 --frames 200 --presets ${HF_PRESETS:-very-slow} --json >> "$OUT/rays.jsonl" 2>> "$OUT/rays.log"
  for s in interior many_lights; do
    $S bench-rays "$(scene_file "$s")" --tracer software --frames 200 --presets medium,very-slow \
      --json >> "$OUT/rays.jsonl" 2>> "$OUT/rays.log"
  done
done
