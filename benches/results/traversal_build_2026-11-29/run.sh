#!/usr/bin/env bash
# obvhs build parameters beyond its presets, and the lean nearest hit, on issue 17's traversal
# workloads: `../bench_rays_ab.sh` with RUNS of binary:presets pairs (the same presets for the
# heightfield and interior). The binaries (README): `solari_a` the commit under test; the
# others the same with one field of the very-slow preset changed, or `lean_hit.patch`.
# Usage: RUNS="solari_a:slow,very-slow solari_c:very-slow" REPS=2 bash benches/results/traversal_build_2026-11-29/run.sh
set -u
RUNS="$RUNS" REPS=${REPS:-2} bash benches/results/bench_rays_ab.sh
