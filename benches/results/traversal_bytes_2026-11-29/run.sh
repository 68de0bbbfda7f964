#!/usr/bin/env bash
# The node test's bytes as floats by a mantissa trick (README) against the commit before it:
# `../bench_rays_ab.sh` with `solari_a` and `solari_b`, the heightfield at very-slow and
# interior at medium and very-slow, REPS interleaved rounds (the table of medians; README's
# percentages are b over a).
# Usage: REPS=3 bash benches/results/traversal_bytes_2026-11-29/run.sh
set -u
RUNS="solari_a:very-slow:medium,very-slow solari_b:very-slow:medium,very-slow" REPS=${REPS:-3} \
  bash benches/results/bench_rays_ab.sh
