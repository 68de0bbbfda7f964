#!/usr/bin/env bash
# ReSTIR DI's reuse (its merge's attribution, the few-lights rule) and the one-pass GI and DI,
# on the device, one warm machine. Carry .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT; the
# binaries under /root/bins are the builds under test (experiment builds with one patch of
# experiments/ applied: solari_NAME for experiments/NAME.patch) and wrappers that add flags
# (solari_none: --di-reuse none). README.md lists each call.
#   time: the emitter BVH study's `run.sh time` over $BINS (ab_passes_h200.sh, 1920x1080,
#         defaults with --denoiser fallback, 300 frames, two interleaved reps; table by
#         memory_scratch_2026-11-26/ab_variants.py), SCENES as there
# Usage: BINS="..." SCENES="..." bash benches/results/di_reuse_2026-11-26/run.sh time
set -u
case "${1:-}" in
  time) BINS="${BINS:-solari_base solari_none}" bash benches/results/emitter_bvh_2026-11-26/run.sh time ;;
  *) echo "usage: $0 time" >&2; exit 2 ;;
esac
