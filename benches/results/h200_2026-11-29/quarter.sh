#!/usr/bin/env bash
# GI from a quarter of the pixels (forty-second session), on the device (H200), one warm
# machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds `solari`
# (the commit under test), `solari_base` (the commit before) and wrappers: `<bin>_rh` adding
# `--gi restir --gi-half-rate`, `solari_rq` `--gi restir --gi-quarter-rate`, `solari_pq`
# `--gi-quarter-rate` (path GI), `solari_ph` `--gi-half-rate`.
#   time:  ab_passes_h200.sh over BINS (default "solari_base_rh solari_rh solari_rq solari
#          solari_ph solari_pq") with `--denoiser fallback` on SCENES (default the four),
#          1920x1080, 300 frames, REPS interleaved reps (default 2).
#   error: atrous_plane_2026-11-26/kernel_error.sh over ERROR_BINS (default "solari
#          solari_rh solari_rq solari_pq"), RUNS frames:mean-of (default "8:1 32:1 136:1
#          136:16"): 960x540, the fallback denoiser, against a 1024-spp full-bounce reference.
# Usage: bash benches/results/h200_2026-11-29/quarter.sh time|error|both
set -u
R=benches/results/restir_half_2026-11-27/run.sh
error() {
  ERROR_BINS="${ERROR_BINS:-solari solari_rh solari_rq solari_pq}" \
    RUNS="${RUNS:-8:1 32:1 136:1 136:16}" bash $R error
}
timing() {
  BINS="${BINS:-solari_base_rh solari_rh solari_rq solari solari_ph solari_pq}" TAG=${TAG:-time} \
    FLAGS="--denoiser fallback" SCENES="${SCENES:-cornell_box sun_boxes many_lights interior}" \
    bash $R time
}
case "${1:-}" in
  error) error ;;
  time) timing ;;
  both) timing; error ;;
  *) echo "usage: $0 time|error|both" >&2; exit 2 ;;
esac
