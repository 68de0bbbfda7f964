#!/usr/bin/env bash
# Spatial reuse at half rate, and the pixels that traced reusing too while their history is
# young (fortieth session), on the device (H200), one warm machine. Carry .gl,
# .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds `solari` (the experiment),
# `solari_prev` (58eacd3's code), `solari_base` (a wrapper running solari_prev), and
# `solari_restir_h` / `solari_restir_h_prev` (each with --gi restir --gi-half-rate).
#   time:  ab_passes_h200.sh over `solari_base solari` with `--gi restir --gi-half-rate
#          --denoiser fallback`, 1920x1080, 300 frames, two interleaved reps.
#   error: kernel_error.sh over the two wrappers, frames 8, 32, 136 and the mean of 121-136.
# Usage: bash benches/results/h200_2026-11-28d/young.sh
set -u
R=benches/results/restir_half_2026-11-27/run.sh
BINS="solari_base solari" TAG=young FLAGS="--gi restir --gi-half-rate --denoiser fallback" \
  REPS=2 bash $R time > /dev/null 2>&1
ERROR_BINS="solari_restir_h_prev solari_restir_h" RUNS="8:1 32:1 136:1 136:16" bash $R error \
  > "$OUT/error_stdout.txt" 2>&1
