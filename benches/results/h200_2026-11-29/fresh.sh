#!/usr/bin/env bash
# Pixels without history trace at reduced rates (forty-second session), on the device (H200).
# Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds `solari` (the change),
# `solari_old` (the commit before) and wrappers `<bin>_rh` (`--gi restir --gi-half-rate`),
# `<bin>_rq` (`--gi restir --gi-quarter-rate`).
#   time:  ab_passes_h200.sh over the four wrappers with `--denoiser fallback`, cornell_box and
#          interior, 1920x1080, 300 frames, two interleaved reps.
#   orbit: apart_2026-11-27/orbit_error.sh over the four, cornell_box and interior, frames 32
#          and 96 of the orbit camera.
# Usage: bash benches/results/h200_2026-11-29/fresh.sh
set -u
BINS="solari_old_rh solari_rh solari_old_rq solari_rq" TAG=time FLAGS="--denoiser fallback" \
  SCENES="cornell_box interior" bash benches/results/restir_half_2026-11-27/run.sh time
BINS="solari_old_rh solari_rh solari_old_rq solari_rq" SCENES="cornell_box interior" \
  FRAMES="32 96" bash benches/results/apart_2026-11-27/orbit_error.sh
