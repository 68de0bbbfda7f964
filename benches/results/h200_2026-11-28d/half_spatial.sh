#!/usr/bin/env bash
# ReSTIR GI's spatial reuse at half rate (fortieth session), on the device (H200), one warm
# machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds
# `solari_before` (e01ad54), `solari` (the change; which build each call ran: README) and
# wrappers of it: `solari_hs` (adds --gi-half-rate-spatial), `solari_restir`
# (--gi restir), `solari_restir_h` (--gi restir --gi-half-rate), `solari_restir_hs` (the same
# with --gi-half-rate-spatial); for the committed build, where it is on by default,
# `solari_off` (adds --gi-half-rate-spatial off).
#   time:  ab_passes_h200.sh over BINS (default "solari_before solari solari_hs") with
#          `--gi restir --gi-half-rate --denoiser fallback`, 1920x1080, 300 frames, REPS
#          interleaved reps (default 2); table by memory_scratch_2026-11-26/ab_variants.py.
#   error: atrous_plane_2026-11-26/kernel_error.sh (960x540, defaults with the fallback
#          denoiser, against a 1024-spp full-bounce reference) over ERROR_BINS (default
#          "solari_restir solari_restir_h solari_restir_hs"), RUNS frames:mean-of (default
#          "8:1 32:1 136:1 136:16").
# Usage: bash benches/results/h200_2026-11-28d/half_spatial.sh time|error
set -u
R=benches/results/restir_half_2026-11-27/run.sh
case "${1:-}" in
  time) BINS="${BINS:-solari_before solari solari_hs}" TAG=${TAG:-time} \
          FLAGS="--gi restir --gi-half-rate --denoiser fallback" REPS=${REPS:-2} bash $R time ;;
  error) ERROR_BINS="${ERROR_BINS:-solari_restir solari_restir_h solari_restir_hs}" \
          RUNS="${RUNS:-8:1 32:1 136:1 136:16}" bash $R error ;;
  *) echo "usage: $0 time|error" >&2; exit 2 ;;
esac
