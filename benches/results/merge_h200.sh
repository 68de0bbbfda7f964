#!/usr/bin/env bash
# Merged instances on the device (H100/H200): `bench-rays --compare-checks` (merged BVH
# against the two-level one, same binary) on the shared scenes, then the per-pass A/B of
# `ab_passes_h200.sh` with BINS="solari_base solari", where `solari_base` is a wrapper that
# runs the same `solari` with `--merge-instances off`. Carry .gl, .dev/bins.tar.xz and
# .dev/SOLARI_COMMIT. Results under $OUT: rays.jsonl, rays.log, ab*/ (see ab_passes_h200.sh).
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
for s in interior furnace_sphere many_lights sun_boxes cornell_box metal_rough_spheres; do
  echo "== rays $s $(date -u +%T)" >&2
  /root/bins/solari bench-rays "$(scene_file "$s")" --tracer software --frames 200 \
    --presets "${RAY_PRESETS:-medium,very-slow}" --compare-checks --json >> "$OUT/rays.jsonl" 2>> "$OUT/rays.log"
done
SCENES="${AB_SCENES:-cornell_box sun_boxes many_lights interior furnace_sphere}" \
  FLAGS="--denoiser fallback" FRAMES=300 REPS=2 BVH_SCENES=" " \
  RESULTS=/root/ab_default bash benches/results/ab_passes_h200.sh > "$OUT/ab_default.txt" 2>&1
mv "$OUT/ab.tar.gz" "$OUT/ab_default.tar.gz"
SCENES="many_lights furnace_sphere interior" FLAGS="--gi cache --denoiser fallback" \
  FRAMES=300 REPS=2 BVH_SCENES=" " RESULTS=/root/ab_cache \
  bash benches/results/ab_passes_h200.sh > "$OUT/ab_cache.txt" 2>&1
mv "$OUT/ab.tar.gz" "$OUT/ab_cache.tar.gz"
