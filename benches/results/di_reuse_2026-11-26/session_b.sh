#!/usr/bin/env bash
# One device call: the new default (DI reuse skipped for few lights under the fallback
# denoiser) against the commit before on the four scenes; then on interior three candidates
# for the last 0.15 ms (the DI shade pass without its shadow ray, for attribution only; four
# à-trous iterations; no BRDF-sampled DI candidate), with their error. Binaries: solari_base
# (acd86ef), solari (this change), solari_noshadow (experiments/noshadow.patch on it), and
# wrappers of solari: solari_iter4 (--denoise-iterations 4), solari_brdf0 (--brdf-candidates
# 0), solari_all (--di-reuse all).
set -u
ROOT=$OUT
OUT=$ROOT/default BINS="solari_base solari" bash benches/results/di_reuse_2026-11-26/run.sh time
OUT=$ROOT/interior BINS="solari solari_all solari_noshadow solari_iter4 solari_brdf0" SCENES=interior \
  bash benches/results/di_reuse_2026-11-26/run.sh time
OUT=$ROOT/error BINS="solari solari_iter4 solari_brdf0" SCENES=interior RUNS="8:1 136:16" \
  bash benches/results/atrous_plane_2026-11-26/kernel_error.sh > "$ROOT/error.log" 2>&1
cat "$ROOT/error/kernel_error.csv"
