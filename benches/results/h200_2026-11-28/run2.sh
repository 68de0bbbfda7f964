#!/usr/bin/env bash
# Thirty-seventh session, second H200 call: the default frame on the shared scenes the first
# call left out (emissive_strength_test, furnace_uniform and damaged_helmet, which is not in
# the repository: carry a copy of ../shared/scenes/damaged_helmet as .dev/damaged_helmet), and
# ReSTIR GI at half rate (`--gi restir --gi-half-rate`) on the four main scenes. Per-pass A/B
# script, 1920x1080, 300 frames, two reps. Carry .gl, .dev/bins.tar.xz, .dev/SOLARI_COMMIT
# and .dev/damaged_helmet.
set -u
mkdir -p "$OUT" crates/solari-testdata/scenes/damaged_helmet
cp .dev/damaged_helmet/* crates/solari-testdata/scenes/damaged_helmet/
SCENES="emissive_strength_test furnace_uniform damaged_helmet" FLAGS="--denoiser fallback" FRAMES=300 REPS=2 BINS=solari \
  BVH_SCENES=" " RESULTS=/root/ab_default2 bash benches/results/ab_passes_h200.sh > "$OUT/ab_default2.txt" 2>&1
mv "$OUT/ab.tar.gz" "$OUT/ab_default2.tar.gz"; rm -f "$OUT/ab_table.txt"
SCENES="cornell_box sun_boxes many_lights interior" FLAGS="--gi restir --gi-half-rate --denoiser fallback" FRAMES=300 REPS=2 BINS=solari \
  BVH_SCENES=" " RESULTS=/root/ab_restir_half bash benches/results/ab_passes_h200.sh > "$OUT/ab_restir_half.txt" 2>&1
mv "$OUT/ab.tar.gz" "$OUT/ab_restir_half.tar.gz"; rm -f "$OUT/ab_table.txt"
