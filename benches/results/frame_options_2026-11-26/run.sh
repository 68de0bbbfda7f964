#!/usr/bin/env bash
# The whole default frame against two settings that trade error for time, on the device, one
# warm machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT. Binaries under /root/bins:
# solari (81f1318's code) and wrappers that add `--di-reuse temporal|spatial|none`
# (solari_di_*) or `--di-reuse none --gi-half-rate` (solari_fast).
#   reuse: the emitter BVH study's `run.sh time` over solari and the three solari_di_*, on
#          interior and many_lights (reuse/)
#   time:  the same over solari, solari_di_none and solari_fast on the four scenes
#   error: atrous_plane_2026-11-26/kernel_error.sh over the same three, RUNS="8:1 136:1 136:16"
# Usage: bash benches/results/frame_options_2026-11-26/run.sh reuse|time|error
set -u
case "${1:-}" in
  reuse) BINS="solari solari_di_temporal solari_di_spatial solari_di_none" \
           SCENES="interior many_lights" bash benches/results/emitter_bvh_2026-11-26/run.sh time ;;
  time) BINS="solari solari_di_none solari_fast" bash benches/results/emitter_bvh_2026-11-26/run.sh time ;;
  error) BINS="solari solari_di_none solari_fast" RUNS="${RUNS:-8:1 136:1 136:16}" \
           bash benches/results/atrous_plane_2026-11-26/kernel_error.sh ;;
  *) echo "usage: $0 reuse|time|error" >&2; exit 2 ;;
esac
