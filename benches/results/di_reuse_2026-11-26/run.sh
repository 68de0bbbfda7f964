#!/usr/bin/env bash
# ReSTIR DI's reuse (its merge's attribution, the few-lights rule) on the device, one warm
# machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; the binaries under /root/bins
# are solari_base (the commit under test) and experiment builds of it, each with one patch of
# experiments/ applied (solari_NAME for experiments/NAME.patch), plus wrappers of solari_base
# that add flags (solari_none: --di-reuse none).
#   time: ab_passes_h200.sh over $BINS, 1920x1080, defaults with --denoiser fallback, 300
#         frames, two interleaved reps; table by memory_scratch_2026-11-26/ab_variants.py
# Usage: BINS="..." SCENES="..." bash benches/results/di_reuse_2026-11-26/run.sh time
set -u
source benches/results/device_env.sh
unpack_bins
BINS=${BINS:-solari_base solari_none}
mkdir -p "$OUT"
case "${1:-}" in
  time)
    RESULTS=/root/ab BINS="$BINS" FLAGS="--denoiser fallback" REPS=${REPS:-2} FRAMES=300 \
      BVH_SCENES=" " SCENES="${SCENES:-cornell_box sun_boxes many_lights interior}" \
      bash benches/results/ab_passes_h200.sh > "$OUT/time_log.txt" 2>&1
    python3 benches/results/memory_scratch_2026-11-26/ab_variants.py /root/ab "$BINS" \
      | tee "$OUT/time_table.txt"
    ;;
  *) echo "usage: $0 time" >&2; exit 2 ;;
esac
