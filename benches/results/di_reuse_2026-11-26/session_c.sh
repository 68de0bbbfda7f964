#!/usr/bin/env bash
# One device call: Russian roulette at the start of specular GI's paths (experiments/
# specular_roulette_4.patch: survival min(1, max(4 x the first bounce's luminance weight,
# 1/8)); solari_rr2: 2x and 1/4), time on the four scenes and error of frames 8, 136 and the
# mean of 121-136 on each. Binaries: solari (ed5883d), solari_rr4, solari_rr2.
set -u
ROOT=$OUT
OUT=$ROOT/time BINS="solari solari_rr4 solari_rr2" bash benches/results/di_reuse_2026-11-26/run.sh time
OUT=$ROOT/error BINS="solari solari_rr4 solari_rr2" RUNS="8:1 136:1 136:16" \
  bash benches/results/atrous_plane_2026-11-26/kernel_error.sh > "$ROOT/error.log" 2>&1
cat "$ROOT/error/kernel_error.csv"
