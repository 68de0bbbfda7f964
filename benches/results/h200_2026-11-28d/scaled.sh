#!/usr/bin/env bash
# ReSTIR GI at half rate (spatial reuse at half rate, the default with it) at internal scale
# 1, 0.67 and 0.5 with 1080p output (fortieth session), on the device (H200), one warm
# machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds `solari`
# (58eacd3) and wrappers `solari_s67`, `solari_s50` (add --internal-scale 0.67 / 0.5).
# ab_passes_h200.sh over the three with `--gi restir --gi-half-rate --denoiser fallback`,
# 1920x1080 output, 300 frames, two interleaved reps; table by
# memory_scratch_2026-11-26/ab_variants.py.
# Usage: bash benches/results/h200_2026-11-28d/scaled.sh
set -u
BINS="solari solari_s67 solari_s50" TAG=scaled FLAGS="--gi restir --gi-half-rate --denoiser fallback" \
  REPS=2 bash benches/results/restir_half_2026-11-27/run.sh time
