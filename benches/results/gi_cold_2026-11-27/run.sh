#!/usr/bin/env bash
# ReSTIR GI's young frames (twenty-eighth session), on the device (H100/H200), one warm machine.
# Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds `solari_base` (the
# commit before), `solari` (the change: cold cells ignored and the adaptive cap, both on by
# default) and wrappers of it: `solari_restir_old` (--gi restir with both off: the old
# estimator), `solari_restir_cold` (--gi restir, adaptive cap off), `solari_restir` (--gi restir).
#   time:  ab_passes_h200.sh over BINS (default "solari_base solari"), FLAGS (default
#          `--gi restir --denoiser fallback`), 1920x1080, 300 frames, $REPS interleaved reps
#          (default 3); table by memory_scratch_2026-11-26/ab_variants.py; TAG names the files.
#   error: atrous_plane_2026-11-26/kernel_error.sh (960x540, defaults with the fallback
#          denoiser, against a 1024-spp full-bounce reference) over ERROR_BINS (default: path
#          GI and the three ReSTIR GI wrappers), RUNS frames:mean-of (default "8:1 32:1 136:1
#          136:16").
# Usage: bash benches/results/gi_cold_2026-11-27/run.sh time|error|both
# It runs restir_half_2026-11-27/run.sh (the same phases) with this session's defaults.
set -u
R=benches/results/restir_half_2026-11-27/run.sh
time_phase() { BINS="${BINS:-solari_base solari}" REPS=${REPS:-3} bash $R time; }
error_phase() {
  ERROR_BINS="${ERROR_BINS:-solari solari_restir_old solari_restir_cold solari_restir}" \
    RUNS="${RUNS:-8:1 32:1 136:1 136:16}" bash $R error
}
case "${1:-}" in
  time) time_phase ;;
  error) error_phase ;;
  both) time_phase; error_phase ;;
  *) echo "usage: $0 time|error|both" >&2; exit 2 ;;
esac
