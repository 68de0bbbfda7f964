#!/usr/bin/env bash
# Pixels without history at reduced rates (forty-third session), on the device (H200). Carry
# .gl, .dev/bins.tar.xz and .dev/SOLARI_COMMIT. /root/bins holds `solari_old` (the commit
# before), `solari_a` and `solari_b` (the variants, README), `solari` (a copy of the one that
# renders references and compares) and wrappers `<bin>_rq` (`--gi restir --gi-quarter-rate`),
# `<bin>_rh` (`--gi restir --gi-half-rate`), `<bin>_rqoff` (`_rq` with `--gi-trace-fresh off`).
#   time:  restir_half_2026-11-27/run.sh time over $BINS with `--denoiser fallback`, $SCENES,
#          1920x1080, 300 frames, two interleaved reps.
#   orbit: apart_2026-11-27/orbit_error.sh over $BINS, $SCENES, frames 32 and 96 of the
#          orbit camera.
#   still: atrous_plane_2026-11-26/kernel_error.sh over $BINS, $SCENES (960x540, a still
#          camera, frames 8 and 136 and the mean of 121-136).
#   soak:  `solari soak interior --frames $FRAMES --toggle-lights 1000 --camera-path orbit
#          --size 1920x1080 --gi restir --gi-quarter-rate` (every pass's non-finite detector
#          on, every frame), the summary in $OUT/soak.json.
# Usage: BINS="..." SCENES="..." bash benches/results/merge_fresh_2026-11-29/run.sh time|orbit|still|soak
set -u
case "${1:-}" in
  time)
    TAG=${TAG:-time} FLAGS="--denoiser fallback" bash benches/results/restir_half_2026-11-27/run.sh time ;;
  orbit)
    FRAMES="32 96" bash benches/results/apart_2026-11-27/orbit_error.sh ;;
  still)
    RUNS="8:1 136:1 136:16" bash benches/results/atrous_plane_2026-11-26/kernel_error.sh 2> "$OUT/still_log.txt" ;;
  soak)
    source benches/results/device_env.sh
    unpack_bins
    mkdir -p "$OUT"
    /root/bins/solari soak "$(scene_file interior)" --frames "${FRAMES:-25000}" --toggle-lights 1000 \
      --camera-path orbit --size 1920x1080 --gi restir --gi-quarter-rate --progress-every 5000 \
      > "$OUT/soak.json" 2> "$OUT/soak.log"
    echo "soak rc=$?"
    python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print("clean", d["clean"], "overflows", d["cache_overflows"], "gpu", d["gpu_frame_ms"], "wall", d["wall_frame_ms"])' "$OUT/soak.json" ;;
  *) echo "usage: $0 time|orbit|still|soak" >&2; exit 2 ;;
esac
