#!/usr/bin/env bash
# The world cache's warm-up rounds under ReSTIR GI at half rate (forty-first session), on
# the device (H200). Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds
# `solari_base` (28cf034), `solari` (67db0be) and wrappers `<bin>_rh` adding
# `--gi restir --gi-half-rate`. kernel_error.sh (960x540, the fallback denoiser, against a
# 1024-spp full-bounce reference) on the Cornell box and interior, frames 4 and 8 and the mean
# of frames 121-136.
set -u
SCENES="cornell_box interior" ERROR_BINS="solari_base_rh solari_rh" RUNS="4:1 8:1 136:16" \
  bash benches/results/restir_half_2026-11-27/run.sh error
