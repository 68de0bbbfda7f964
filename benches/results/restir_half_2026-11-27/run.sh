#!/usr/bin/env bash
# ReSTIR GI from half the pixels (twenty-seventh session), on the device (H100/H200), one warm
# machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds `solari_base`
# (the commit before), `solari` (the change), and wrappers of the change: `solari_half`
# (--gi-half-rate), `solari_restir` (--gi restir), `solari_restir_half` (both).
#   time:  ab_passes_h200.sh over the three, `--gi restir --denoiser fallback`, 1920x1080,
#          300 frames, $REPS interleaved reps (default 2); table by
#          memory_scratch_2026-11-26/ab_variants.py; FLAGS replaces the flags, TAG names the
#          files (default time).
#   error: atrous_plane_2026-11-26/kernel_error.sh (960x540, defaults with the fallback
#          denoiser, against a 1024-spp full-bounce reference; frames 8 and 136 and the mean
#          of frames 121-136) over `solari` (path GI, the default), `solari_restir` and
#          `solari_restir_half` (wrappers adding `--gi restir`, and `--gi-half-rate`).
# Usage: bash benches/results/restir_half_2026-11-27/run.sh time|error|both
set -u
source benches/results/device_env.sh
unpack_bins
BINS=${BINS:-solari_base solari solari_half}
mkdir -p "$OUT"
time_phase() {
  # TAG names this run's files (default time): $OUT/$TAG.tar.gz, $OUT/${TAG}_table.txt.
  local tag=${TAG:-time} r=/root/ab_${TAG:-time}
  RESULTS=$r BINS="$BINS" FLAGS="${FLAGS:---gi restir --denoiser fallback}" \
    REPS=${REPS:-2} FRAMES=300 BVH_SCENES=" " \
    SCENES="${SCENES:-cornell_box sun_boxes many_lights interior}" \
    bash benches/results/ab_passes_h200.sh > "$OUT/${tag}_log.txt" 2>&1
  mv "$OUT/ab.tar.gz" "$OUT/$tag.tar.gz"; rm -f "$OUT/ab_table.txt"
  python3 benches/results/memory_scratch_2026-11-26/ab_variants.py "$r" "$BINS" \
    | tee "$OUT/${tag}_table.txt"
}
error_phase() {
  BINS="${ERROR_BINS:-solari solari_restir solari_restir_half}" RUNS="${RUNS:-8:1 136:1 136:16}" \
    bash benches/results/atrous_plane_2026-11-26/kernel_error.sh 2> "$OUT/error_log.txt"
}
case "${1:-}" in
  time) time_phase ;;
  error) error_phase ;;
  both) time_phase; error_phase ;;
  *) echo "usage: $0 time|error|both" >&2; exit 2 ;;
esac
