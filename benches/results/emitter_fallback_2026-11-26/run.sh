#!/usr/bin/env bash
# The emitter BVH's fallback (no emitter BVH: emitter rays trace the whole scene and keep its
# first surface where it emits), on the device, one warm machine. Carry .gl,
# .dev/bins.tar.xz and .dev/SOLARI_COMMIT; the binaries under /root/bins are solari_base
# (6e81863, before), solari (ca1023f, the change) and solari_fs (a wrapper: the change with
# --emitter-bvh off, the fallback itself).
#   time:     the emitter BVH study's `run.sh time` over the three (1920x1080, defaults with
#             --denoiser fallback, 300 frames, two interleaved reps)
#   di-error: its `run.sh di-error` for solari and solari_fs (direct light alone, 960x540,
#             against the 1-bounce reference)
# Usage: bash benches/results/emitter_fallback_2026-11-26/run.sh time|di-error
set -u
here=benches/results/emitter_bvh_2026-11-26
case "${1:-}" in
  time) BINS=${BINS:-solari_base solari solari_fs} bash "$here/run.sh" time ;;
  di-error) BINS=${BINS:-solari solari_fs} bash "$here/run.sh" di-error ;;
  *) echo "usage: $0 time|di-error" >&2; exit 2 ;;
esac
