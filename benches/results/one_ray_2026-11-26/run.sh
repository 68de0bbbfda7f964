#!/usr/bin/env bash
# The device commands behind benches/RESULTS.md, "One visibility ray in ReSTIR GI's spatial
# reuse" (twenty-first session; each was one `device` call, carrying .gl, .dev/bins.tar.xz
# and .dev/SOLARI_COMMIT). .dev/bins.tar.xz held stripped release builds: `solari_base`
# (584e793), `solari` (the change, where `--gi-spatial-visibility` defaulted to `both`), and
# two wrappers that run the new binary with the other settings, so that all four run
# interleaved on one warm machine:
#   printf '#!/bin/sh\nexec /root/bins/solari "$@" --gi-spatial-visibility chosen\n' > solari_chosen
#   printf '#!/bin/sh\nexec /root/bins/solari "$@" --gi-spatial-visibility neighbour\n' > solari_neighbour
set -u
case "${1:-}" in
time)
  # Per-pass GPU ms, 1920x1080, 300 frames, two interleaved reps (ab.tar.gz; the same with
  # both rays of a pixel traced in fixed rounds is ab_rounds_uncompacted.tar.gz).
  RESULTS=/root/ab BINS="solari_base solari solari_chosen solari_neighbour" \
    FLAGS="--gi restir --denoiser fallback" REPS=2 BVH_SCENES=" " \
    SCENES="cornell_box sun_boxes many_lights interior" bash benches/results/ab_passes_h200.sh ;;
error)
  # relMSE at 960x540 against a 1024-spp full-bounce reference (gi_err.tar.gz).
  RESULTS=/root/gi PHASES=error MODES="restir+spec restir+spec+chosen restir+spec+biased path+spec" \
    bash benches/results/gi_h200.sh ;;
soak)
  # 20,000 frames each of interior and sun_boxes at once, a light toggled every 1,000 (soak/).
  FRAMES=20000 RUNS="interior:1000 sun_boxes:1000" \
    GI_ARGS="--gi restir --gi-spatial-visibility chosen --denoiser fallback" \
    bash benches/results/soak_parallel_h200.sh start > /dev/null 2>&1
  bash benches/results/soak_parallel_h200.sh poll 540 ;;
*) echo "usage: $0 time|error|soak" >&2; exit 2 ;;
esac
