#!/usr/bin/env bash
# Extra world-cache update rounds in a run's first frames (forty-first session), on the
# device (H200). Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; /root/bins holds
# `solari` (the commit under test), `solari_k` (experiments/cache_rounds.patch: with
# SOLARI_EXP_CACHE_ITERS=K and SOLARI_EXP_CACHE_WARM=F, frames 0..F-1 record the cache's
# update and blend K times; the same random numbers each round) and wrappers
# `solari_k4f8`, `solari_k4f32` (K 4; F 8 and 32).
# error: atrous_plane_2026-11-26/kernel_error.sh (960x540, the defaults with the fallback
# denoiser, against a 1024-spp full-bounce reference) over ERROR_BINS, RUNS frames:mean-of.
set -u
ERROR_BINS="${ERROR_BINS:-solari solari_k4f8 solari_k4f32}" RUNS="${RUNS:-4:1 8:1 16:1 32:1 136:16}" \
  bash benches/results/restir_half_2026-11-27/run.sh error
