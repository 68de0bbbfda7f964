#!/usr/bin/env bash
# The traced G-buffer's depth-bounded first try, on the device (H100/H200), one warm machine.
# /root/bins holds solari_head (b3704a3, before) and solari_mX (ddb5a79's code with
# GUESS_MARGIN = X; the shipped value is 1.005). Carry .gl, .dev/bins.tar.xz, .dev/SOLARI_COMMIT.
#   bash benches/results/gbuffer_guess_2026-11-26/run.sh "solari_head solari_m1.002 solari_m1.005 solari_m1.01" 2
# Table: mkdir x && tar xzf $OUT/ab.tar.gz -C x && python3 gb_table.py x "<the same BINS>"
# (G-buffer ms, change against the first binary, GPU frame ms; medians of REPS runs).
set -u
RESULTS=/root/ab BINS="$1" FLAGS="--denoiser fallback --gbuffer traced" REPS=${2:-2} FRAMES=300 \
  BVH_SCENES=" " SCENES="furnace_sphere interior cornell_box sun_boxes many_lights metal_rough_spheres furnace_uniform emissive_strength_test" \
  bash benches/results/ab_passes_h200.sh
