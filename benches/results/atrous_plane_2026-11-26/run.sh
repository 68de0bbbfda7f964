#!/usr/bin/env bash
# The device commands behind benches/RESULTS.md, "The denoiser's plane distance without the
# tap's position" (twenty-second session; one `device` call each, carrying .gl,
# .dev/bins.tar.xz and .dev/SOLARI_COMMIT). .dev/bins.tar.xz held stripped release builds:
# `solari_base` (3845149) and `solari` (c69a11b) for `time` and `image`; for `kernel-time`
# and `kernel-error`, `solari_c69` (c69a11b), `solari_dk` (a732f7f, the diamond kernel the
# default) and a wrapper running it with the full kernel:
#   printf '#!/bin/sh\nexec /root/bins/solari_dk "$@" --denoise-kernel full\n' > solari_dk_full
# (The experiment builds before a732f7f, in kernel/experiment_*, hard-coded the diamond
# (`solari_k13`) or the 5x5 square without its corners (`solari_k21`); `solari_i4` was a
# wrapper adding --denoise-iterations 4; their commands were these with BINS="solari
# solari_k21 solari_k13 solari_i4", RUNS as default and "1:1 8:1".)
set -u
case "${1:-}" in
time)
  # Per-pass GPU ms, 1920x1080, 300 frames, default settings with the fallback denoiser, two
  # interleaved reps (ab.tar.gz, ab_variants.txt).
  RESULTS=/root/ab BINS="solari_base solari" FLAGS="--denoiser fallback" REPS=2 BVH_SCENES=" " \
    SCENES="cornell_box sun_boxes many_lights interior" bash benches/results/ab_passes_h200.sh
  python3 benches/results/memory_scratch_2026-11-26/ab_variants.py /root/ab "solari_base solari" \
    | tee "$OUT/ab_variants.txt" ;;
image)
  # The same frames through both: frame 120 at 1920x1080 (default settings, fallback
  # denoiser) twice with the base binary and once with the change; each compared with the
  # base's first (the base against itself is the run-to-run floor: the world cache's atomics
  # sum in no fixed order). image.txt.
  source benches/results/device_env.sh
  unpack_bins
  mkdir -p /root/img
  for s in cornell_box sun_boxes many_lights interior; do
    f=$(scene_file "$s")
    for run in base_a:solari_base base_b:solari_base new:solari; do
      /root/bins/${run#*:} render "$f" --mode realtime --denoiser fallback --frames 120 \
        --size 1920x1080 --out /root/img/${s}_${run%%:*}.exr > /dev/null 2>&1
    done
    for t in base_b new; do
      echo "$s $t against base_a: $(/root/bins/solari compare /root/img/${s}_$t.exr /root/img/${s}_base_a.exr | tr '\n' ' ')"
    done
  done | tee "$OUT/image.txt" ;;
kernel-time)
  # The kernels' time: as `time` (kernel/time_variants.txt, kernel/time.tar.gz).
  RESULTS=/root/ab BINS="solari_c69 solari_dk solari_dk_full" FLAGS="--denoiser fallback" REPS=2 \
    BVH_SCENES=" " SCENES="cornell_box sun_boxes many_lights interior" \
    bash benches/results/ab_passes_h200.sh
  python3 benches/results/memory_scratch_2026-11-26/ab_variants.py /root/ab \
    "solari_c69 solari_dk solari_dk_full" | tee "$OUT/ab_variants.txt" ;;
kernel-error)
  # The kernels' error against full-bounce references at 960x540: frames 1 and 8 (young
  # histories), frame 136 and the mean of 16 after 120 (kernel/error.csv).
  RUNS="1:1 8:1 136:1 136:16" BINS="solari_dk solari_dk_full" \
    bash benches/results/atrous_plane_2026-11-26/kernel_error.sh ;;
cache-gi)
  # Issue 17's "DI + cache GI + fallback denoiser" with a732f7f alone (`solari` in the tar):
  # the same command with cache GI, two reps (cache_gi/).
  RESULTS=/root/ab BINS="solari" FLAGS="--gi cache --denoiser fallback" REPS=2 BVH_SCENES=" " \
    SCENES="cornell_box sun_boxes many_lights interior" bash benches/results/ab_passes_h200.sh
  python3 benches/results/memory_scratch_2026-11-26/ab_variants.py /root/ab "solari" \
    | tee "$OUT/cache_gi_passes.txt" ;;
*) echo "usage: $0 time|image|kernel-time|kernel-error|cache-gi" >&2; exit 2 ;;
esac
