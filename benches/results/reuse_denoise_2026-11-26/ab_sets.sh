#!/usr/bin/env bash
# A/B of two binaries (.dev/bins.tar.xz: solari_base, solari) under three flag sets, one
# ab_passes_h200.sh run per set, on one warm device machine: the defaults, ReSTIR GI, and
# cache GI (issue 17's many_lights 3 ms configuration). Results: $OUT/ab_SET.{tar.gz,txt,log}.
# Usage: bash benches/results/reuse_denoise_2026-11-26/ab_sets.sh  (SCENES, REPS, FRAMES
# override).
set -u
for set in "default|--denoiser fallback" "restir|--gi restir --denoiser fallback" "cache|--gi cache --denoiser fallback"; do
  name=${set%%|*}
  flags=${set#*|}
  RESULTS=/root/ab_$name FLAGS="$flags" \
    SCENES="${SCENES:-cornell_box sun_boxes many_lights interior furnace_sphere}" \
    REPS=${REPS:-3} FRAMES=${FRAMES:-300} BVH_SCENES="" \
    bash benches/results/ab_passes_h200.sh > /dev/null 2> "$OUT/ab_$name.log"
  mv "$OUT/ab.tar.gz" "$OUT/ab_$name.tar.gz"
  mv "$OUT/ab_table.txt" "$OUT/ab_$name.txt"
done
