#!/usr/bin/env bash
# GI rays with directions shared across a tile (forty-first session), on the device (H200),
# one warm machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds
# `solari` (the commit under test) and experiment builds `solari_c00`, `solari_c01`,
# `solari_c03` (experiments/coherent.patch with GI_SPREAD 0.0, 0.1, 0.3: each pixel's two
# direction numbers are a per-16x8-tile random point plus GI_SPREAD times its own, wrapped),
# and wrappers `<bin>_rh` adding `--gi restir --gi-half-rate`.
#   time:  ab_passes_h200.sh over BINS with the defaults (`--denoiser fallback`: path GI) on
#          SCENES_DEFAULT, then with `--gi restir --gi-half-rate --denoiser fallback` on the
#          four main scenes; 1920x1080, 300 frames, REPS interleaved reps (default 2).
#   error: atrous_plane_2026-11-26/kernel_error.sh over ERROR_BINS, RUNS frames:mean-of.
# Usage: bash benches/results/h200_2026-11-28e/coherent.sh time|error
set -u
R=benches/results/restir_half_2026-11-27/run.sh
BINS=${BINS:-solari solari_c00 solari_c01 solari_c03}
case "${1:-}" in
  time)
    BINS="$BINS" TAG=default FLAGS="--denoiser fallback" \
      SCENES="${SCENES_DEFAULT:-cornell_box sun_boxes many_lights interior furnace_sphere}" bash $R time
    BINS="$BINS" TAG=restir_half FLAGS="--gi restir --gi-half-rate --denoiser fallback" bash $R time ;;
  error)
    ERROR_BINS="${ERROR_BINS:-solari solari_c00 solari_c01 solari_c03 solari_rh solari_c00_rh solari_c01_rh solari_c03_rh}" \
      RUNS="${RUNS:-8:1 32:1 136:16}" bash $R error ;;
  *) echo "usage: $0 time|error" >&2; exit 2 ;;
esac
