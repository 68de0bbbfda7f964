#!/usr/bin/env bash
# Thirty-seventh session: an H200 came (the first since the 25th session). One warm machine:
#   rays: bench-rays (1920x1080 primary + one cosine hemisphere ray per pixel, 200 frames,
#         software tracing) on the 8.4M-triangle heightfield and interior (merged against
#         two-level with --compare-checks), the workloads of issue 17's traversal bar;
#   time: the per-pass A/B script over the remaining shared scenes with the defaults
#         (metal_rough_spheres, furnace_sphere), cache GI on the three small scenes and
#         ReSTIR GI (`--gi restir`) on the four main ones.
# The four main scenes' default frame came from `gi_cold_2026-11-27/run.sh time` (README).
# Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT.
set -u
source benches/results/device_env.sh
unpack_bins
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$OUT/gpu.csv" 2>/dev/null
S=/root/bins/solari
$S bench-rays --heightfield 2048 --frames 200 --presets medium,very-slow --json >> "$OUT/rays.jsonl" 2>> "$OUT/rays.log"
for s in interior many_lights; do
  $S bench-rays "$(scene_file "$s")" --tracer software --frames 200 --presets medium,very-slow \
    --compare-checks --json >> "$OUT/rays.jsonl" 2>> "$OUT/rays.log"
done
SCENES="metal_rough_spheres furnace_sphere" FLAGS="--denoiser fallback" FRAMES=300 REPS=2 BINS=solari \
  BVH_SCENES=" " RESULTS=/root/ab_default bash benches/results/ab_passes_h200.sh > "$OUT/ab_default.txt" 2>&1
mv "$OUT/ab.tar.gz" "$OUT/ab_default.tar.gz"; mv "$OUT/ab_table.txt" "$OUT/ab_default_table.txt"
SCENES="cornell_box sun_boxes many_lights" FLAGS="--gi cache --denoiser fallback" FRAMES=300 REPS=2 BINS=solari \
  BVH_SCENES=" " RESULTS=/root/ab_cache bash benches/results/ab_passes_h200.sh > "$OUT/ab_cache.txt" 2>&1
mv "$OUT/ab.tar.gz" "$OUT/ab_cache.tar.gz"; mv "$OUT/ab_table.txt" "$OUT/ab_cache_table.txt"
SCENES="cornell_box sun_boxes many_lights interior" FLAGS="--gi restir --denoiser fallback" FRAMES=300 REPS=2 BINS=solari \
  BVH_SCENES=" " RESULTS=/root/ab_restir bash benches/results/ab_passes_h200.sh > "$OUT/ab_restir.txt" 2>&1
mv "$OUT/ab.tar.gz" "$OUT/ab_restir.tar.gz"; mv "$OUT/ab_table.txt" "$OUT/ab_restir_table.txt"
