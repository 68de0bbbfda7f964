#!/usr/bin/env bash
# Issue 19 (environment maps) on the H200 (device tool), one command.
#   1. timing, 1920x1080: `solari render --mode realtime --denoiser fallback --frames 200
#      --json`: the binary before environment maps (solari_prev) and after (solari), both
#      without a map, interleaved, two rounds; then the new one with --environment sky.hdr
#      (2048x1024, benches/results/sky_hdr.py: sky, ground and a sun of 20 W/m^2);
#   2. light, 960x540, with the sky: the reference (--spp $SPP), the real-time image (mean of
#      16 frames after 120) and `solari compare` against the reference.
# Carry .gl and .dev (scenes, sky.hdr, bins.tar.xz; .dev/SOLARI_COMMIT names the commits).
# Usage: bash benches/results/environment_h200.sh (SCENES, LIGHT_SCENES, SPP override).
# JSON and logs land in $OUT/environment_h200.tar.gz.
set -u
source benches/results/device_env.sh
mkdir -p /root/bins && tar xJf .dev/bins.tar.xz -C /root/bins
NEW=/root/bins/solari
PREV=/root/bins/solari_prev
R=${RESULTS:-/root/environment}
SPP=${SPP:-1024}
SKY=.dev/sky.hdr
SCENES=${SCENES:-sun_boxes interior}
LIGHT_SCENES=${LIGHT_SCENES:-sun_boxes}
mkdir -p "$R" "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
scene_file() { ls .dev/scenes/"$1"/*.gltf | head -n 1; }
time_run() { # name binary scene extra...
  local name=$1 bin=$2 f=$3; shift 3
  "$bin" render "$f" --mode realtime --denoiser fallback --frames 200 --size 1920x1080 \
    --json --out "$R/x.png" "$@" > "$R/time_$name.json" 2> "$R/time_$name.log"
}
for round in 1 2; do
  for s in $SCENES; do
    echo "== $s timing $round $(date -u +%T)" >&2
    time_run "${s}_prev_$round" $PREV "$(scene_file $s)"
    time_run "${s}_new_$round" $NEW "$(scene_file $s)"
    time_run "${s}_sky_$round" $NEW "$(scene_file $s)" --environment $SKY
  done
done
for s in $LIGHT_SCENES; do
  f=$(scene_file $s)
  echo "== $s reference $(date -u +%T)" >&2
  $NEW render "$f" --environment $SKY --mode reference --spp "$SPP" --size 960x540 \
    --out "$R/${s}_ref.exr" --json > "$R/${s}_ref.json" 2> "$R/${s}_ref.log"
  $NEW render "$f" --environment $SKY --mode realtime --denoiser fallback --frames 136 \
    --mean-of 16 --size 960x540 --json --out "$R/${s}_rt.exr" --out "$R/${s}_rt.png" \
    > "$R/${s}_rt.json" 2> "$R/${s}_rt.log"
  $NEW compare "$R/${s}_rt.exr" "$R/${s}_ref.exr" --json > "$R/cmp_${s}.json" 2>&1
done
echo "== done $(date -u +%T)" >&2
(cd "$R" && tar czf "$OUT/environment_h200.tar.gz" *.json *.log *.png gpu.csv)
