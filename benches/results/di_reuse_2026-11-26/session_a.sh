#!/usr/bin/env bash
# One device call of this study: the reuse-off frame with two specular bounces instead of
# three (time on interior), the raw frames' error with and without DI reuse (no denoiser),
# and the two-bounce error on interior. Binaries: solari = solari_base (acd86ef), wrappers
# solari_none (--di-reuse none), solari_none_spec2 (--di-reuse none --specular-bounces 2).
set -u
ROOT=$OUT
OUT=$ROOT/time BINS="solari_base solari_none solari_none_spec2" SCENES=interior \
  bash benches/results/di_reuse_2026-11-26/run.sh time
OUT=$ROOT/raw DENOISER=none BINS="solari solari_none" SCENES="cornell_box sun_boxes interior" \
  RUNS="8:1 136:1 136:16" bash benches/results/atrous_plane_2026-11-26/kernel_error.sh > "$ROOT/raw.log" 2>&1
cat "$ROOT/raw/kernel_error.csv"
OUT=$ROOT/spec2 BINS="solari_none solari_none_spec2" SCENES=interior RUNS="8:1 136:16" \
  bash benches/results/atrous_plane_2026-11-26/kernel_error.sh > "$ROOT/spec2.log" 2>&1
cat "$ROOT/spec2/kernel_error.csv"
