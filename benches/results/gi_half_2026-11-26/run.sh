#!/usr/bin/env bash
# Path GI from half the pixels (RestirGiSettings::half_rate, `--gi-half-rate`), on the device,
# one warm machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT. Binaries under
# /root/bins: solari_prev (b3c132d, before), solari (5d65383, the setting off) and solari_half
# (a wrapper: solari with --gi-half-rate).
#   time:  the emitter BVH study's `run.sh time` over the three (defaults, --denoiser fallback)
#   error: atrous_plane_2026-11-26/kernel_error.sh over solari and solari_half,
#          RUNS="8:1 136:1 136:16" (960x540 against a 1024-spp full-bounce reference)
# The experiment builds that came first (first/, compacted/) replaced
# restir_gi_initial.wesl with restir_gi_initial_half.wesl (idle checkerboard lanes) and
# restir_gi_initial_half_compacted.wesl (the shipped packing) in builds of b3c132d; they ran
# as `BINS="solari solari_gihalf[ solari_gihalfc]" bash .../emitter_bvh_2026-11-26/run.sh time`
# and the same kernel_error.sh call.
# Usage: bash benches/results/gi_half_2026-11-26/run.sh time|error
set -u
case "${1:-}" in
  time) BINS="${BINS:-solari_prev solari solari_half}" bash benches/results/emitter_bvh_2026-11-26/run.sh time ;;
  error) BINS="${BINS:-solari solari_half}" RUNS="${RUNS:-8:1 136:1 136:16}" \
           bash benches/results/atrous_plane_2026-11-26/kernel_error.sh ;;
  *) echo "usage: $0 time|error" >&2; exit 2 ;;
esac
