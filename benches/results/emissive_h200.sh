#!/usr/bin/env bash
# Issue 19 item 1 (emissive textures) on the H200 (device tool), one command.
#   1. timing, 1920x1080: `solari render --mode realtime --denoiser fallback --frames 200
#      --json`, the binary before (solari_prev) and after (solari) interleaved, two rounds;
#   2. light, 960x540: the reference (--spp $SPP) with the new binary, the real-time image
#      (mean of 16 frames after 120) with both, and `solari compare` of each against the
#      reference (mean/reference is the brightness ratio).
# Carry .gl and .dev (scenes, bins.tar.xz; .dev/SOLARI_COMMIT names the commits).
# Usage: bash benches/results/emissive_h200.sh (SCENES, SPP override). JSON and logs land
# in $OUT/emissive_h200.tar.gz.
set -u
source benches/results/device_env.sh
mkdir -p /root/bins && tar xJf .dev/bins.tar.xz -C /root/bins
NEW=/root/bins/solari
PREV=/root/bins/solari_prev
R=${RESULTS:-/root/emissive}
SPP=${SPP:-1024}
SCENES=${SCENES:-damaged_helmet interior sun_boxes}
LIGHT_SCENES=${LIGHT_SCENES:-damaged_helmet}
mkdir -p "$R" "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv > "$R/gpu.csv" 2>/dev/null
scene_file() { ls .dev/scenes/"$1"/*.gltf | head -n 1; }
for round in 1 2; do
  for s in $SCENES; do
    for b in prev new; do
      bin=$NEW; [ $b = prev ] && bin=$PREV
      echo "== $s $b timing $round $(date -u +%T)" >&2
      "$bin" render "$(scene_file $s)" --mode realtime --denoiser fallback --frames 200 \
        --size 1920x1080 --json --out "$R/x.png" > "$R/time_${s}_${b}_$round.json" \
        2> "$R/time_${s}_${b}_$round.log"
    done
  done
done
for s in $LIGHT_SCENES; do
  f=$(scene_file $s)
  echo "== $s reference $(date -u +%T)" >&2
  $NEW render "$f" --mode reference --spp "$SPP" --size 960x540 --out "$R/${s}_ref.exr" \
    --json > "$R/${s}_ref.json" 2> "$R/${s}_ref.log"
  for b in prev new; do
    bin=$NEW; [ $b = prev ] && bin=$PREV
    "$bin" render "$f" --mode realtime --denoiser fallback --frames 136 --mean-of 16 \
      --size 960x540 --json --out "$R/${s}_rt_$b.exr" > "$R/${s}_rt_$b.json" 2> "$R/${s}_rt_$b.log"
    $NEW compare "$R/${s}_rt_$b.exr" "$R/${s}_ref.exr" --json > "$R/cmp_${s}_rt_${b}.json" 2>&1
  done
done
echo "== done $(date -u +%T)" >&2
(cd "$R" && tar czf "$OUT/emissive_h200.tar.gz" *.json *.log gpu.csv)
