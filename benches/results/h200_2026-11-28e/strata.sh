#!/usr/bin/env bash
# GI directions stratified over 4x4 pixel blocks (forty-first session), on the device (H200),
# one warm machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds
# `solari` (the commit under test), `solari_st` (the build with strata; which code: README)
# and wrappers `<bin>_rh` adding `--gi restir --gi-half-rate`.
#   error: atrous_plane_2026-11-26/kernel_error.sh over ERROR_BINS (default the four), RUNS
#          frames:mean-of (default "8:1 32:1 136:1 136:16"): 960x540, the fallback denoiser,
#          against a 1024-spp full-bounce reference.
#   time:  ab_passes_h200.sh over BINS (default "solari solari_st") with the defaults
#          (`--denoiser fallback`) on SCENES (default cornell_box interior furnace_sphere),
#          1920x1080, 300 frames, REPS interleaved reps (default 2).
# Usage: bash benches/results/h200_2026-11-28e/strata.sh error|time|both
set -u
R=benches/results/restir_half_2026-11-27/run.sh
error() {
  ERROR_BINS="${ERROR_BINS:-solari solari_st solari_rh solari_st_rh}" \
    RUNS="${RUNS:-8:1 32:1 136:1 136:16}" bash $R error
}
timing() {
  BINS="${BINS:-solari solari_st}" TAG=${TAG:-time} FLAGS="--denoiser fallback" \
    SCENES="${SCENES:-cornell_box interior furnace_sphere}" bash $R time
}
case "${1:-}" in
  error) error ;;
  time) timing ;;
  both) error; timing ;;
  *) echo "usage: $0 error|time|both" >&2; exit 2 ;;
esac
